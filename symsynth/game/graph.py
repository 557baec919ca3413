"""The game of semantics §6 as a graph of positions, explored one at a time.

A position is `(v, q, h, robot)`: abstract state, DFA state after the trace
so far, human moves left, and whose turn it is (the human's first).  Every
move that makes the DFA accept leads to one target position WIN.
`GameGraph` gives a position's moves (cached: moves depend on `v` only,
DFA steps on `(q, letter)` only) and explores what a start reaches; the
explicit and forward solvers search it, strategy files and the simulator
walk it.
"""

from __future__ import annotations

from collections import deque
from typing import NamedTuple

from tqdm import tqdm

from symsynth.automata import SymbolicDFA
from symsynth.automata.shared import dfa_of
from symsynth.automata.symbolic import State as DFAState
from symsynth.game.abstraction import State, costmap_of, human_moves, letter, quantize, robot_moves
from symsynth.game.symmetry import Symmetry
from symsynth.scene.propositions import interpret_all
from symsynth.logic import ast
from symsynth.scene.model import Scene

PASS = "pass"
WIN, START = 0, 1  # indices of the target and of the initial position


class Node(NamedTuple):
    v: State
    q: DFAState
    h: int
    robot: bool


class Edge(NamedTuple):
    action: str
    target: int  # position index; WIN when the DFA accepts
    units: int  # 0 for the human
    state: State  # the abstract state after the move


class GameGraph:
    """The game graph's successor function, with the DFA and the moves cached
    (moves depend on `v` only, DFA steps on (q, letter) only).  Also what the
    strategy file walks (`game.strategy`)."""

    def __init__(self, scene: Scene, formula: ast.Formula, resolution: float, *,
                 symmetric: bool = False):
        costmap_of(scene)  # fail early, not at the first motion
        self.scene = scene
        #: with `symmetric`, every state a move leads to is canonical
        #: (`game.symmetry`); None when all objects are distinct
        self.symmetry = Symmetry.of(scene, formula) if symmetric else None
        self.props = interpret_all(formula, scene)
        self.dfa: SymbolicDFA = dfa_of(formula)
        self.resolution = resolution
        self._steps: dict[tuple[DFAState, frozenset[str]], DFAState] = {}
        self._accepting: dict[DFAState, bool] = {}
        self._letters: dict[State, frozenset[str]] = {}
        self._robot: dict[State, list[tuple[str, State, int]]] = {}
        self._human: dict[State, list[tuple[str, State]]] = {}

    def canon(self, v: State) -> State:
        """`v`, or its canonical state when the graph is symmetric."""
        return v if self.symmetry is None else self.symmetry.canon(v)

    def read(self, q: DFAState, v: State) -> DFAState:
        """The DFA state after reading ρ(v) from q."""
        if v not in self._letters:
            self._letters[v] = letter(self.scene, self.props, v)
        key = (q, self._letters[v])
        if key not in self._steps:
            self._steps[key] = self.dfa.step(q, key[1])
        return self._steps[key]

    def moves(self, node: Node) -> list[tuple[str, Node | None, int, State]]:
        """(action, successor or None for a win, units, state after)."""
        v, q, h = node.v, node.q, node.h
        if node.robot:
            if v not in self._robot:
                self._robot[v] = [(a, self.canon(w), quantize(c, self.resolution))
                                  for a, w, c in robot_moves(self.scene, v)]
            return [(a, self._after(w, q, h, robot=False), units, w) for a, w, units in self._robot[v]]
        out: list[tuple[str, Node | None, int, State]] = [(PASS, Node(v, q, h, True), 0, v)]
        if h > 0:
            if v not in self._human:
                self._human[v] = [(a, self.canon(w)) for a, w in human_moves(self.scene, v)]
            out += [(a, self._after(w, q, h - 1, robot=True), 0, w) for a, w in self._human[v]]
        return out

    def accepts(self, q: DFAState) -> bool:
        if q not in self._accepting:
            self._accepting[q] = self.dfa.is_accepting(q)
        return self._accepting[q]

    def _after(self, w: State, q: DFAState, h: int, robot: bool) -> Node | None:
        q2 = self.read(q, w)
        return None if self.accepts(q2) else Node(w, q2, h, robot)

    def explore(self, start: Node) -> tuple[list[Node | None], list[list[Edge]]]:
        """The positions reachable from `start` (index START; WIN has none) and their edges."""
        nodes: list[Node | None] = [None, start]
        index = {start: START}
        edges: list[list[Edge]] = [[], []]
        queue = deque([START])
        bar = tqdm(desc="explicit: positions", unit=" pos", delay=1.0, leave=False, disable=None)
        while queue:
            i = queue.popleft()
            if i & 0xFFF == 0:
                bar.update(i - bar.n)
            node = nodes[i]
            if node is None:  # WIN, never queued: it has no moves
                continue
            for action, succ, units, w in self.moves(node):
                if succ is None:
                    j = WIN
                elif succ in index:
                    j = index[succ]
                else:
                    j = index[succ] = len(nodes)
                    nodes.append(succ)
                    edges.append([])
                    queue.append(j)
                edges[i].append(Edge(action, j, units, w))
        bar.close()
        return nodes, edges
