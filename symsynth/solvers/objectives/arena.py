"""The position graph the objectives of semantics §9 are solved on, as arrays.

Node i stands for the robot-turn position (v, q, h) and, where `hflag[i]`,
the human-turn position at the same (v, q, h), whose pass leads to the
robot's turn at i (the compiled solver's layout).  Node 0's human turn is
the initial position.  Robot moves in CSR form: `r_off`, `r_tgt` (the
node whose human turn the move leads to; -1: the task is won), `r_units`
(quantized cost), `r_name` (an index into `names`).  Human moves likewise:
`h_off`, `h_tgt` (the node whose robot turn it leads to, in layer h - 1;
-1: won), with `h_prob` the model's probability of each move and `stay[i]`
the pass's.  `rval[i]` is the worst-case value V of node i's robot turn
(semantics §6, units; `INF` where infinite).

Two builders: `from_explicit` (the explicit solver's graph of
`game.graph`, any human model) and `from_compiled` (the compiled solver's
explored arrays, for models whose distribution depends on the number of
moves alone, `human_model.UniformModel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from symsynth.game.abstraction import initial_state, legal_human_moves
from symsynth.game.graph import PASS, GameGraph, Node
from symsynth.game.human_model import HumanModel
from symsynth.game.solution import OutOfReach
from symsynth.logic import ast
from symsynth.scene.model import Scene

INF = np.int64(1 << 60)


@dataclass
class Arena:
    layer: np.ndarray  # h of each node
    hflag: np.ndarray
    r_off: np.ndarray
    r_tgt: np.ndarray
    r_units: np.ndarray
    h_off: np.ndarray
    h_tgt: np.ndarray
    rval: np.ndarray
    #: the worst-case strategy: its robot move at each node (absolute edge index, -1: none)
    wchoice: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    stay: np.ndarray = field(default_factory=lambda: np.zeros(0))
    h_prob: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: how to name a node's position and a robot move, for strategies
    positions: list = field(default_factory=list, repr=False)
    names: list[str] = field(default_factory=list, repr=False)
    r_name: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64), repr=False)
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def size(self) -> int:
        return len(self.layer)

    def human_value(self) -> np.ndarray:
        """V at each node's human turn: the largest of its pass and its moves."""
        from symsynth.solvers.objectives.kernels import human_values

        return human_values(self.rval, self.h_off, self.h_tgt)


def from_explicit(scene: Scene, formula: ast.Formula, k: int, resolution: float,
                  model: HumanModel | None) -> Arena | None:
    """The explicit solver's graph as an `Arena` (None when ρ(v0) alone is
    accepted), with the worst-case values of its Dijkstra."""
    from symsynth.solvers.explicit import _dijkstra

    game = GameGraph(scene, formula, resolution)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return None
    nodes, edges = game.explore(Node(v0, q0, k, False))
    value, chosen = _dijkstra(nodes, edges)
    index, order, human_of = _numbered(nodes)
    key0 = (v0, q0, k)
    if index[key0] != 0:  # the start first (explore numbers it first, so this never runs)
        raise RuntimeError("internal error: the start is not the arena's node 0")
    n = len(order)
    names: dict[str, int] = {}
    r_off, r_tgt, r_units, r_name = [0], [], [], []
    h_off: list[int] = [0]
    h_tgt: list[int] = []
    h_prob: list[float] = []
    stay = np.ones(n)
    for j in range(n):
        for edge in edges[order[j]]:
            target = nodes[edge.target]
            r_tgt.append(-1 if target is None else index[(target.v, target.q, target.h)])
            r_units.append(edge.units)
            r_name.append(names.setdefault(edge.action, len(names)))
        r_off.append(len(r_tgt))
        if j in human_of:
            out = [e for e in edges[human_of[j]] if e.action != PASS]
            if out and model is not None:
                node = nodes[human_of[j]]
                assert node is not None
                moves = legal_human_moves(scene, node.v)
                by_name = {m.action: m for m in moves}
                p_pass, p_moves = model.distribution(node.v, node.h, [by_name[e.action] for e in out])
                stay[j] = float(p_pass)
                h_prob.extend(float(p) for p in p_moves)
            for e in out:
                target = nodes[e.target]
                h_tgt.append(-1 if target is None else index[(target.v, target.q, target.h)])
            if model is None:
                h_prob.extend([0.0] * len(out))
        h_off.append(len(h_tgt))
    rval = np.array([value.get(order[j], INF) if order[j] >= 0 else INF for j in range(n)], np.int64)
    wchoice = np.array([r_off[j] + chosen[order[j]] if order[j] in chosen else -1 for j in range(n)], np.int64)
    positions: list[tuple] = [()] * n
    for (v, q, h), j in index.items():
        positions[j] = (v, q, h)
    hflag = np.zeros(n, np.uint8)
    hflag[list(human_of)] = 1
    return Arena(np.array([p[2] for p in positions], np.int64), hflag, np.array(r_off, np.int64),
                 np.array(r_tgt, np.int64), np.array(r_units, np.int64), np.array(h_off, np.int64),
                 np.array(h_tgt, np.int64), rval, wchoice, stay, np.array(h_prob, np.float64), positions,
                 list(names), np.array(r_name, np.int64))


def _numbered(nodes: list) -> tuple[dict[tuple, int], list[int], dict[int, int]]:
    """The arena's numbering of the explicit graph's positions: each
    (v, q, h) once, in the graph's order; with the explicit index of its
    robot turn (-1: none) and of its human turn, where it has one."""
    index: dict[tuple, int] = {}
    order: list[int] = []  # explicit index of each arena node's robot turn
    human_of: dict[int, int] = {}  # arena node -> explicit index of its human turn
    for i, node in enumerate(nodes):
        if node is not None:
            j = index.setdefault((node.v, node.q, node.h), len(index))
            if j == len(order):
                order.append(-1)
            if node.robot:
                order[j] = i
            else:
                human_of[j] = i
    return index, order, human_of


def from_compiled(scene: Scene, formula: ast.Formula, k: int, resolution: float,
                  model: HumanModel | None) -> Arena | None:
    """The compiled solver's explored graph and values as an `Arena`; models
    must be uniform over the moves (`pass_probability`), else `OutOfReach`."""
    from symsynth.solvers.compiled import HUMAN_MOVES_KEPT, explore_packed

    if model is not None and not hasattr(model, "pass_probability"):
        raise OutOfReach(f"the compiled solver takes human models uniform over the moves "
                         f"(random(P)); {model.name} is solved by --solver explicit")
    packed = explore_packed(scene, formula, k, resolution)
    if packed is None:
        return None
    if not packed.keeps_human_moves:
        raise OutOfReach("the compiled objectives keep every human move; this game has more than "
                         f"{HUMAN_MOVES_KEPT}")
    tables, rval, chosen = packed.tables, packed.rval, packed.choice
    seconds = {"explore": packed.seconds["tables"] + packed.seconds["explore"], "solve": packed.seconds["solve"]}
    keys, hflag, lo, hi, r_off, r_tgt, r_move = packed.explored[:7]
    h_off, h_tgt = packed.explored[8], packed.explored[9]
    layer = np.empty(len(keys), np.int64)
    for h in range(k + 1):
        layer[lo[h]:hi[h]] = h
    units = (r_move.astype(np.int64) >> tables.code_bits)
    wchoice = np.where(chosen >= 0, r_off[:-1] + chosen, -1).astype(np.int64)
    arena = Arena(layer, hflag, r_off, r_tgt.astype(np.int64), units, h_off, h_tgt.astype(np.int64), rval,
                  wchoice, seconds=seconds)
    if model is not None:
        counts = np.diff(h_off)
        wide = int(counts.max(initial=0)) + 1
        pairs = layer * wide + counts
        table = np.zeros((k + 1) * wide)
        for x in np.flatnonzero(np.bincount(pairs, minlength=len(table))).tolist():  # each (h, moves) asked once
            table[x] = float(model.pass_probability(x // wide, x % wide))  # checked above
        arena.stay = table[pairs]
        share = np.where(counts > 0, (1.0 - arena.stay) / np.maximum(counts, 1), 0.0)
        arena.h_prob = np.repeat(share, counts)
    arena.tables = tables  # type: ignore[attr-defined]  # to name positions and moves
    arena.r_move = r_move  # type: ignore[attr-defined]
    return arena


def budget_units(budget: float, resolution: float) -> int:
    """⌊B / r⌋ on the decimals (semantics §9)."""
    from symsynth.game.abstraction import decimal

    return math.floor(decimal(budget) / decimal(resolution))
