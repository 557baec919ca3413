"""A hybrid strategy: optimal while the human has more than j moves left, the
replanning strategy σ after (issue 32).

W_j is what the hybrid strategy τ_j pays at most from the start.  τ_j plays
an action certified by the search below at every robot turn with h > j
human moves left, and σ (`solvers.replan`: the first action of a least-cost
no-human plan) at every robot turn with h <= j.  W_0 = E_p (σ is optimal
when no human move is left), W_k = B_k (σ's bound, `solvers.replan`), and
every W_j >= E_p, since τ_j is a strategy.

The question "W_j(start) <= b?" (`Hybrid.within`) is asked depth first over
the positions with h > j, on the AND-OR search's nodes and moves
(`solvers.andor.Memo`, its kernels generating the moves):

- a robot turn at node i with budget b: some action of u units whose human
  turn after it holds within b - u, tried in the order of u + low(after);
- a human turn: the pass (the robot turn of the same node) and every move
  must hold within b; a move to a robot turn with h - 1 = j is a **leaf**:
  "does σ pay at most b from there?", `BudgetedBound.within_from` (σ's
  question started at that position);
- a move or action that makes the task hold costs nothing more.

The order at a human turn: one move first (one already refuted within b,
else the last refuter, else the move of the largest lower bound), then the
pass, then the other moves.  The pass goes before most moves because a
human turn is mostly refuted by its pass, after all its moves were
certified: at 8 x 12 x k = 2, with the moves first, 80 % of σ's leaf
questions were spent at turns whose pass then failed; and the one move
before it because a turn refuted by a move is nearly always refuted by the
first move asked (bench/results/hybrid.md, `bench/hybrid_leaves.py`).

Lower bounds.  The memo's `lo` (proven lower bounds on the game's value
val) prune: W_j >= val >= lo everywhere.  Both answers are exact for W_j:
the search above h = j tries every action within its bounds, and σ's
question is exact (`solvers.replan_budget`).  A "no" is not a bound on val,
though (a leaf σ cannot certify may be within b for a better strategy), so
the search's `lo` are never raised from it.  It is a bound on W_j: the
hybrid keeps its own (`no_r`, `no_h`, `no_leaf`: W_j > the kept number),
raised as the search's `lo` are, by Bellman's equations on lower bounds:
at a refuted robot turn to min over actions of u + low(after), at a refuted
human turn to the largest low of its replies (low: the larger of `lo` and
one above the kept refutation).  W_j is exactly the least cost of τ_j-type
strategies from a node, so these are lower bounds whatever the order.
They only ever say no and order the actions; no yes rests on them.

Soundness of a yes
------------------
Each certified robot turn keeps (hi, action) with hi >= u + hi_H(after); each
certified human turn keeps hi_H >= the pass's hi and every move's hi (a
leaf's hi: the least budget σ was certified within, which may be below
the budget asked: σ's yes keeps the largest rise its certificates showed,
`BudgetedBound.kept_within`, each a plan or a proven hi; a win: 0).  A value is
written only when the question it answers was certified, and only ever
lowered.  A question with a budget at least the kept hi is answered from it.
A question asked deeper at the same node (the game has cycles, and budgets
fall along them) may have kept a lower hi while this one ran, and that one
is kept.  So these inequalities hold at all times.  Along any play of τ_j from a
certified human turn: every robot action lowers hi by its cost u >= 1
(search.py's rule: zero-cost games are refused), a pass or a move does not
raise it, and a move into h = j hands over to σ, which pays at most the
leaf's hi.  So the play wins and its cost is at most hi_H(start).  τ_j is
memoryless over (state, DFA state, h): at h > j the kept action of the
node, at h <= j σ's action (the same at every h).

Use and measurements
--------------------
`hybrid_answer` tightens an anytime answer of `solvers.andor` after σ's
upper end, with τ_1 (`HAND_OVER`).  It reuses σ's bound, built over the
search's memo, whose answers make the leaves cheap.  On the pattern
family, W_1 = E_p at 6 x 8 x k = 2 and 3 and 8 x 12 x k = 2 (where σ pays
0.3-2.2 % more), W_2 is above E_p, and at 7 x 10 x k = 3 W_1 = 744, between
E_p = 740 and σ's 748.  The cost is σ's question at each leaf (about
1.5-6 ms, 80 % of it in the replies' kernel): "W_1 <= 720?" at 8 x 12 x
k = 2 asks 2,608 of them for a certificate of 1,759 leaves
(bench/results/hybrid.md).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Iterator, Mapping

from symsynth.game.abstraction import after_robot_action, in_costmap_units
from symsynth.game.solution import OutOfReach, Position, Solution, Step, bracket_verdict
from symsynth.logic import ast
from symsynth.solvers.andor_proof import worst_reply
from symsynth.solvers.packed import search as sk
from symsynth.solvers.replan import NoHumanValue
from symsynth.solvers.replan_budget import BudgetedBound, Deadline

INF = math.inf
#: Questions between two looks at the clock (a leaf, σ's question, took up to 6 ms at 8 x 12)
LOOK_EVERY = 8
#: j of the anytime answer's τ_j: σ takes over when the human has this many moves left
#: (issue 32's measurements: W_1 = E_p at four of five games, nearer E_p than σ at the fifth; W_2 above)
HAND_OVER = 1


class Hybrid:
    """"W_j(start) <= b?" on `memo` (an `andor.Memo` of the game with k moves, its
    lower bounds raised by the search's rounds), σ's questions to `bound`."""

    def __init__(self, memo, bound: BudgetedBound, j: int, start: int):
        self.memo, self.bound, self.j, self.start = memo, bound, j, start
        self.hi_r: dict[int, tuple[int, int]] = {}  # node -> (hi, the move's index in rm_*)
        self.hi_h: dict[int, int] = {}
        self.leaf: dict[int, int] = {}  # node at h = j -> least budget σ was certified within
        self.no_r: dict[int, int] = {}
        self.no_h: dict[int, int] = {}
        self.no_leaf: dict[int, int] = {}
        self.refuter: dict[int, int] = {}
        self.deadline: float | None = None
        self.calls = 0
        self.leaves = 0

    def within(self, b: int, deadline: float | None = None) -> bool:
        """Whether τ_j pays at most b from the start (`Deadline` when `deadline` passes)."""
        self.deadline = deadline
        if self.memo.t.accepting[self.memo.position(int(self.memo.rec[self.start, sk.KEY]))[1]]:
            return b >= 0  # won at the start (a node is made for it all the same)
        old = sys.getrecursionlimit()
        sys.setrecursionlimit(max(old, 20_000))
        try:
            with self.bound.limited(deadline):
                return self._human(self.start, b)
        finally:
            sys.setrecursionlimit(old)

    def least(self, lower: int, upper: int, deadline: float | None = None) -> float:
        """W_j(start) when it is at most `upper`, given lower <= W_j(start): the
        least b in [lower, upper] that `within` says yes to; inf when above upper
        (or when the deadline passed before one was found)."""
        yes, _ = _tightened(self, lower, upper + 1, deadline)
        return INF if yes is None else yes

    @property
    def strategy(self) -> HybridStrategy:
        """τ_j: what `within` certified at h > j, σ below (module doc)."""
        return HybridStrategy(self)

    def _h(self, i: int) -> int:
        return int(self.memo.rec[i, sk.KEY]) & ((1 << self.memo.hb) - 1)

    def _look(self) -> None:
        self.calls += 1
        if self.deadline is not None and self.calls % LOOK_EVERY == 0 and time.perf_counter() > self.deadline:
            raise Deadline

    def _robot(self, i: int, b: int) -> bool:
        """The robot turn of node i (h > j) is certified within b."""
        memo = self.memo
        if b < memo.rec[i, sk.LO_R]:
            return False
        hi = self.hi_r.get(i)
        if hi is not None and hi[0] <= b:
            return True
        if b <= self.no_r.get(i, -1):
            return False
        self._look()
        off, count = self.memo.expand(i, True)
        bits = memo.t.code_bits
        options = []
        for e in range(off, off + count):
            t, units = int(memo.rm_tgt[e]), int(memo.rm_move[e]) >> bits
            options.append((units + (0 if t < 0 else self._low_h(t)), units, t, e))
        options.sort()
        for bound, units, t, e in options:
            if bound > b:
                break
            if t < 0 or self._human(t, b - units):
                hi = units + (0 if t < 0 else self.hi_h[t])
                if hi < self.hi_r.get(i, (INF,))[0]:  # (a question below this one may have set a lower one)
                    self.hi_r[i] = (hi, e)
                return True
        if self.hi_r.get(i, (INF,))[0] <= b:  # set by a question below this one, after its action was tried
            return True
        # W > b, and W >= min over actions of u + W's lower bound after it (raised by the refutations)
        low = min((units + (0 if t < 0 else self._low_h(t)) for _, units, t, _ in options), default=b + 1)
        self.no_r[i] = max(b, self.no_r.get(i, -1), low - 1)
        return False

    def _low_r(self, t: int, leaf: bool) -> int:
        """A lower bound on W at node t's robot turn (σ's value at a leaf): the
        memo's lo, one above a budget refuted there."""
        return max(int(self.memo.rec[t, sk.LO_R]), (self.no_leaf if leaf else self.no_r).get(t, -1) + 1)

    def _low_h(self, t: int) -> int:
        """A lower bound on W at node t's human turn: the memo's lo, one above a budget refuted there."""
        return max(self.memo.lo_h(t), self.no_h.get(t, -1) + 1)

    def _human(self, i: int, b: int) -> bool:
        """The human turn of node i (h > j) is certified within b: one move first
        (one known to say no, else the last refuter, else the largest lower
        bound), then the pass, then the other moves (module doc: why)."""
        memo = self.memo
        if b < memo.lo_h(i):
            return False
        hi = self.hi_h.get(i)
        if hi is not None and hi <= b:
            return True
        if b <= self.no_h.get(i, -1):
            return False
        off, count = self.memo.expand(i, False)
        below = self._h(i) - 1
        first, leaf = self.refuter.get(i), below == self.j
        reply = self._leaf if leaf else self._robot
        lows = {int(t): self._low_r(int(t), leaf) for t in memo.hm_tgt[off:off + count] if t >= 0}
        moves = sorted(lows, key=lambda t: (b >= lows[t], t != first, -lows[t]))
        head = moves[:1]  # the move most likely to refute (known to, when b < its low), then the pass, the rest
        ok = all(self._reply(i, t, b, reply) for t in head) and self._robot(i, b) \
            and all(self._reply(i, t, b, reply) for t in moves[len(head):])
        if not ok:
            if self.hi_h.get(i, INF) <= b:  # set by a question below this one
                return True
            # W > b, and W >= every reply's lower bound (raised by the refutations)
            low = max([self._low_r(i, False)] + [self._low_r(t, leaf) for t in moves])
            self.no_h[i] = max(b, self.no_h.get(i, -1), low - 1)
            return False
        hi = max([self.hi_r[i][0]] + [self.leaf[t] if leaf else self.hi_r[t][0] for t in moves])
        self.hi_h[i] = min(hi, self.hi_h.get(i, hi))  # (a question below this one may have set a lower one)
        return True

    def _reply(self, i: int, t: int, b: int, reply) -> bool:
        """`reply(t, b)`, t kept as human turn i's refuter when it says no."""
        if reply(t, b):
            return True
        self.refuter[i] = t
        return False

    def _leaf(self, i: int, b: int) -> bool:
        """σ pays at most b from node i's robot turn (h = j)."""
        memo = self.memo
        if b < memo.rec[i, sk.LO_R]:
            return False
        if self.leaf.get(i, INF) <= b:
            return True
        if b <= self.no_leaf.get(i, -1):
            return False
        self._look()
        self.leaves += 1
        x, q = memo.position(int(memo.rec[i, sk.KEY]))
        ok = self.bound.within_from(x, q, self.j, b)
        if ok:  # (σ's yes may hold for less than b: `BudgetedBound.kept_within`)
            self.leaf[i] = int(min(b, self.bound.kept_within(x, q, self.j), self.leaf.get(i, b)))
        else:
            self.no_leaf[i] = max(b, self.no_leaf.get(i, -1))
        return ok

    # -- the strategy ------------------------------------------------------------------
    def action(self, i: int) -> str:
        """The kept action at node i's robot turn (certified)."""
        memo = self.memo
        e = self.hi_r[i][1]
        return memo.t.action(memo.t.code(int(memo.rm_move[e])))

    def play(self) -> tuple[Step, ...]:
        """τ_j against the human of the largest kept hi (the pass first on ties)
        up to the hand-over to σ, then σ's plan with the human passing; after
        `within` said yes."""
        memo, t = self.memo, self.memo.t
        steps: list[Step] = []
        i = self.start
        while True:
            x, q = memo.position(int(memo.rec[i, sk.KEY]))
            v, h = t.unpack(x), self._h(i)
            step, after = worst_reply(memo, v, q, h, i, self._kept)
            if step is not None:
                steps.append(step)
                if after < 0:
                    return tuple(steps)
                if h - 1 == self.j:
                    return tuple(steps) + self._sigma_plan(after)
                i, v = after, step.state
            steps.append(self._robot_step(i, v))
            i = int(memo.rm_tgt[self.hi_r[i][1]])
            if i < 0:
                return tuple(steps)

    def _kept(self, i: int) -> int:
        """What τ_j pays at most from node i's robot turn: σ's certified budget at
        h = j, the kept hi above."""
        return self.leaf[i] if self._h(i) == self.j else self.hi_r[i][0]

    def _robot_step(self, i: int, v) -> Step:
        memo = self.memo
        action, units = self.action(i), memo.t.units(int(memo.rm_move[self.hi_r[i][1]]))
        after = after_robot_action(memo.t.scene, v, action)
        return Step("robot", action, in_costmap_units(units, memo.t.resolution), after)

    def _sigma_plan(self, i: int) -> tuple[Step, ...]:
        """σ's plan from node i's robot turn, the human passing."""
        memo = self.memo
        x, q = memo.position(int(memo.rec[i, sk.KEY]))
        r = memo.t.resolution
        return tuple(Step("robot", a, in_costmap_units(u, r), after)
                     for a, u, after, _ in self.bound.oracle.plan(memo.t.unpack(x), q))


class HybridStrategy(Mapping):
    """τ_j as a strategy: the certified action at h > j, σ's at h <= j (module doc)."""

    def __init__(self, hybrid: Hybrid):
        self._hybrid = hybrid
        self._sigma = hybrid.bound.strategy

    def __getitem__(self, position: Position) -> str:
        v, q, h = position
        hy = self._hybrid
        if h <= hy.j:
            return self._sigma[position]
        t, memo = hy.memo.t, hy.memo
        qi = t.dfa_index.get(q)
        i = None if qi is None else memo.find(memo.key2(t.pack(v), qi, h))
        if i is None or i not in hy.hi_r:
            raise KeyError(position)
        return hy.action(i)

    def __iter__(self) -> Iterator[Position]:
        raise TypeError("the hybrid strategy hands over to σ, which has no table to list")

    def __len__(self) -> int:
        raise TypeError("the hybrid strategy hands over to σ, which has no table to count")


def hybrid_answer(solution: Solution, memo, start: int, formula: ast.Formula, deadline: float,
                  bound: BudgetedBound | None = None) -> Solution:
    """An anytime answer tightened by τ_j (j = `HAND_OVER`, below k): "W_j <= b?"
    asked from the lower end up (`_tightened`), the first yes a new upper end
    with τ_j as its strategy (module doc; at the lower end E_p is proven),
    until `deadline`; the stats say what was asked.  σ's questions go to
    `bound` (σ's bound of the same game, its answers reused) or a new one
    over the search's memo.
    Not asked when the game's positions are reduced by a symmetry (σ's are
    not) or the deadline has passed."""
    lower, t = solution.lower_units, memo.t
    if lower is None or t.symmetry is not None or memo.k == 0 or time.perf_counter() >= deadline:
        return solution
    clock = time.perf_counter()
    bound = bound or BudgetedBound(t.scene, formula, memo.k, t.resolution,
                                   NoHumanValue(t.scene, formula, t.resolution, memo))
    hybrid = Hybrid(memo, bound,
                    min(HAND_OVER, memo.k - 1), start)
    yes, no = _tightened(hybrid, lower, solution.units, deadline)
    stats = dict(solution.stats) | {"hybrid_seconds": round(time.perf_counter() - clock, 2),
                                    "hybrid_leaves": hybrid.leaves, "hybrid_not_within": no}
    if yes is None:
        return dataclasses.replace(solution, stats=stats)
    r, exact = t.resolution, yes <= lower
    realizable = bracket_verdict(None if exact else lower, yes, r, solution.budget)
    principal = hybrid.play()
    return dataclasses.replace(solution, cost_bound=in_costmap_units(yes, r), units=yes, realizable=realizable,
                               strategy=hybrid.strategy, principal_play=principal,
                               counter_play=principal if exact and realizable is False else None,
                               stats=stats | {"hybrid_bound": yes,
                                              "upper_by": f"hybrid (optimal above h = {hybrid.j}, {bound.name} below)"},
                               lower_units=None if exact else lower)


def _tightened(hybrid: Hybrid, lower: int, upper: int | None, deadline: float | None) -> tuple[int | None, int]:
    """(the least b found with W_j <= b, below `upper` (None: none), or None; the
    largest b found with W_j > b): asked at `lower` (a yes proves E_p), then
    one more each time, as the search's rounds, until `deadline` (a no
    raised W_j's lower bound at the start only to b + 1 at 8 x 12 x k = 2,
    715 to 719, so no jump is tried).  A budget
    well above W_j is no quicker to certify: at 8 x 12 x k = 2, "<= 721?" was
    not answered in 18.8 s where "<= 720?" took 7.1 s (bench/results/hybrid.md)."""
    top = lower if upper is None else upper - 1  # the largest b worth asking
    b = lower
    try:
        while b <= top:
            if hybrid.within(b, deadline):
                return b, b - 1
            b += 1
    except (Deadline, OutOfReach, RecursionError):  # (OutOfReach: a zero-cost move in a no-human search;
        pass  # RecursionError: a play deeper than `within`'s limit, budgets of many thousand units)
    return None, b - 1
