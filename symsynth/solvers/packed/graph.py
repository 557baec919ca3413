"""The compiled solver's explored and solved nodes read back (`Graph`): node
lookups, the human's replies, plays, and the strategy as a mapping."""

from __future__ import annotations

from collections.abc import Iterator, Mapping

import numpy as np

from symsynth.game.abstraction import after_robot_action, legal_human_moves
from symsynth.game.solution import Position, Step
from symsynth.solvers.packed.kernels import INF
from symsynth.solvers.packed.tables import Tables

class Graph:
    """The explored nodes with their values, for strategies and plays.

    Node i stands for the robot-turn position (v, q, h) and, where `hflag[i]`,
    the human-turn position at the same (v, q, h) (its pass leads to the
    robot's); h is the node's layer."""

    def __init__(self, tables: Tables, explored: tuple, rval: np.ndarray, choice: np.ndarray):
        self.keys, self.hflag, self.lo, self.hi, self.r_off, self.r_tgt, self.r_move = explored
        self.rval = rval
        self.choice = choice  # the chosen robot move, relative to r_off (-1: none)
        self.tables = tables
        self._sorted: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def layer(self, i: int) -> int:
        return next(h for h in range(self.tables.k + 1) if self.lo[h] <= i < self.hi[h])

    def index(self, x: int, q: int, h: int) -> int | None:
        """The node of packed state x, DFA state q and layer h, None if unexplored."""
        if h not in self._sorted:
            lo, hi = int(self.lo[h]), int(self.hi[h])
            order = np.argsort(self.keys[lo:hi], kind="stable")
            self._sorted[h] = (order + lo, self.keys[lo:hi][order])
        order, keys = self._sorted[h]
        key = self.tables.key(x, q)
        j = int(np.searchsorted(keys, key))
        return int(order[j]) if j < len(keys) and keys[j] == key else None

    def position(self, i: int) -> Position:
        t = self.tables
        key = int(self.keys[i])
        return (t.unpack(key >> t.qbits), t.dfa_states[key & ((1 << t.qbits) - 1)], self.layer(i))

    def robot_edges(self, i: int) -> range:
        return range(int(self.r_off[i]), int(self.r_off[i + 1]))

    def chosen(self, i: int) -> int:
        """The robot move (an index into r_*) the strategy takes at node i."""
        return int(self.r_off[i]) + int(self.choice[i])

    def _robot_step(self, i: int, e: int) -> tuple[Step, int]:
        t = self.tables
        v = self.position(i)[0]
        name = t.action(t.code(self.r_move[e]))
        after = after_robot_action(t.scene, v, name)
        return Step("robot", name, t.units(self.r_move[e]) * t.resolution, after), int(self.r_tgt[e])

    def replies(self, i: int) -> list[tuple[Step | None, int, int]]:
        """The human's replies at node i's human turn: (step, its node (-1: the
        task is won), its value), the pass (step None, node i) first."""
        t = self.tables
        v, q, h = self.position(i)
        out: list[tuple[Step | None, int, int]] = [(None, i, int(self.rval[i]))]
        qi = t.dfa_index[q]
        for mv in (legal_human_moves(t.scene, v) if h > 0 else ()):
            w = t.canon(t.pack(mv.after))
            q2 = t.step(qi, w)
            j = -1 if t.accepting[q2] else self.index(w, q2, h - 1)
            if j is None:
                raise RuntimeError("internal error: a human move left the explored nodes")
            out.append((Step("human", mv.action, 0.0, mv.after), j, 0 if j < 0 else int(self.rval[j])))
        return out

    def principal_play(self, start: int) -> tuple[Step, ...]:
        """The strategy against the reply of largest value (the pass, then the
        first, on ties), to the win."""
        play, i = [], start
        while True:
            step, j, _ = max(self.replies(i), key=lambda reply: reply[2])
            if step is not None:
                play.append(step)
                if j < 0:
                    break
                i = j
            step, i = self._robot_step(i, self.chosen(i))
            play.append(step)
            if i < 0:
                break
        return tuple(play)

    def counter_play(self, start: int) -> tuple[Step, ...]:
        play, i, seen = [], start, set()
        while i not in seen:
            seen.add(i)
            step, j, _ = next(reply for reply in self.replies(i) if reply[2] >= INF)
            if step is not None:
                play.append(step)
                i = j
            edges = list(self.robot_edges(i))
            if not edges:
                break
            step, i = self._robot_step(i, min(edges, key=lambda x: self.tables.units(self.r_move[x])))
            play.append(step)
            if i < 0:
                raise RuntimeError("internal error: the counter play reached a win")
        return tuple(play)


class CompiledStrategy(Mapping):
    """The robot's action at explored robot-turn positions of finite value."""

    def __init__(self, graph: Graph):
        self._graph = graph

    def __getitem__(self, position: Position) -> str:
        g, t = self._graph, self._graph.tables
        v, q, h = position
        qi = t.dfa_index.get(q)
        i = None if qi is None or not 0 <= h <= t.k else g.index(t.pack(v), qi, h)
        if i is None or g.rval[i] >= INF:
            raise KeyError(position)
        return t.action(t.code(g.r_move[g.chosen(i)]))

    def __iter__(self) -> Iterator[Position]:
        g = self._graph
        return iter([g.position(int(i)) for i in np.flatnonzero(g.rval < INF)])

    def __len__(self) -> int:
        return int(np.count_nonzero(self._graph.rval < INF))
