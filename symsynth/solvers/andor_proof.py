"""The AND-OR search's proof read back (`solvers.andor` builds it and says why
its entries are proven): the robot's proven actions, the strategy they make,
and plays."""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from typing import TYPE_CHECKING

import numpy as np

from symsynth.game.abstraction import State, after_robot_action, in_costmap_units, legal_human_moves
from symsynth.game.solution import Position, Step
from symsynth.solvers.packed import search as sk
from symsynth.solvers.packed.kernels import INF

if TYPE_CHECKING:
    from symsynth.solvers.andor import Memo


class Proof:
    """The memo's proven entries read back: positions, the chosen actions, plays."""

    def __init__(self, memo: Memo):
        self.memo, self.t = memo, memo.t

    def index(self, position: Position) -> int | None:
        v, q, h = position
        qi = self.t.dfa_index.get(q)
        if qi is None or not 0 <= h <= self.memo.k:
            return None
        return self.memo.find(self.memo.key2(self.t.pack(v), qi, h))

    def position(self, i: int) -> Position:
        t, memo = self.t, self.memo
        key2 = int(memo.rec[i, sk.KEY])
        key = key2 >> memo.hb
        return (t.unpack(key >> t.qbits), t.dfa_states[key & ((1 << t.qbits) - 1)], key2 & ((1 << memo.hb) - 1))

    def hi_r(self, i: int) -> int:
        return int(self.memo.rec[i, sk.HI_R])

    def chosen(self, i: int) -> tuple[str, int, int]:
        """(action, units, node after or -1) of the robot's proven action at node i."""
        memo, t = self.memo, self.t
        e = int(memo.rec[i, sk.R_OFF]) + int(sk._small(memo.rec, np.int64(i), np.int64(32))) - 1
        move = int(memo.rm_move[e])
        return t.action(t.code(move)), t.units(move), int(memo.rm_tgt[e])

    def play(self, start: int) -> tuple[Step, ...]:
        """The proven strategy against the replies of largest proven hi (the
        pass first on ties), to the win."""
        t, r = self.t, self.t.resolution
        play: list[Step] = []
        i = start
        while True:
            v, q, h = self.position(i)
            step, i = worst_reply(self.memo, v, t.dfa_index[q], h, i, self.hi_r)
            if step is not None:
                play.append(step)
                if i < 0:
                    return tuple(play)
                v = self.position(i)[0]
            action, units, i = self.chosen(i)
            after = after_robot_action(t.scene, v, action)
            play.append(Step("robot", action, in_costmap_units(units, r), after))
            if i < 0:
                return tuple(play)


def worst_reply(memo: Memo, v: State, q: int, h: int, i: int, value: Callable[[int], int]) -> tuple[Step | None, int]:
    """The human's reply at node i (state v, DFA state index q, h moves left)
    of the largest `value` of its node (0 for a reply that wins; the pass,
    valued at i's own, first on ties): (its step, None for the pass; its
    node, -1 when the reply wins).  Every reply must have been generated."""
    t = memo.t
    best: tuple[int, Step | None, int] = (value(i), None, i)
    for mv in (legal_human_moves(t.scene, v) if h > 0 else ()):
        w = t.canon(t.pack(mv.after))
        q2 = t.step(q, w)
        j = -1 if t.accepting[q2] else memo.find(memo.key2(w, q2, h - 1))
        if j is None:
            raise RuntimeError("internal error: a human reply of the proof was never generated")
        worth = 0 if j < 0 else value(j)
        if worth > best[0]:
            best = (worth, Step("human", mv.action, 0.0, mv.after), j)
    return best[1], best[2]


class ProvenStrategy(Mapping):
    """The robot's proven action at every position with an entry: every play
    of it from there costs at most the entry's hi (module doc)."""

    def __init__(self, proof: Proof):
        self._proof = proof

    def __getitem__(self, position: Position) -> str:
        i = self._proof.index(position)
        if i is None or self._proof.hi_r(i) >= INF:
            raise KeyError(position)
        return self._proof.chosen(i)[0]

    def _proven(self) -> np.ndarray:
        memo = self._proof.memo
        return np.flatnonzero(memo.rec[:memo.count, sk.HI_R] < INF)

    def __iter__(self) -> Iterator[Position]:
        return iter([self._proof.position(int(i)) for i in self._proven()])

    def __len__(self) -> int:
        return len(self._proven())
