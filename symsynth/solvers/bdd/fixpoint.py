"""The cost-bounded attractor: a least fixpoint over (state, budget) pairs.

Positions are (v, q, h): abstract state, DFA state after the trace so far,
human moves left.  A set X over (v, q, h, e) holds the human-turn positions
from which the robot forces acceptance spending at most e; R holds the
robot-turn positions.  One round of the fixpoint:

    R(v,q,h,e) = \\E v', c: T(v,v',c) /\\ c <= e /\\ X(v', D(q,v'), h, e - c)
    X(v,q,h,e) = Acc(q) \\/ (R(v,q,h,e) /\\ \\A v': H(v,v') /\\ h > 0
                                                => Z(v', D(q,v'), h - 1, e))
    where Z = Acc \\/ R   (the robot's turn after a human move, or a win)

The human moves first and may pass (then the robot plays from R itself) or
move (then it plays from Z with one move less).

The robot never changes h and the human only lowers it, so the fixpoint is
solved one layer h = 0, 1, ..., k at a time, over (v, q, e) alone.  When
layer h starts, layer h - 1 is final, and so is what the human can force
there:

    Safe_h(v,q,e) = \\A v': H(v,v') => Z_{h-1}(v', D(q,v'), e)    (Safe_0 = true)

is computed once per layer, and within the layer a round is only the
robot's step and a conjunction: X_h = Acc \\/ (R_h /\\ Safe_h).  (Solved
all layers together, the human step came round with every round, over the
whole of R: 58-72% of the time on the benchmark family; layer by layer,
5 x 7 went from 170 s to 60 s, k + 1 human steps instead of 55.)

Every set is kept to well-formed states (semantics §2): their values do not
depend on the others (a move from a well-formed state leads to one), and
the junk the relations give on the others made the sets about a third
larger (benchmark family, 5 x 7: 60 s -> 36 s).

The iterates R_{h,1}, R_{h,2}, ... are kept: R_{h,i} wins within i robot
actions while the human passes, and strategy extraction picks actions that
lead into an earlier iterate of the same layer; a human move goes down a
layer.  The layers are joined into iterates over (v, q, h, e), R_i =
\\/_h (h = j /\\ R_{j,i}), a layer that converged early staying at its last
iterate.

Without costs (`with_costs=False`) the same iteration is the qualitative
attractor; its ranks bound the number of robot actions and hence the width
the budget needs.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

from symsynth.automata.bdd import Function, and_exists
from symsynth.automata.symbolic import prime
from symsynth.solvers.bdd.arena import Arena


@dataclass
class Attractor:
    """The fixpoint's iterates and where its time went."""

    layers: list[Function]  # R_1, R_2, ...
    wins: list[Function]  # X_0 = Acc, X_1, ...: X_{i-1} gave R_i
    converged: bool
    rounds: list[int]  # rounds of each layer h = 0, 1, ... (the last one may have stopped)
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def robot_win(self) -> Function:
        return self.layers[-1]

    @property
    def win(self) -> Function:
        return self.wins[-1]

    @property
    def action_bound(self) -> int:
        """Robot actions enough to win from what the last layer won: a rank
        in that layer, then at most every round of each layer below (a
        human move goes down a layer and can land on any rank there)."""
        return sum(self.rounds)


def reachable(arena: Arena, start: Function) -> list[Function]:
    """The positions (v, q) of each layer h = 0..k that a play from `start`
    (a human-turn position of layer k, over (v, q)) reaches, at either
    turn.  The human turns of layer h are the start (h = k) and what a
    robot move leads to; the robot turns, the human turns passed and what
    a human move out of a human turn of layer h + 1 leads to.  A play ends
    when the task is done: accepting positions are reached, not left.

    Restricted to these (`attractor`'s `within`), the attractor computes
    the same values at every robot turn and every human turn reached: a
    value reads the moves out of its position only, and those lead to
    positions reached.  (At a robot turn reached, X, a human-turn set, may
    be wrong; nothing reads it there.)
    """
    bdd = arena.bdd
    primed_q = {b: prime(b) for b in arena.dfa.bits}
    # q' = D(q, v'): the DFA reads the state a move leads to
    reads = bdd.true
    for b, d in arena.dfa_next.items():
        reads &= bdd.apply("<=>", bdd.var(primed_q[b]), d)
    robot = bdd.false
    for rel in arena.robot.values():
        robot |= bdd.exist(set(arena.c.bits), rel)  # \E c: T_fam(v, v', c)
    robot &= reads  # ... /\ q' = D(q, v')
    human = arena.human & reads  # H(v, v') /\ q' = D(q, v')
    current = set(arena.state_bits) | set(arena.dfa.bits)
    back = {p: b for b, p in zip(arena.state_bits, arena.next_bits)}
    back.update({p: b for b, p in primed_q.items()})
    live = ~arena.accepting

    def image(relation: Function, u: Function) -> Function:
        # (\E v, q: relation(v, q, v', q') /\ u(v, q) /\ ~Acc(q))[v, q := v', q']
        return bdd.let(back, and_exists(bdd, relation, u & live, current))

    layers: list[Function] = []
    seeds = bdd.false  # robot turns after a human move from the layer above
    for h in range(arena.k, -1, -1):
        first = start if h == arena.k else bdd.false
        reached = frontier = first | seeds
        while frontier != bdd.false:
            frontier = image(robot, frontier) & ~reached
            reached |= frontier
        layers.append(reached)
        human_turns = first | image(robot, reached)
        seeds = image(human, human_turns)
    return layers[::-1]


def attractor(arena: Arena, *, with_costs: bool,
              stop: Callable[[Function], bool] | None = None,
              progress: Callable[[int], None] | None = None,
              within: list[Function] | None = None) -> Attractor:
    """Iterate to the least fixpoint, or until `stop(X)` holds for X of the
    top layer h = k (the lower layers are then final).  With `within` (a
    set over (v, q) per layer h, closed under the moves out of its
    non-accepting positions: `reachable`), every set is kept inside it.
    """
    bdd = arena.bdd
    step = _RobotStep(arena, with_costs, progress)
    move_sub = arena.move_substitution()
    moved = set(arena.next_bits)
    well_formed = arena.enc.well_formed()
    per_layer: list[tuple[list[Function], list[Function]]] = []
    below = None  # Z_{h-1} = Acc \/ R_{h-1}, final
    stopped = False
    for h in range(arena.k + 1):
        # well-formed, and reached in layer h when restricted
        wf = well_formed if within is None else well_formed & within[h]
        acc = arena.accepting & wf  # Acc(q), on well-formed states
        clock = time.perf_counter()
        if below is None:
            safe = wf  # h = 0: the human has no move
        else:
            # \A v': H(v, v') => Z_{h-1}(v', D(q, v'), e)
            after_move = bdd.let(move_sub, below)
            safe = wf & ~and_exists(bdd, arena.human, ~after_move, moved)
        step.seconds["human"] += time.perf_counter() - clock
        layers, wins, robot, stopped = step.layer(acc, wf, safe, stop if h == arena.k else None)
        per_layer.append((layers, wins))
        below = acc | robot
    rounds = [len(layers) for layers, _ in per_layer]
    return Attractor(_join(arena, [l for l, _ in per_layer]), _join(arena, [w for _, w in per_layer]),
                     not stopped, rounds, step.seconds)


class _RobotStep:
    """The rounds of one layer: the robot's step from the frontier, and the
    conjunction with what the human cannot spoil.

    The robot step works on the frontier X_i \\ X_{i-1} only: the image
    distributes over union, so R_{i+1} = R_i \\/ pre(X_i \\ X_{i-1}) exactly,
    and each position is carried through a relation once per budget band
    it gains, not once per round (image time 9.8 s -> 2.4 s on the
    benchmark family at 4 x 6)."""

    def __init__(self, arena: Arena, with_costs: bool, progress: Callable[[int], None] | None):
        bdd = self.bdd = arena.bdd
        self.substitution = arena.robot_substitution(with_costs)
        moved = set(arena.next_bits)
        if with_costs:
            self.relations = list(arena.robot.values())
            self.hidden = moved | set(arena.c.bits)
            self.affordable = arena.affordable()
        else:
            self.relations = [bdd.exist(set(arena.c.bits), rel) for rel in arena.robot.values()]
            self.hidden = moved
            self.affordable = bdd.true
        self.progress = progress
        self.done = 0  # rounds over every layer, for `progress`
        self.seconds = {"compose": 0.0, "image": 0.0, "human": 0.0}

    def layer(self, acc: Function, wf: Function, safe: Function,
              stop: Callable[[Function], bool] | None) -> tuple[list[Function], list[Function], Function, bool]:
        """The iterates R_i and X_i of a layer, its R, and whether `stop` ended it."""
        bdd, seconds = self.bdd, self.seconds
        layers: list[Function] = []
        wins: list[Function] = []
        robot = bdd.false
        x = acc
        old = None  # at least one round, also when Acc is empty (task `false`)
        while x != old:
            frontier = x if old is None else x & ~old
            old = x
            wins.append(x)
            clock = time.perf_counter()
            # X(v', D(q, v'), e - c) /\ c <= e, on the frontier
            shifted = bdd.let(self.substitution, frontier) & self.affordable
            seconds["compose"] += time.perf_counter() - clock
            clock = time.perf_counter()
            # \E v', c: T_fam(v, v', c) /\ shifted, one family at a time
            gained = bdd.false
            for rel in self.relations:
                gained |= and_exists(bdd, rel, shifted, self.hidden)
            gained &= wf
            # R \/ what the frontier gained
            robot |= gained
            seconds["image"] += time.perf_counter() - clock
            clock = time.perf_counter()
            # Acc \/ (R /\ Safe_h), R grown by what the frontier gained
            x = old | (gained & safe)
            seconds["human"] += time.perf_counter() - clock
            layers.append(robot)
            self.done += 1
            if self.progress is not None:
                self.progress(self.done)
            if stop is not None and stop(x):
                wins.append(x)
                return layers, wins, robot, True
        return layers, wins, robot, False


def _join(arena: Arena, per_layer: list[list[Function]]) -> list[Function]:
    """Iterates over (v, q, h, e): the i-th is \\/_h (h = j /\\ i-th of layer j),
    a shorter layer repeating its last."""
    bdd = arena.bdd
    joined = []
    for i in range(max(len(seq) for seq in per_layer)):
        u = bdd.false
        for h, seq in enumerate(per_layer):
            u |= arena.h.eq(bdd, h) & seq[min(i, len(seq) - 1)]
        joined.append(u)
    return joined
