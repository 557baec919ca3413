"""The replanning strategy and the upper bound it certifies (issue 32).

The **replanning strategy** σ plays, at every robot turn, the first action of a
least-cost plan of the game with no human move left: with V_0(v, q) that game's
value (the no-human value), σ takes an action a with V_0(p) = c(a) + V_0(after a).
It is memoryless (the same at every h) and needs no table: `NoHumanValue` finds
the action by the AND-OR search with no human move left from the position
(`solvers.andor`), one memo for every question (a new one with k = 0, or an
AND-OR search's memo of the game, read at its h = 0 nodes), so a plan once
proven is read back, not searched.

σ is well defined: the action read back at a node is the memo's proven one, and along a
proven plan every node's upper end is exact (c + hi(after) <= V_0(p) <= c + V_0(after)),
and an exact upper end is never changed again; so σ's plan from p_{i+1} is the rest of its
plan from p_i.

The bound
---------
B_h(p) is what σ pays at most from a position p with h human moves left.  Let
p_0 = p, p_1, ... be σ's own plan from p (no human move), ending in a win; at
each human turn on it (p_0 itself only when p is a human turn) the human passes
or moves, and after a move at p_i to p' the robot is to play at p' with h - 1
left.  σ has paid V_0(p) - V_0(p_i) by then (every action of an optimal plan
lowers V_0 by its cost), so

    B_0(p) = V_0(p),
    B_h(p) = V_0(p) + max(0, max over i and moves m at p_i of B_{h-1}(m p_i) - V_0(p_i)),

where a move that makes the task hold counts B = 0 (the robot has won).  This is
an equation, not a bound: B_k(start) is exactly the most σ pays against any human,
so E_p <= B_k(start).  It holds for every game of the semantics whose robot moves
cost at least one unit (V_0 finite where σ goes; else B is infinite and there is
no bound).  `replanning_bound` evaluates it with `levels` levels of the recursion
enumerated; each level multiplies the V_0 questions by the plan length times the
human's moves (about 30 x 50 at pattern 8 x 12), so `levels = k` is only
affordable for small games or k <= 1.  `solvers.replan_budget` asks "B_k <= T?"
instead, which scales further (it is what `solvers.andor` uses for an anytime
answer's upper end).

Below the enumerated levels a **tail** D may stand in: if every human move at
every position σ meets rises V_0 by at most D, then B_h(p) <= V_0(p) + h D
(potential V_0 + h D: a robot action of σ lowers it by its cost, a human move
does not raise it).  A bound on D from the costmap alone is
bench/replan_repair.py's D+ (its proof in bench/results/game-notes.md, "A repair
bound D+ from the costmap"); one of its cases, C5 (an object the human puts from
Else onto a location), has no constant bound (the notes say why), so D+ is not
proven and a bound that uses a tail is reported as **conditional**, never as the
upper end of a certified interval (`ReplanBound.certified`).

The solver asks `solvers.replan_budget`'s question ("does σ pay at most T?")
instead of enumerating; `replanning_bound` stays as its reference (the tests
compare the two on generated scenes) and for `bench/replan_interval.py`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from symsynth.game.abstraction import State, after_robot_action, in_costmap_units, legal_human_moves
from symsynth.game.solution import OutOfReach, Position, Step
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.packed.kernels import INF as INF_UNITS
from symsynth.solvers.packed.search import LO_H

if TYPE_CHECKING:
    from symsynth.solvers.andor import Memo

INF = math.inf
#: The largest budget the no-human questions ask (the kernel sorts by budget << 16 in 64 bits)
MAX_BUDGET = 1 << 40
ZERO_COST = ("a robot move of this game costs 0 units: the AND-OR search that finds the replanning strategy's "
             "plans does not answer such games")


#: Questions between two returns of the search's kernel for V_0 (a quarter of it under a
#: deadline): its questions take no deadline of their own, so they are not cut finer when a
#: caller's search is (andor.CHUNK); the enumeration's deadline stops them where a chunk ends
ORACLE_CHUNK = 2_000_000


class NoHumanValue:
    """V_0 and σ's action at any (state, DFA state): the AND-OR search with no
    human move left from there (exact: it proves lower = upper), over one memo."""

    def __init__(self, scene: Scene, formula: ast.Formula, resolution: float = 1.0, memo: Memo | None = None):
        """With `memo`, an AND-OR search's memo of the same game at `resolution`
        over tables without symmetry (any k: V_0 is read at its h = 0 nodes),
        whose proven bounds it starts from; else a new one with k = 0."""
        from symsynth.solvers import andor
        from symsynth.solvers.packed.lower import BoundTables
        from symsynth.solvers.packed.tables import Tables

        andor.prepare()
        self.scene, self._andor = scene, andor
        if memo is None:
            tables = Tables(scene, formula, resolution, None, 0)
            memo = andor.Memo(tables, BoundTables(tables, formula), 0)
        elif memo.t.symmetry is not None:
            raise ValueError("the replanning strategy reads V_0 at real positions: a memo over canonical ones "
                             "does not serve")
        elif memo.t.resolution != resolution or memo.t.scene is not scene:
            raise ValueError("the search's memo is of another game (scene or resolution)")
        self.t, self.memo = memo.t, memo
        self.memo.chunk = ORACLE_CHUNK
        self.memo.tighten()  # no human move left: the assignment bound pays here
        self.proof = andor.Proof(self.memo)
        self.questions = 0

    def start(self, v: State) -> int:
        """The DFA state (index) after reading the initial letter of state v."""
        return self.t.step(self.t.dfa_index[self.t.dfa.initial], self.t.pack(v))

    def step(self, q: int, v: State) -> int:
        return self.t.step(q, self.t.pack(v))

    def accepting(self, q: int) -> bool:
        return bool(self.t.accepting[q])

    def _node(self, v: State, q: int) -> int | None:
        """The proven node of (v, q), None when V_0 is infinite."""
        memo = self.memo
        i = memo.node(memo.key2(self.t.pack(v), q, 0))
        self.questions += 1
        try:
            return i if self.settle(i) else None
        except self._andor.CutOff:  # past the enumeration's deadline (`replanning_bound`)
            raise _Deadline from None

    def settle(self, i: int) -> bool:
        """Prove V_0 at memo node i (lo = hi after it); False when it is infinite.
        "V_0 <= 2 lo + 64?" first, a plan within about twice the lower bound,
        then halving [lo, hi].  Without one, the search's rounds from below, and
        where they give up (`andor.MAX_ROUNDS`: V_0 far above the lower bound, a
        cheap cycle raising lo one unit a round) `_doubled`.  Every answer is
        proven, so lo <= V_0 <= hi throughout."""
        andor, memo = self._andor, self.memo
        if memo.hi_h(i) >= INF_UNITS > memo.lo_h(i):
            self.ask(i, 2 * memo.lo_h(i) + 64)
        if memo.hi_h(i) >= INF_UNITS:
            try:
                if andor._search(memo, i, None)[1] is None:
                    return False
            except andor.ZeroCost:
                raise OutOfReach(ZERO_COST) from None
            except andor._TooManyRounds:
                if not self._doubled(i):
                    return False
        while memo.lo_h(i) < memo.hi_h(i):
            self.ask(i, (memo.lo_h(i) + memo.hi_h(i)) // 2)
        return True

    def _doubled(self, i: int) -> bool:
        """"V_0 <= 2 lo + 64?" until a yes (True) or lo is infinite (False), the
        trap check after every no.  It ends: a no that expands no new node is
        followed by the trap check, which, once every node a plan could use is
        expanded, proves lo infinite where no plan exists (the no-human game is
        finite); while nodes are left, a larger budget expands more of them.
        Calling the trap after each no (not every 8, 16, ... as the rounds do)
        keeps the budget, and so the search's depth, near what the game needs:
        a budget far above it sends the depth-first search round cheap cycles
        (a review measured 1.8 GB of stack at b = 4.3 M with the trap held back).
        Only reached where the rounds gave up, so the trap's pass over the memo
        is rare.  Budgets stop at `MAX_BUDGET`: past it V_0 is out of reach."""
        memo = self.memo
        while memo.hi_h(i) >= INF_UNITS:
            lo = memo.lo_h(i)
            if lo >= INF_UNITS:
                return False
            if lo > MAX_BUDGET:
                raise OutOfReach(f"a no-human value above {MAX_BUDGET} units: rescale the costmap "
                                 "(a coarser --resolution)")
            if not self.ask(i, min(2 * lo + 64, MAX_BUDGET)):
                memo.trap()
        return True

    def ask(self, i: int, b: int) -> bool:
        """V_0 <= b at node i, answered: lo > b or hi <= b after it."""
        memo = self.memo
        try:
            ok = memo.ask(i, b, False, None)
        except self._andor.ZeroCost:
            raise OutOfReach(ZERO_COST) from None
        if not ok and memo.lo_h(i) <= b:
            memo.rec[i, LO_H] = b + 1
        return bool(ok)

    def value(self, v: State, q: int) -> float:
        """V_0(v, q) in units (inf when the robot cannot win alone); 0 when q accepts."""
        if self.accepting(q):
            return 0
        i = self._node(v, q)
        return INF if i is None else int(self.memo.hi_h(i))

    def plan(self, v: State, q: int) -> list[tuple[str, int, State, int]]:
        """σ's plan from (v, q): (action, units, state after, DFA state after) to the win."""
        out: list[tuple[str, int, State, int]] = []
        i = None if self.accepting(q) else self._node(v, q)
        if i is None and not self.accepting(q):
            raise ValueError("V_0 is infinite here: no plan")
        while i is not None:
            action, units, j = self.proof.chosen(i)
            if j < 0:  # the action wins: the state after is read from the move itself
                after = after_robot_action(self.scene, v, action)
                out.append((action, units, after, self.step(q, after)))
                return out
            v, state, _ = self.proof.position(j)
            q = self.t.dfa_index[state]
            out.append((action, units, v, q))
            i = j
        return out

    def action(self, v: State, q: int) -> str:
        """σ's action at (v, q)."""
        i = self._node(v, q)
        if i is None:
            raise KeyError("V_0 is infinite: σ has no action")
        return self.proof.chosen(i)[0]


class ReplanningStrategy(Mapping):
    """σ as a strategy (Position -> action), computed when asked: memoryless and
    the same at every h.  Iterating it is refused (it has no table); what reads a
    strategy along its plays (`game.strategy.guaranteed_units`) only looks up."""

    def __init__(self, oracle: NoHumanValue):
        self._oracle = oracle

    def __getitem__(self, position: Position) -> str:
        v, q, _ = position
        qi = self._oracle.t.dfa_index.get(q)
        if qi is None:
            raise KeyError(position)
        return self._oracle.action(v, qi)

    def __iter__(self) -> Iterator[Position]:
        raise TypeError("the replanning strategy is computed position by position: it has no table to list")

    def __len__(self) -> int:
        raise TypeError("the replanning strategy is computed position by position: it has no table to count")


@dataclass(frozen=True)
class ReplanBound:
    """B_k(start) for σ (module doc), in units.

    - `v0`: V_0 at the start (nan when the deadline passed first); `first_rise`: the largest rise of V_0 over one human
      move on σ's plan from the start (what the first enumerated level adds);
    - `upper`: the bound (inf when σ can meet a position where it cannot win);
    - `levels`: enumerated levels; `tail`: the per-move bound used below them;
    - `certified`: the bound is proven (every level enumerated, or a proven tail);
    - `complete`: False when the deadline stopped the enumeration (then `upper` is None).
    """

    v0: float
    first_rise: float
    upper: float | None
    levels: int
    tail: float | None
    certified: bool
    complete: bool
    questions: int
    seconds: float
    principal: tuple[Step, ...] = ()
    oracle: NoHumanValue | None = field(default=None, repr=False, compare=False)

    @property
    def strategy(self) -> ReplanningStrategy:
        """σ, the strategy that pays at most `upper`."""
        if self.oracle is None:
            raise ValueError("no oracle kept with this bound")
        return ReplanningStrategy(self.oracle)


class _Deadline(Exception):
    pass


def replanning_bound(scene: Scene, formula: ast.Formula, k: int, *, resolution: float = 1.0,
                     levels: int | None = None, tail: float | None = None, tail_proven: bool = False,
                     deadline: float | None = None, oracle: NoHumanValue | None = None) -> ReplanBound:
    """B_k(start) with `levels` (default k) levels enumerated and `tail` (units per
    human move) below them (module doc).  `tail_proven` says whether the tail is a
    proven bound on every rise σ can meet; the bench's D+ is not (C5)."""
    from symsynth.game.abstraction import initial_state

    clock = time.perf_counter()
    levels = k if levels is None else min(levels, k)
    if levels < k and tail is None:
        raise ValueError("fewer levels than k need a tail bound for the levels below")
    oracle = oracle or NoHumanValue(scene, formula, resolution)
    walk = _Walk(oracle, tail, deadline)
    v = initial_state(scene)
    q = oracle.start(v)
    walk.top = k
    v0 = math.nan  # unknown when the deadline passes before V_0 at the start is proven
    # V_0's questions stop too where a chunk ends past the deadline (one V_0 at sorting
    # 8 x 12, with no reduction by interchangeable objects here, took 111 s)
    oracle.memo.cutoff = deadline
    try:
        v0 = oracle.value(v, q)
        if deadline is not None and levels >= 2 and _hopeless(oracle, v, q, levels, deadline):
            raise _Deadline
        upper = walk.bound(v, q, k, k - levels, True)
        complete = True
    except _Deadline:
        upper, complete = None, False
    finally:
        oracle.memo.cutoff = None  # σ's plans on the bound's plays are proven: read back without one
    certified = complete and (levels == k or tail_proven)
    principal = tuple(walk.play(v, q, k, True)) if certified and levels == k and upper is not None \
        and upper < INF else ()
    return ReplanBound(v0, walk.first_rise, upper, levels, None if levels == k else tail, certified,
                       complete, oracle.questions, time.perf_counter() - clock, principal, oracle)


#: V_0 questions a second the enumeration is taken to answer at least (pattern 3 x 5 -
#: 8 x 12: 700 - 25,000 a second), for `_hopeless`
QUESTIONS_PER_SECOND = 2000


def _hopeless(oracle: NoHumanValue, v: State, q: int, levels: int, deadline: float) -> bool:
    """Whether `levels` enumerated levels clearly cannot finish by `deadline`: the
    human's moves on σ's plan from the start, T, to the power levels - 1 (pattern
    3 x 5 - 4 x 6 at k = 3 asked 0.6 - 1 times that), above ten times what the time
    left answers at `QUESTIONS_PER_SECOND`."""
    if oracle.accepting(q) or oracle.value(v, q) == INF:
        return False
    turns = [(v, q)] + [(after, qa) for _, _, after, qa in oracle.plan(v, q)[:-1]]
    moves = sum(len(legal_human_moves(oracle.scene, vi)) for vi, _ in turns)
    return moves ** (levels - 1) > 10 * QUESTIONS_PER_SECOND * max(0.0, deadline - time.perf_counter())


class _Walk:
    """The recursion B_h, memoized by (state, DFA state, h, whether the human moves first)."""

    def __init__(self, oracle: NoHumanValue, tail: float | None, deadline: float | None):
        self.o, self.tail, self.deadline = oracle, tail, deadline
        self.memo: dict[tuple, float] = {}
        self.worst: dict[tuple, tuple | None] = {}
        self.first_rise = -INF
        self.top = -1

    def bound(self, v: State, q: int, h: int, floor: int, human_first: bool) -> float:
        """B_h at (v, q); levels at h <= floor use the tail."""
        o = self.o
        if o.accepting(q):
            return 0
        if h == 0:
            return o.value(v, q)
        if h <= floor:
            if self.tail is None:  # pragma: no cover - replanning_bound asks for one
                raise ValueError("no tail bound for the levels below the enumerated ones")
            return o.value(v, q) + h * self.tail
        key = (v, q, h, human_first)
        if key in self.memo:
            return self.memo[key]
        if self.deadline is not None and time.perf_counter() > self.deadline:
            raise _Deadline
        v0 = o.value(v, q)
        if v0 == INF:
            self.memo[key] = INF
            return INF
        rise, worst = 0.0, None
        for n, (vi, qi, left) in enumerate(self._turns(v, q, v0, human_first)):
            for mv in legal_human_moves(o.scene, vi):
                q2 = o.step(qi, mv.after)
                after = self.bound(mv.after, q2, h - 1, floor, False)
                if after - left > rise:
                    rise, worst = after - left, (n, mv.action, mv.after, q2)
                if h == self.top:
                    self.first_rise = max(self.first_rise, o.value(mv.after, q2) - left)
        self.memo[key] = v0 + rise
        self.worst[key] = worst
        return v0 + rise

    def play(self, v: State, q: int, h: int, human_first: bool) -> list[Step]:
        """σ against the human of the largest B (recorded by `bound`), to the win."""
        plan = self.o.plan(v, q) if not self.o.accepting(q) else []
        worst = self.worst.get((v, q, h, human_first)) if h > 0 else None
        r = self.o.t.resolution
        if worst is None:
            return [Step("robot", a, in_costmap_units(u, r), after) for a, u, after, _ in plan]
        n, action, after, q2 = worst
        robot = n if human_first else n + 1  # robot actions before the human's turn n
        out = [Step("robot", a, in_costmap_units(u, r), s) for a, u, s, _ in plan[:robot]]
        out.append(Step("human", action, 0.0, after))
        return out + self.play(after, q2, h - 1, False)

    def _turns(self, v: State, q: int, v0: float, human_first: bool) -> list[tuple[State, int, float]]:
        """The human turns on σ's plan from (v, q): (state, DFA state, V_0 there)."""
        turns = [(v, q, v0)] if human_first else []
        left = v0
        for _, units, after, q_after in self.o.plan(v, q):
            left -= units
            if self.o.accepting(q_after):
                break
            turns.append((after, q_after, left))
        return turns
