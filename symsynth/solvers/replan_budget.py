"""Whether the replanning strategy σ pays at most a budget (issue 32):
`solvers.replan`'s B_k(start) <= T, asked as a question, not computed.

With R_h(p) = B_h(p) - V_0(p) (what σ may pay above its no-human plan),
`solvers.replan`'s recursion reads

    R_0(p) = 0,
    R_h(p) = max(0, max over the human turns p_i on σ's plan from p and the
                 moves m there of V_0(m p_i) - V_0(p_i) + R_{h-1}(m p_i)),

with R = -V_0(p_i) for a move that makes the task hold (B = 0 there).  So
"R_h(p) <= s?" is, for s >= 0: for every turn i and move m, "R_{h-1}(m p_i)
<= s - (V_0(m p_i) - V_0(p_i))?".  What makes it far cheaper than the
value:

- At h = 1 the question on a move is "V_0(m p_i) <= V_0(p_i) + s?", which
  needs no V_0, only a plan within the budget (V_0 is the least cost of a
  plan) or a proof that none exists.  All the moves of the turns of one plan
  go to the machine code in one call (`packed.replies._settle`), up to the
  first "no", and each is answered by the first of:
  1. the no-human searches' shared memo (`NoHumanValue`'s: a k = 0 one, or
     the AND-OR search's own at its h = 0 nodes), when the node's proven
     bounds decide it (lo > b: no; hi <= b: yes);
  2. a repair: the moved object carried back and the hand put where it was,
     ending in p_i itself, so V_0(m p_i) <= its cost + V_0(p_i);
  3. σ's own next actions played from m p_i until the play meets σ's plan
     at some p_j (cost + V_0(p_j)) or wins;
  4. the search for a plan within the budget (`packed.search._ask`, the same
     question the AND-OR search asks itself), which also proves a "no".
  The plans of 2 and 3 are checked action by action: each is generated at
  the state it is played in, with its cost there (by the branch of the
  game's move generator that makes it, `packed.replies._robot_move`), and
  the DFA reads every letter, so neither needs a case analysis of the
  human's move to be sound (bench/replan_repair.py's D+ does).
- A question answered at (p, h) with a smaller s that said yes, or a larger
  one that said no, answers it again (R_h(p) is one number); the same per
  turn of a plan (p_i, h), since σ's plans from different positions meet.
  At h = 1 a yes is kept for the largest rise its certificates showed (the
  kernel returns the bound that answered each reply: the node's proven hi,
  or a plan's cost), which may be below s: R_1(p) is at most that.

Above h = 1 the moves' V_0 are found exactly (σ's plan from m p_i is needed
there) and the moves of all turns asked in the order of their rise, largest
first, so a "no" comes early.  Every answer is exact: "yes" proves
B_k(start) <= T, whence E_p <= T (σ is a strategy, `solvers.replan`), and
"no" proves that σ can be made to pay more than T.  σ's actions are the
memo's proven ones, as in `solvers.replan` (the same oracle may serve both):
a node with an exact upper end keeps its chosen action, so the plans a
question read stay σ's plans.

`solvers.replan_spare` asks the same question for σ_Z, the strategy that
keeps spare places free: it changes where the values, plans and replies'
memo come from (`value_at`, `_oracle_at`, `_memo_at`) and adds two
shortcuts by a proven rise bound (`_by_class`, `_exact_children`).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

import numpy as np

from symsynth.game.abstraction import in_costmap_units, initial_state, legal_human_moves
from symsynth.game.solution import OutOfReach, Solution, Step, bracket_verdict
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.packed import replies as rk
from symsynth.solvers.packed import search as sk
from symsynth.solvers.replan import ORACLE_CHUNK, ZERO_COST, NoHumanValue, ReplanningStrategy
from symsynth.solvers.rise import Rises, rise_bounds

if TYPE_CHECKING:
    from symsynth.solvers.andor import Memo

INF = math.inf
#: Search steps between two looks at the clock within one call of `packed.replies._settle`
#: under a deadline (2 M took up to 9 s at 7 x 10)
DEADLINE_CHUNK = 100_000
#: Calls of the recursion (each a kernel call or a V_0) between two looks at the clock
LOOK_EVERY = 64

#: Seconds past the limit the replanning upper end's principal play may take (it reads the
#: question's answers back, a search only where one is missing)
PLAY_GRACE = 1.0


class Deadline(Exception):
    """The deadline passed before the question was answered."""


class BudgetedBound:
    """"Does σ pay at most T from the start?" for any T, the answers of
    earlier questions kept (module doc)."""

    #: The strategy's name in an answer's stats
    name = "σ"

    def __init__(self, scene: Scene, formula: ast.Formula, k: int, resolution: float = 1.0,
                 oracle: NoHumanValue | None = None):
        from symsynth.solvers import andor

        self.k, self._andor = k, andor
        self.oracle = oracle or NoHumanValue(scene, formula, resolution)
        self.t, self.memo = self.oracle.t, self.oracle.memo
        self._values: dict[tuple[int, int], float] = {}
        self._known: dict[tuple[int, int, int, bool], tuple[float, float]] = {}  # (largest no, least yes)
        self._at_turn: dict[tuple[int, int, int], tuple[float, float]] = {}  # the same for one turn
        self.deadline: float | None = None
        self._calls = 0
        #: replies answered by the memo's bounds, by a repair, by σ's plan followed, by the search
        self.counts = np.zeros(4, np.int64)
        self.settled = 0  # moves checked against a budget in machine code
        v = initial_state(scene)
        self.start = (self.t.pack(v), self.oracle.start(v))
        self._keys = np.empty(1024, np.int64)
        self._turn = np.empty(1024, np.int64)
        self._plan_key = np.empty(256, np.int64)
        self._plan_move = np.empty(256, np.int64)

    @contextmanager
    def limited(self, deadline: float | None) -> Iterator[None]:
        """Every question inside ends by `deadline` (time.perf_counter; None: no
        end): the bound's own loops look at it, and the no-human searches stop
        where a chunk of their steps ends past it (`Memo.cutoff`); `Deadline`
        then (a no-human search that gives up its rounds goes on by doubling its
        budget, `NoHumanValue.settle`)."""
        memos = self._memos()
        self.deadline = deadline
        for memo in memos:
            memo.cutoff = deadline
        try:
            yield
        except self._andor.CutOff:
            raise Deadline from None
        finally:
            self.deadline = None
            for memo in memos:
                memo.cutoff = None

    # -- what a subclass of another strategy changes (`solvers.replan_spare`) ------------------
    def _memos(self) -> list[Memo]:
        """Every no-human memo the questions search."""
        return [self.memo]

    def value_at(self, x: int, q: int, h: int) -> float:
        """What the strategy's bound starts from at (x, q) with h moves left: V_0 for σ."""
        return self.value(x, q)

    def _memo_at(self, h: int) -> Memo:
        """The memo whose V_0 the replies at a turn with h moves left are asked on."""
        return self.memo

    def _oracle_at(self, h: int) -> NoHumanValue:
        """The oracle whose plan the strategy follows with h moves left."""
        return self.oracle

    def _by_class(self, keys: np.ndarray, turn: np.ndarray, plan: tuple[np.ndarray, ...],
                  s: float) -> np.ndarray | None:
        """At h = 1: per reply, a bound on V_0 after it within its budget known
        without a certificate (-1: none); None when no reply has one."""
        return None

    @property
    def strategy(self) -> ReplanningStrategy:
        """σ, the strategy that `within` speaks of."""
        return ReplanningStrategy(self.oracle)

    def answered(self, target: int) -> bool | None:
        """What `within(target)` said or would say from what is known, None when unknown."""
        x, q = self.start
        if self.t.accepting[q] or self.value_at(x, q, self.k) >= INF:
            return target >= 0 if self.t.accepting[q] else False
        no, yes = self._known.get((x, q, self.k, True), (-1.0, INF))
        s = target - self.value_at(x, q, self.k)
        return True if s >= yes else False if s < 0 or s <= no else None

    def worst_play(self, upper: int) -> tuple[Step, ...]:
        """σ against a human who makes it pay `upper`, when `upper` is B_k(start)
        (`within(upper)` yes, `within(upper - 1)` no): at each position, σ's plan
        up to the turn of a move whose rise plus what σ can be made to pay after
        it exceeds what is left of upper - 1, that move, and on from there."""
        t, r = self.t, self.t.resolution
        x, q = self.start
        h, human_first = self.k, True
        s = upper - 1 - self.value_at(x, q, h)
        steps: list[Step] = []
        while not t.accepting[q]:
            found = self._exceeding(x, q, h, s, human_first) if h > 0 and s >= 0 else None
            v = t.unpack(x)
            plan = [Step("robot", a, in_costmap_units(u, r), after)
                    for a, u, after, _ in self._oracle_at(h).plan(v, q)]
            if found is None:
                return tuple(steps + plan)
            j, w, q2, rise = found
            robot = j if human_first else j + 1  # σ's actions before the human's turn j
            steps += plan[:robot]
            here = plan[robot - 1].state if robot > 0 else v
            move = next(mv for mv in legal_human_moves(self.oracle.scene, here) if t.pack(mv.after) == w)
            steps.append(Step("human", move.action, 0.0, move.after))
            x, q, h, human_first, s = w, q2, h - 1, False, s - rise
        return tuple(steps)

    def _exceeding(self, x: int, q: int, h: int, s: float, human_first: bool) -> tuple[int, int, int, float] | None:
        """A move (turn, state after, DFA state after, rise) on σ's plan from
        (x, q) after which σ can be made to pay more than s above V_0(x, q):
        asked in the order `_fits` asks them (a rise above s first, then the
        largest rises first), so that its answers are read back, not searched."""
        plan = self._turns(x, q, human_first)
        xs, qs, left, _ = plan
        count = self._replies(xs, qs)
        keys, turn = self._keys[:count].copy(), self._turn[:count].copy()
        r, _ = self._settle(keys, left[turn] + s, turn, plan, self._memo_at(h))
        moves = self._rises(keys[:r + 1], turn, left, h - 1)
        if r < count:  # that move's V_0 is above its budget
            rise, w, q2, j = moves[-1]
            return j, w, q2, rise
        moves.sort(reverse=True)
        for rise, w, q2, j in moves:
            if not self._fits(w, q2, h - 1, s - rise, False):
                return j, w, q2, rise
        return None

    def passing_play(self) -> tuple[Step, ...]:
        """σ's play when the human always passes: its no-human plan from the start."""
        v = self.oracle.t.unpack(self.start[0])
        if self.t.accepting[self.start[1]]:
            return ()
        r = self.t.resolution
        plan = self.oracle.plan(v, self.start[1])
        return tuple(Step("robot", a, in_costmap_units(u, r), after) for a, u, after, _ in plan)

    @property
    def v0(self) -> float:
        """What the bound starts from at the start (units): V_0 for σ."""
        return self.value_at(*self.start, self.k)

    def within(self, target: int, deadline: float | None = None) -> bool:
        """Whether B_k(start) <= target (units, finite: a budget for the
        search); `Deadline` when `deadline`
        (time.perf_counter) passes first (what was answered is kept)."""
        self.deadline = deadline
        x, q = self.start
        return self.within_from(x, q, self.k, target, human_first=True)

    def within_from(self, x: int, q: int, h: int, target: int, human_first: bool = False) -> bool:
        """Whether σ pays at most target from (x, q) (packed state, DFA index)
        with h human moves left, at its robot turn (or its human turn, with
        `human_first`): B_h there <= target."""
        if self.t.accepting[q]:
            return target >= 0
        v0 = self.value_at(x, q, h)
        return v0 <= target and self._fits(x, q, h, target - v0, human_first)

    def kept_within(self, x: int, q: int, h: int, human_first: bool = False) -> float:
        """The least target `within_from(x, q, h, target, human_first)` is known
        to say yes to (inf when none is): a yes at h = 1 keeps the largest rise
        its certificates showed, which may be below the target asked."""
        if self.t.accepting[q]:
            return 0
        v0 = self.value_at(x, q, h)
        return v0 if h == 0 else v0 + self._known.get((x, q, h, human_first), (-1.0, INF))[1]

    def least(self, lower: int, upper: int, deadline: float | None = None) -> float:
        """B_k(start) exactly when it is at most `upper`, given lower <=
        B_k(start): the least T in [lower, upper] that `within` says yes to,
        by bisection; inf when B_k(start) > upper."""
        v0 = self.v0
        if v0 >= INF or not self.within(upper, deadline):
            return INF
        lower, hi = max(lower, int(v0)), upper
        while lower < hi:
            mid = (lower + hi) // 2
            if self.within(mid, deadline):
                hi = mid
            else:
                lower = mid + 1
        return lower

    # -- the recursion ---------------------------------------------------------------
    def _fits(self, x: int, q: int, h: int, s: float, human_first: bool) -> bool:
        """R_h(x, q) <= s (module doc); V_0(x, q) finite and q not accepting."""
        if s < 0:
            return False
        if h == 0:
            return True
        key = (x, q, h, human_first)
        no, yes = self._known.get(key, (-1.0, INF))
        if s >= yes:
            return True
        if s <= no:
            return False
        self._look()
        plan = self._turns(x, q, human_first)
        xs, qs, left = plan[:3]
        todo, kept = [], 0.0  # the turns to settle; the largest rise known at the others
        for j, turn in enumerate(zip(xs.tolist(), qs.tolist())):
            no_j, yes_j = self._at_turn.get((*turn, h), (-1.0, INF))
            if s <= no_j:
                self._known[key] = (s, yes)
                return False
            if s < yes_j:
                todo.append(j)
            else:
                kept = max(kept, yes_j)
        # every move's V_0 within its budget first (R_{h-1} >= 0): all of it at h = 1, a quick no above
        rise, upper = self._settle_turns(plan, np.array(todo, np.int64), s, h)
        if rise is not None and h > 1:
            rise = s if self._deeper(xs[todo], qs[todo], left[todo], h, s, upper) else None
        # at h = 1 a yes holds for the largest rise its certificates showed (R_1 <= that), not only for s
        self._known[key] = (s, yes) if rise is None else (no, max(kept, rise))
        return rise is not None

    def _record(self, turn: tuple[int, int, int], s: float, ok: bool) -> None:
        """What was answered at a turn: its moves rise (plus R below) by at most s, or not."""
        no, yes = self._at_turn.get(turn, (-1.0, INF))
        self._at_turn[turn] = (no, min(yes, s)) if ok else (max(no, s), yes)

    def _settle_turns(self, plan: tuple[np.ndarray, ...], todo: np.ndarray, s: float,
                      h: int) -> tuple[float | None, np.ndarray]:
        """V_0(m p_j) <= V_0(p_j) + s for every turn j in todo and move m there
        (plan: `_turns`' arrays): at h = 1 that is the answer at each turn,
        above it a necessary condition.  (None when it fails, else the largest
        rise V_0(m p_j) - V_0(p_j) the certificates showed (at least 0, at most
        s); per move, in `_replies`' order over the turns todo, the bound on
        its V_0 that answered it.)  At h = 1 a move `_by_class` bounds is
        answered by that bound, with no certificate."""
        xs, qs, left, codes = plan
        count = self._replies(xs[todo], qs[todo])
        turn = todo[self._turn[:count]]
        keys, known = self._keys[:count], None
        if h == 1:
            known = self._by_class(keys, turn, plan, s)
            if known is not None:
                keys = np.where(known >= 0, -1, keys)
        r, upper = self._settle(keys, left[turn] + s, turn, plan, self._memo_at(h))
        if known is not None:
            upper = np.where(known >= 0, known, upper)
        failed = int(np.searchsorted(todo, turn[r])) if r < count else len(todo)
        rises = np.zeros(len(xs))  # per turn (R_1 >= 0); only h = 1 reads them
        if h == 1:
            np.maximum.at(rises, turn[:r], upper[:r] - left[turn[:r]])
            for j in todo[:failed].tolist():
                self._record((int(xs[j]), int(qs[j]), 1), float(rises[j]), True)
        if failed < len(todo):
            j = int(todo[failed])
            self._record((int(xs[j]), int(qs[j]), h), s, False)
            return None, upper
        return float(rises[todo].max(initial=0.0)), upper

    def _deeper(self, xs: np.ndarray, qs: np.ndarray, left: np.ndarray, h: int, s: float,
                upper: np.ndarray) -> bool:
        """At h >= 2: R_{h-1}(m p_j) + V_0(m p_j) - V_0(p_j) <= s for every turn j
        and move m (whose V_0 are known to be within V_0(p_j) + s, `upper` the
        bounds that showed it, in `_replies`' order), the moves of every turn
        asked together, largest rise first (a no comes early)."""
        count = self._replies(xs, qs)
        children = self._exact_children(self._keys[:count].copy(), self._turn[:count].copy(), left, h, s, upper)
        children.sort(reverse=True)
        for rise, x2, q2, j in children:
            if not self._fits(x2, q2, h - 1, s - rise, False):
                self._record((int(xs[j]), int(qs[j]), h), s, False)
                return False
        for j in range(len(xs)):
            self._record((int(xs[j]), int(qs[j]), h), s, True)
        return True

    def _exact_children(self, keys: np.ndarray, turn: np.ndarray, left: np.ndarray, h: int, s: float,
                        upper: np.ndarray) -> list[tuple[float, int, int, int]]:
        """`_rises` of the moves at h >= 2 that `_deeper` must ask (for σ: all)."""
        return self._rises(keys, turn, left, h - 1)

    def _rises(self, keys: np.ndarray, turn: np.ndarray, left: np.ndarray,
               h: int) -> list[tuple[float, int, int, int]]:
        """(rise, x, q after, turn) of each reply (`keys`, a move that wins: < 0,
        skipped), h moves left after it, `left` V_0 at each turn of the plan:
        the rise from there to `value_at` after the move."""
        out = []
        for key, j in zip(keys.tolist(), turn.tolist()):
            if key >= 0:
                x, q = self.memo.position(key)
                out.append((self.value_at(x, q, h) - float(left[j]), x, q, j))
        return out

    def _look(self, every: int = LOOK_EVERY) -> None:
        """`Deadline` when the deadline has passed, looked at once in `every` calls."""
        self._calls += 1
        if self.deadline is not None and self._calls % every == 0 and time.perf_counter() > self.deadline:
            raise Deadline

    # -- the no-human game's memo ----------------------------------------------------------
    def value(self, x: int, q: int) -> float:
        """V_0(x, q) in units, exact (inf: the robot cannot win alone; 0: q accepts)."""
        return self._value_on(self.oracle, self._values, x, q)

    def _value_on(self, oracle: NoHumanValue, values: dict[tuple[int, int], float], x: int, q: int) -> float:
        """`value` by `oracle`, kept in `values`."""
        if self.t.accepting[q]:
            return 0
        found = values.get((x, q))
        if found is not None:
            return found
        self._look()
        memo = oracle.memo
        i = memo.node(memo.key2(x, q, 0))
        oracle.questions += 1
        value = float(memo.hi_h(i)) if oracle.settle(i) else INF
        values[(x, q)] = value
        return value

    def _turns(self, x: int, q: int, human_first: bool) -> tuple[np.ndarray, ...]:
        """The human turns on σ's plan from (x, q): packed states, DFA states, V_0
        there, and σ's action there (its code)."""
        memo, qbits = self.memo, self.t.qbits
        i = memo.find(memo.key2(x, q, 0))
        if i is None:  # pragma: no cover - value(x, q) made it
            raise RuntimeError("internal error: σ's plan asked before its value")
        while True:
            count = int(rk._plan(np.int64(i), memo.rec, memo.rm_tgt, memo.rm_move, np.int64(memo.hb),
                                 self._plan_key, self._plan_move))
            if count >= 0:
                break
            self._plan_key = np.empty(2 * len(self._plan_key), np.int64)
            self._plan_move = np.empty(2 * len(self._plan_move), np.int64)
        keys, moves = self._plan_key[:count - 1], self._plan_move[:count]
        bits = self.t.code_bits
        codes = moves & ((1 << bits) - 1)
        v0 = self.value(x, q)
        left = v0 - np.cumsum(moves[:count - 1] >> bits)
        xs, qs = keys >> qbits, keys & ((1 << qbits) - 1)
        if human_first:
            return np.append(x, xs), np.append(q, qs), np.append(v0, left), codes
        return xs, qs, left.astype(np.float64), codes[1:]

    def _replies(self, xs: np.ndarray, qs: np.ndarray) -> int:
        """Every human move at the turns into self._keys / self._turn; their count."""
        memo = self.memo
        need = len(xs) * memo.room
        if len(self._keys) < need:
            self._keys = np.empty(need, np.int64)
            self._turn = np.empty(need, np.int64)
        return int(rk._replies(xs, qs, memo.P, memo.G, memo.S(), self._keys, self._turn))

    def _settle(self, keys: np.ndarray, budgets: np.ndarray, turn: np.ndarray,
                plan: tuple[np.ndarray, ...], memo: Memo) -> tuple[int, np.ndarray]:
        """(the first move whose V_0 (on `memo`'s game) is above its budget
        (`packed.replies._settle`), len(keys) when none is; per move before it,
        the bound on V_0 that answered it); move r is at turn turn[r] of the
        plan (`_turns`' arrays)."""
        st = memo.st
        if memo.hb != self.memo.hb:  # (a memo with more moves left keeps h in more bits)
            keys = np.where(keys >= 0, (keys >> self.memo.hb) << memo.hb, keys)
        xs, qs, left, codes = plan
        budgets = np.minimum(budgets, float(1 << 40)).astype(np.int64)
        bases = np.minimum(left, float(1 << 40)).astype(np.int64)
        first = 0
        upper = np.zeros(len(keys), np.int64)
        while True:
            st[sk.ST_ABORT] = 0
            st[sk.ST_LIMIT] = st[sk.ST_CALLS] + (ORACLE_CHUNK if self.deadline is None else DEADLINE_CHUNK)
            first = int(rk._settle(keys, budgets, turn, xs, qs, bases, codes, np.int64(first), memo.P, memo.G,
                                   memo.B, memo.M(), memo.S(), np.int64(memo.room), self.counts, upper))
            why = int(st[sk.ST_ABORT])
            if why == 0:
                self.settled += first
                return first, upper
            if why == sk.ABORT_ZERO:
                raise OutOfReach(ZERO_COST)
            memo.recover(why)
            self._look(every=1)


#: The steps above the lower end at which `certified_upper` asks, as shares of it
#: (doubling: 1 %, 2 %, 4 %, ...); the first "yes" is then halved towards the last "no"
FIRST_STEP = 0.01
#: `certified_upper` asks up to this many times the larger of the lower end and V_0(start)
#: (a bound beyond it is no use as an upper end, and the budgets of its questions stay small)
MAX_RATIO = 4


def certified_upper(scene: Scene, formula: ast.Formula, k: int, lower: int, ceiling: int | None, *,
                    resolution: float = 1.0, deadline: float | None = None, memo: Memo | None = None,
                    rises: Rises | None = None) -> tuple[int, BudgetedBound] | None:
    """The least T found before `deadline` with B_k(start) <= T proven, asked at
    `lower` (E_p >= lower, so a yes there proves E_p = lower) and then 1 %, 2 %,
    4 %, ... above it while below `ceiling` (an upper end known otherwise, None:
    none) and
    `MAX_RATIO` times the lower end; the first yes then bisected towards the
    last no while time is left.  With the bound (whose `strategy` pays at most
    T); None when no T was proven in time.  `memo`: a search's memo to start
    the no-human questions from (`NoHumanValue`).  With `rises` (`solvers.rise`'s
    bound R), for σ_Z (`solvers.replan_spare.SpareBound`), whose question is
    cheaper for a looser T: asked at `replan_spare.SPARE_FIRST` times the lower
    end first, then as above (the targets above it only)."""
    oracle = NoHumanValue(scene, formula, resolution, memo)
    first = lower
    if rises is None:
        bound = BudgetedBound(scene, formula, k, resolution, oracle)
    else:
        from symsynth.solvers.replan_spare import SPARE_FIRST, SpareBound

        bound = SpareBound(scene, formula, k, rises, resolution, oracle)
        first = math.floor(SPARE_FIRST * lower)
    no, yes = lower - 1, None
    try:
        with bound.limited(deadline):
            top = MAX_RATIO * max(lower, int(min(bound.v0, 1 << 40)), 1)
            cap = top if ceiling is None else min(ceiling - 1, top)
            for target in _targets(lower, min(first, cap), cap):
                if bound.within(target, deadline):
                    yes = target
                    break
                no = target
            while yes is not None and no + 1 < yes:  # (an interrupted bisection keeps the least yes)
                mid = (no + yes) // 2
                if bound.within(mid, deadline):
                    yes = mid
                else:
                    no = mid
    except Deadline:
        pass
    return None if yes is None else (yes, bound)


def _targets(lower: int, first: int, cap: int) -> Iterator[int]:
    """`first`, then lower + 1 %, 2 %, 4 %, ... of lower above it, up to `cap`
    (`certified_upper`)."""
    if first > cap:
        return
    yield first
    target, step = lower, max(1, math.ceil(lower * FIRST_STEP))
    while target < cap:
        target, step = min(lower + step, cap), 2 * step
        if target > first:
            yield target


def replanned_answer(solution: Solution, scene: Scene, formula: ast.Formula, k: int, budget: float | None,
                     deadline: float, memo: Memo | None = None) -> tuple[Solution, BudgetedBound | None]:
    """An anytime answer whose upper end is the replanning strategy's when that is
    proven (`replan_budget.certified_upper`) below the search's (and E_p when it
    meets the lower end), with σ's bound (None when none was proven).  Its
    principal play is the strategy against a human who makes it pay that much
    when the bisection showed it is what σ pays, else σ's plan with the human
    passing.  `memo`: the search's, whose proven bounds at h = 0 the strategy's
    no-human questions start from.  The strategy is σ_Z (`solvers.replan_spare`)
    when `solvers.rise.rise_bounds` bounds its rises, else, or when σ_Z's bound
    is infinite (S_Z may have no plan where the scene has one), σ; the stats
    say which."""
    lower, r = solution.lower_units, solution.resolution
    assert lower is not None  # the caller answers exact solutions itself
    clock = time.perf_counter()
    spare = rise_bounds(scene, formula, r)
    asked: list[str] = []
    for rises in (None,) if spare is None else (spare, None):
        if asked and time.perf_counter() >= deadline:  # σ_Z used the time: σ would find nothing either
            break
        asked.append("σ" if rises is None else
                     f"σ_Z (spare places {', '.join(rises.spares)}; rise bound R = {rises.total})")
        try:
            found = certified_upper(scene, formula, k, lower, None if solution.units is None else int(solution.units),
                                    resolution=r, deadline=deadline, memo=memo, rises=rises)
        except OutOfReach:  # a zero-cost move
            found = None
        if found is not None:
            break
    stats = dict(solution.stats) | {"replanning_seconds": round(time.perf_counter() - clock, 2),
                                    "replanning_strategy": asked[-1] if found is not None else
                                    " then ".join(asked) + ": no bound proven"}
    if found is None:
        return dataclasses.replace(solution, stats=stats), None
    upper, bound = found
    exact = upper <= lower
    realizable = bracket_verdict(None if exact else lower, upper, r, budget)
    try:  # σ against the worst human, read back from the answers; its plan if that runs long
        with bound.limited(deadline + PLAY_GRACE):
            worst = bound.answered(upper - 1) is False  # upper is what σ pays against the worst human
            principal = bound.worst_play(upper) if worst else bound.passing_play()
    except Deadline:
        principal = bound.passing_play()
    return dataclasses.replace(solution, cost_bound=in_costmap_units(upper, r), units=upper, realizable=realizable,
                               strategy=bound.strategy, principal_play=principal,
                               counter_play=principal if exact and realizable is False else None,
                               stats=stats | {"replanning_bound": upper, "upper_by": "replanning"},
                               lower_units=None if exact else lower), bound
