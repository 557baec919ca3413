"""The compiled AND-OR search (`--solver andor`): the forward solver's
algorithm (`solvers.forward`) with its core in machine code, on the packed
positions of the compiled solver (`solvers.packed`).

From the initial position it asks one question, "is val(p) <= b?", depth
first (`packed.search._ask`): at a robot turn (an OR node) some action of
cost c must have val(after) <= b - c, tried in order of c + lo(after), with
h >= 1 the one proven at h = 0 (σ's) first; at a human turn (an AND node) the pass and every move must have val <= b, the
reply that refuted the last question first, then by lo, largest first.
Each position (state, DFA state, h: the human's moves left) is a node of a
hash table of packed keys with four proven numbers, for its robot and its
human turn:

- `lo`: val >= lo.  Initially `solvers.bound.LowerBound` (its proof is
  there; the tables in `packed.lower`), raised by every "no": at a robot
  turn to min over actions of c + lo(after), at a human turn to the largest
  lo of its replies (Bellman's equations on lower bounds, so still lower
  bounds whatever the order of the search; the human's lo is at least the
  robot's, since the human may pass).
- `hi` with the robot's chosen action: val <= hi, proven by a strategy every
  play of which from there costs at most hi.  Set by a "yes" and only ever
  lowered: at a robot turn c + hi(after) of the action that answered, at a
  human turn the largest hi of its replies (0 for a reply that wins).

The start is asked with b = lo(start), then with the raised lo, until the
answer is yes: then lo = b <= E_p <= hi <= b, so E_p = b.

Why it is exact, and ends
-------------------------
- A "no" at b raises lo above b only when the question was answered: a
  question that stopped (the arrays full, a deadline) changes nothing it
  did not prove, and is asked again.
- Every robot move costs at least one unit (the search stops at the first
  move of 0 units it generates, and the layered solver, `solvers.compiled`,
  answers the game): a robot turn asks questions with
  smaller budgets, a human turn asks its pass with the same budget and its
  moves with fewer moves left, so no question waits on itself, and each
  answered "no" leaves lo > b.
- hi strictly decreases along the chosen actions (each costs >= 1 unit,
  and a human turn's hi is the largest of its replies'), so the strategy of
  the hi entries never goes in circles, and every play of it from a
  position with hi costs at most hi: `upper` of an anytime answer, and the
  strategy returned, are checked by following it through every human reply.
- Infinite values: a position whose bound is inf stays so (no object can
  fill a location); a human who keeps the robot circling is found after
  8, 16, 32, ... rounds by `packed.trap._trap` within what was
  generated (the forward solver's qualitative check), lo := inf there.
  Where the robot can circle cheaply, lo rises by the cycle's cost per
  round (the forward solver lifts such cycles with `_tighten`, not ported
  here): after `MAX_ROUNDS` rounds without an answer, and without a time
  limit, the layered solver answers the game.

Human replies are generated when a human turn is first asked and kept as
node numbers (4 bytes each); a node is one 64-byte record (lo, hi, both
turns, move offsets and counts, key) plus its share of the hash table.

Measured against the layered solver (bench/results/game-notes.md, issue
32): it touches 2.5x fewer positions at pattern 6 x 8 and far fewer in the
rounds below E_p, but the last round, which proves E_p from above, follows
every human reply to a win.  Trying σ's action first at h >= 1 and asking
σ's question before the rest of that round brought pattern 7 x 10 x k = 3's
proof within a minute (docs/benchmarks.md, issue 32).
"""

from __future__ import annotations

import dataclasses
import math
import threading
import time
from collections.abc import Mapping
from decimal import Decimal

import numpy as np

from symsynth.game.abstraction import in_costmap_units, initial_state
from symsynth.game.solution import (OutOfReach, Solution, bracket_verdict, check_parameters, task_formula,
                                    won_at_start)
from symsynth.game.symmetry import Symmetry
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.packed import search as sk
from symsynth.solvers.packed.kernels import INF, _find, _table
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.trap import _trap
from symsynth.solvers.packed.tables import Tables, check_width
from symsynth.solvers.andor_proof import Proof, ProvenStrategy
from symsynth.solvers.hybrid import hybrid_answer
from symsynth.solvers.replan_budget import replanned_answer

#: Questions between two looks at the clock (and at the arrays' room): a question cut
#: off there is asked again from the start, its proven parts kept.  Under a time limit a
#: quarter of it, so that the limit is kept within about 2 s (2 M questions took 9 s at
#: 7 x 10 on the loaded machine)
CHUNK = 2_000_000
#: Rounds after which a search without a time limit gives the game to the layered solver: lo
#: rises by a cycle's cost per round where the robot can circle cheaply (the forward solver
#: lifts such cycles with `_tighten`, not ported); the pattern family needs at most 89 (7 x 10)
MAX_ROUNDS = 1024
#: Shares of a time limit: the search's rounds from below until ROUNDS_SHARE of it has
#: passed, its rounds from above until SEARCH_SHARE; then, when the search proved E_p in
#: neither, the replanning strategy's bound (`solvers.replan_budget`) and the hybrid's
#: (`solvers.hybrid`, HYBRID_SHARE of what σ's leaves) are asked for an upper end, and the
#: rounds from below go on until the limit (`_resumed`) on the memo σ's and the hybrid's
#: no-human searches filled: 7 x 10 x k = 3's proof of 740 from above took 22 s of CPU after
#: σ's "<= 748?" (16 s) against 53 s without (bench/above_proof.py), so σ is asked early;
#: the rounds from above never answered at 7 x 10 and beyond and get no share of their own.
#: 0.4 against 0.65 at load 6 (one run each): 8 x 12 x k = 2 exact against [720, 722],
#: 7 x 10 x k = 3 [740, 748] both (exact at load 3.3-4.4 with 0.65); docs/benchmarks.md
ROUNDS_SHARE = 0.4
SEARCH_SHARE = 0.4
REPLAN_SHARE = 0.6
HYBRID_SHARE = 0.25


class Memo:
    """The search's nodes, moves and scratch; the arrays grow between kernel calls."""

    def __init__(self, tables: Tables, bound: BoundTables, k: int, nodes: int = 1 << 12):
        t = tables
        self.t, self.k = t, k
        self.hb = max(1, (k + 1).bit_length())
        obj_class = np.full(t.n, -1, np.int64)
        obj_pos = np.zeros(t.n, np.int64)
        for c in range(len(t.class_offsets) - 1):
            for r in range(t.class_offsets[c], t.class_offsets[c + 1]):
                obj_class[t.class_members[r]] = c
                obj_pos[t.class_members[r]] = r - t.class_offsets[c]
        i64 = np.int64
        self.P = tuple(i64(v) for v in (t.n, t.m, t.F, t.pb, t.eb, t.gb, t.qbits, self.hb, t.code_bits,
                                         t.grab_units, t.drop_units, t.samples_mask, t.free_all))
        self.G = (t.anchor_at, t.anchor_count, t.home_starts, t.rule_start, t.rule_count, t.rule_free,
                  t.rule_units, t.slide_start, t.slide_count, t.is_grasp, t.atom_at, t.free_at, t.trans,
                  t.accepting, t.class_members, t.class_offsets, t.place_rank, t.rank_place, obj_class, obj_pos)
        self.bound = bound
        self.B = bound.args()
        self.room = 4 * (t.n * (t.F + t.m + 2) + t.m + 2)  # the most moves a node can have
        self.bits = max(12, (4 * nodes).bit_length())
        self.table = _table(i64(self.bits))
        self.rec = np.empty((nodes, 8), np.int64)
        self.rm_tgt = np.empty(nodes * 4, np.int32)
        self.rm_move = np.empty(nodes * 4, np.int32)
        self.hm_tgt = np.empty(nodes * 8, np.int32)
        self.chunk: int | None = None  # questions between two looks at the clock; None: CHUNK
        #: a time past which every question stops where its chunk ends, raising `CutOff`
        #: (set by a caller whose questions take no deadline of their own: `solvers.replan`)
        self.cutoff: float | None = None
        self.st = np.zeros(10, np.int64)
        self.st[sk.ST_HINT] = 1
        self.st[sk.ST_BITS] = self.bits
        self.st[sk.ST_DEPTH] = 256
        self.scratch = [np.empty(t.n, np.int64), np.empty(t.n, np.int64),
                        np.empty(len(t.home_starts) + t.anchor_at.shape[2], np.int64),
                        np.empty(t.anchor_at.shape[2], np.int64), np.empty(t.n, np.int64)] + \
            [np.empty(self.room, np.int64) for _ in range(4)] + [np.empty(t.m + 2, np.int64)]
        self.order = np.empty((256, self.room + 1), np.int64)
        self.frames = np.empty((256, 5), np.int64)

    def tighten(self) -> None:
        """From now on a node's lo is raised to `packed.lower`'s assignment bound
        when it is first expanded (`search._tighten`).  Off in the rounds from
        below, which it slowed (8 x 12 x k = 3: 810 against 814 in 25 s); on
        in the no-human searches of `solvers.replan` (σ's "<= 748?" at 7 x 10 x
        k = 3: 16.5 s against 20.2 s, 45 % fewer search steps;
        bench/results/h0-assignment-bound.md), which turn it on for good on a
        shared memo: the rounds resumed after σ's question (`_resumed`) run
        with it."""
        self.B = self.bound.args(tight=True)

    @property
    def count(self) -> int:
        return int(self.st[sk.ST_COUNT])

    def M(self) -> tuple:
        return (self.table, self.rec, self.rm_tgt, self.rm_move, self.hm_tgt)

    def S(self) -> tuple:
        return (self.st, *self.scratch, self.order, self.frames)

    def key2(self, x: int, q: int, h: int) -> int:
        return (self.t.key(x, q) << self.hb) | h

    def position(self, key2: int) -> tuple[int, int]:
        """(x, q) of a key made by `key2`."""
        return key2 >> (self.hb + self.t.qbits), (key2 >> self.hb) & ((1 << self.t.qbits) - 1)

    def node(self, key2: int) -> int:
        """The node of key2, created when new (the arrays have room: called between questions)."""
        self._grow()
        return int(sk._node(np.int64(key2), self.P, self.B, self.M(), self.S()))

    def find(self, key2: int) -> int | None:
        j = int(_find(self.table, np.int64(self.bits), np.int64(key2)))
        return None if j < 0 else j

    def _grow(self) -> None:
        st, room = self.st, self.room
        count = self.count
        if count + room > len(self.rec):
            self.rec = _grown(self.rec, 2 * (count + room))
        if 2 * (count + room) > len(self.table):
            while 2 * (count + room) > (1 << self.bits):
                self.bits += 1
            self.table = sk._rehash(self.rec, np.int64(count), np.int64(self.bits))
            st[sk.ST_BITS] = self.bits
        for name, used in (("rm_tgt", sk.ST_NE), ("rm_move", sk.ST_NE), ("hm_tgt", sk.ST_NH)):
            a = getattr(self, name)
            if st[used] + room > len(a):
                setattr(self, name, _grown(a, int(st[used] + st[used] // 2 + room)))

    def expand(self, i: int, robot: bool) -> tuple[int, int]:
        """(offset, count) of node i's robot moves (in rm_tgt / rm_move) or human
        moves (in hm_tgt), generated when new."""
        off = sk.R_OFF if robot else sk.H_OFF
        while self.rec[i, off] < 0:
            self._grow()
            self.st[sk.ST_ABORT] = 0
            grow = sk._expand_robot if robot else sk._expand_human
            if not grow(np.int64(i), self.P, self.G, self.B, self.M(), self.S()):
                why = int(self.st[sk.ST_ABORT])
                if why == sk.ABORT_ZERO:
                    raise ZeroCost
                self.recover(why)
        return int(self.rec[i, off]), int(sk._small(self.rec, np.int64(i), np.int64(0 if robot else 16)))

    def ask(self, i: int, b: int, robot: bool, deadline: float | None) -> bool | None:
        """val(i) <= b at its robot or human turn?  None when the deadline
        passed first (what was proven on the way is kept)."""
        st = self.st
        while True:
            st[sk.ST_ABORT] = 0
            chunk = self.chunk or CHUNK
            st[sk.ST_LIMIT] = st[sk.ST_CALLS] + (chunk if deadline is None and self.cutoff is None else chunk // 4)
            ok = sk._ask(np.int64(i), np.int64(b), np.int64(robot), self.P, self.G, self.B, self.M(), self.S())
            why = int(st[sk.ST_ABORT])
            if why == 0:
                return bool(ok)
            if why == sk.ABORT_ZERO:
                raise ZeroCost
            self.recover(why)
            if why == sk.ABORT_CALLS and deadline is not None and time.perf_counter() > deadline:
                return None
            if why == sk.ABORT_CALLS and self.cutoff is not None and time.perf_counter() > self.cutoff:
                raise CutOff

    def recover(self, why: int) -> None:
        """Room for a question that stopped for `why` (st[ST_ABORT]): the arrays
        grown (ABORT_ROOM), the stack deepened (ABORT_DEPTH); nothing else."""
        st = self.st
        if why == sk.ABORT_ROOM:
            self._grow()
        elif why == sk.ABORT_DEPTH:
            depth = 2 * int(st[sk.ST_DEPTH])
            st[sk.ST_DEPTH] = depth
            self.order = np.empty((depth, self.room + 1), np.int64)
            self.frames = np.empty((depth, 5), np.int64)

    def lo_h(self, i: int) -> int:
        return int(max(self.rec[i, sk.LO_H], self.rec[i, sk.LO_R]))

    def hi_h(self, i: int) -> int:
        return int(sk._hi_h(self.rec, np.int64(i), np.int64(self.hb)))

    def trap(self) -> int:
        return int(_trap(np.int64(self.count), self.M(), np.int64(self.hb), np.empty(self.count, np.uint8)))


def _grown(a: np.ndarray, size: int) -> np.ndarray:
    b = np.empty((size, *a.shape[1:]), a.dtype)
    b[:len(a)] = a
    return b


class ZeroCost(Exception):
    """The search met a robot move of 0 units (module doc): the layered solver answers."""


class CutOff(Exception):
    """A question ran past `Memo.cutoff`: what it proved on the way is kept."""


class _TooManyRounds(Exception):
    """`MAX_ROUNDS` rounds without an answer: the layered solver answers."""


def solve_andor(scene: Scene, formula: str | ast.Formula | None = None, *,
                k: int | None = None, budget: float | None = None,
                resolution: float = 1.0, symmetric: bool = True,
                time_limit: float | None = None) -> Solution:
    """E_p, a strategy and plays, as `solve_compiled` computes them (module
    doc).  With `time_limit` (seconds of search), an anytime answer when E_p
    is not proven in time: `Solution.lower_units <= E_p <= units`, with a
    strategy that guarantees `units` (None when none was proven in time).
    Games with a zero-cost robot move, and games the robot loses (for the
    counter play), are answered by the layered solver; with `time_limit`, a
    zero-cost move is `OutOfReach` instead (the layered solver has no
    anytime answer of its own: `auto` goes on to the forward search)."""
    from symsynth.solvers.compiled import solve_compiled

    k = check_parameters(scene, k, resolution)
    took = prepare()
    seconds = {} if took is None else {"compile": took}
    clock = time.perf_counter()
    formula = task_formula(scene, formula)
    tables = Tables(scene, formula, resolution, Symmetry.of(scene, formula) if symmetric else None, k)
    check_width(tables, k)
    seconds["tables"] = time.perf_counter() - clock
    try:
        solution = search_tables(tables, formula, budget, seconds, time_limit)
    except (ZeroCost, _TooManyRounds) as why:
        if time_limit is not None:  # (rounds run out only without a limit)
            raise OutOfReach("a robot move of this game costs 0 units, which the AND-OR search hands to the "
                             "layered solver, and that one has no anytime answer: drop the time limit, or "
                             "use the forward search (--solver forward)") from None
        return _layered(solve_compiled(scene, formula, k=k, budget=budget, resolution=resolution,
                                       symmetric=symmetric), why.__doc__ or "")
    if solution.exact and solution.units is None and time_limit is not None:  # lost, within the limit
        return dataclasses.replace(solution, stats=dict(solution.stats) | {
            "counter_play": "not built: the layered solve that builds it takes no time limit"})
    if solution.exact and solution.units is None:  # lost: the layered solver's counter play
        return _layered(solve_compiled(scene, formula, k=k, budget=budget, resolution=resolution,
                                       symmetric=symmetric), "The robot loses: the layered solver's counter play.")
    return solution


def search_tables(tables: Tables, formula: ast.Formula, budget: float | None, seconds: dict[str, float],
                  time_limit: float | None) -> Solution:
    """The search on `tables` (built for k = `tables.k`), its seconds added to
    `seconds`; with `time_limit` (seconds from now) an anytime answer.  A
    game the robot loses is answered E_p infinite with no counter play;
    raises `ZeroCost` (and, without a limit, `_TooManyRounds`) for the
    layered solver to answer."""
    scene, resolution, k, symmetry = tables.scene, tables.resolution, tables.k, tables.symmetry
    clock = time.perf_counter()
    memo = Memo(tables, BoundTables(tables, formula), k)
    seconds["tables"] = seconds.get("tables", 0.0) + time.perf_counter() - clock
    v0 = initial_state(scene)
    q0 = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v0))
    if tables.accepting[q0]:
        return won_at_start(scene, k, resolution, budget, seconds | {"search": 0.0})
    clock = time.perf_counter()
    start = memo.node(memo.key2(tables.canon(tables.pack(v0)), q0, k))
    begun = clock
    deadline = None if time_limit is None else begun + time_limit * SEARCH_SHARE
    lower, upper, rounds = _search(memo, start, deadline,
                                   None if time_limit is None else begun + time_limit * ROUNDS_SHARE)
    seconds["search"] = time.perf_counter() - clock
    solution = _answer(memo, start, lower, upper, budget, seconds, {"rounds": rounds})
    if time_limit is None or solution.exact or k == 0 or lower is None:
        return solution
    end = begun + time_limit * (SEARCH_SHARE + REPLAN_SHARE)
    solution, bound = replanned_answer(solution, scene, formula, k, budget, end, memo if symmetry is None else None)
    if not solution.exact:
        now = time.perf_counter()
        solution = hybrid_answer(solution, memo, start, formula, now + (end - now) * HYBRID_SHARE, bound)
    if not solution.exact:
        solution = _resumed(solution, memo, start, begun + time_limit)
    if isinstance(solution.strategy, ProvenStrategy):  # σ's searches on the memo may have moved its actions at h = 0
        solution = dataclasses.replace(solution, principal_play=Proof(memo).play(start),
                                       stats=dict(solution.stats) | _sizes(memo))
    return solution


def _answer(memo: Memo, start: int, lower: int | None, upper: int | None, budget: float | Decimal | None,
            seconds: Mapping[str, float], stats: Mapping[str, int | float | None]) -> Solution:
    """What the memo proves at `start`: E_p = upper (None: infinite) when lower
    is None, else lower <= E_p <= upper (None: no strategy proven); the proof's
    strategy and play, realized over the symmetry's classes."""
    t = memo.t
    clock = time.perf_counter()
    proof = Proof(memo)
    strategy: Mapping = ProvenStrategy(proof) if upper is not None else {}
    principal = () if upper is None else proof.play(start)
    exact = lower is None
    realizable = bracket_verdict(lower, upper, t.resolution, budget)
    counter = principal if realizable is False and exact else None
    seconds = {**seconds, "plays": seconds.get("plays", 0.0) + time.perf_counter() - clock}
    stats = {**stats, **_sizes(memo)}
    if not exact:
        stats["lower_units"] = lower
    solution = Solution(None if upper is None else in_costmap_units(upper, t.resolution), upper, t.resolution, budget,
                        realizable, memo.k, 2 * memo.count, seconds, strategy, principal, counter,
                        t.scene.object_names, stats, lower_units=None if exact else lower)
    return solution if t.symmetry is None else t.symmetry.realize(solution)


def _resumed(solution: Solution, memo: Memo, start: int, end: float) -> Solution:
    """`solution` (an anytime answer) with the search's rounds from below
    going on until `end` on the memo as σ's and τ_1's questions left it (the
    h = 0 values they proved answer replies and give the h >= 1 turns their
    first action): exact when a round answers yes, else the lower end raised
    to the last round's (exact when it meets the upper end)."""
    clock = time.perf_counter()
    try:
        lower, upper, _ = _search(memo, start, end, end) if clock < end else (solution.lower_units, None, 0)
    except (ZeroCost, MemoryError) as why:  # the answer in hand stays certified
        return dataclasses.replace(solution, stats=dict(solution.stats) | {
            "resumed": "stopped: " + ("a robot move of 0 units" if isinstance(why, ZeroCost) else "out of memory")})
    stats = dict(solution.stats) | {"resumed_seconds": round(time.perf_counter() - clock, 2)}
    stats.pop("lower_units", None)
    if lower is None:
        return _answer(memo, start, None, upper, solution.budget, solution.seconds, stats | {"upper_by": "search"})
    assert lower is not None and solution.lower_units is not None
    raised = max(lower, solution.lower_units)
    exact = solution.units is not None and raised >= solution.units
    if not exact:
        stats["lower_units"] = raised
    realizable = bracket_verdict(None if exact else raised, solution.units, solution.resolution, solution.budget)
    counter = solution.principal_play if exact and realizable is False else solution.counter_play
    return dataclasses.replace(solution, lower_units=None if exact else raised, stats=stats,
                               realizable=realizable, counter_play=counter)


def _sizes(memo: Memo) -> dict[str, int | float]:
    """The memo's nodes, questions, moves and arrays (MB), for a solution's stats."""
    st = memo.st
    return {"nodes": memo.count, "calls": int(st[sk.ST_CALLS]), "robot_moves": int(st[sk.ST_NE]),
            "human_moves": int(st[sk.ST_NH]),
            "peak_nodes_mb": round((memo.rec.nbytes + memo.table.nbytes + memo.rm_tgt.nbytes
                                    + memo.rm_move.nbytes + memo.hm_tgt.nbytes) / 1e6, 1)}


def _layered(solution: Solution, why: str) -> Solution:
    """The layered solver's solution, its stats saying why it answered."""
    return dataclasses.replace(solution, stats={**solution.stats, "answered_by": "compiled", "why": why})


def _search(memo: Memo, start: int, deadline: float | None,
            rounds_until: float | None = None) -> tuple[int | None, int | None, int]:
    """(lower, upper, rounds): lower None when E_p = upper is proven (upper
    None: infinite); else lower <= E_p <= upper (upper None: no strategy
    proven in time).  The rounds from below go on until `rounds_until` (by
    default half the time); then "val <= b?" for b 5%, 10%, 20%, ... above
    lo, as `forward._anytime`."""
    rounds = 0
    half = rounds_until
    if deadline is not None and half is None:
        half = time.perf_counter() + (deadline - time.perf_counter()) / 2
    while True:
        b = memo.lo_h(start)
        if b >= INF:
            return None, None, rounds
        rounds += 1
        ok = memo.ask(start, b, False, half)
        if ok is None:
            break
        if ok:
            return None, b, rounds
        if memo.lo_h(start) <= b:
            memo.rec[start, sk.LO_H] = b + 1
        if rounds >= 8 and rounds & (rounds - 1) == 0:  # 8, 16, 32, ...: a trap the human closes?
            memo.trap()
        if deadline is None and rounds >= MAX_ROUNDS:
            raise _TooManyRounds
        if half is not None and time.perf_counter() > half:
            break
    assert deadline is not None  # the rounds above end otherwise
    slack = 0.05
    while memo.hi_h(start) >= INF and memo.lo_h(start) < INF and time.perf_counter() <= deadline:
        b = min(math.ceil(memo.lo_h(start) * (1 + slack)), 1 << 40)  # (the kernel shifts b by 16 bits)
        slack *= 2
        memo.trap()
        ok = memo.ask(start, b, False, deadline)
        if ok is None:
            break
        if not ok and memo.lo_h(start) <= b:
            memo.rec[start, sk.LO_H] = b + 1
    lo, hi = memo.lo_h(start), memo.hi_h(start)
    if lo >= INF:
        return None, None, rounds
    if hi <= lo:
        return None, hi, rounds
    return lo, (None if hi >= INF else hi), rounds


_warm = threading.RLock()  # prepare solves a game, which calls prepare
_prepared = False


def prepare() -> float | None:
    """Compile the layered solver's kernels and this search's (or load them
    from numba's cache) by solving a small game; the seconds it took, None
    when done already in this process."""
    global _prepared
    with _warm:
        if _prepared:
            return None
        from symsynth.solvers.compiled import compile_kernels

        clock = time.perf_counter()
        compile_kernels()
        _prepared = True
        try:
            if solve_andor(_warm_up_scene()).units is None:
                raise RuntimeError("internal error: the AND-OR search's warm-up game was not won")
            memo_trap_warm_up()
            replan_warm_up()
        except BaseException:
            _prepared = False
            raise
        return time.perf_counter() - clock


def _warm_up_scene() -> Scene:
    """Two distinct blocks to put on l2 and l3 against one human move (two
    Else samples, so no move costs 0): the bound is on, the human moves, the
    robot wins."""
    from symsynth.scene.load import scene_from_data

    places, grasp = ["l1", "l2", "l3", "e1", "e2"], "top"
    anchors = ["home"] + [f"{x}/{grasp}" for x in places]
    motions = [{"mode": "empty", "from": s, "to": t, "rules": [{"free": [], "cost": 2}]}
               for s in anchors for t in anchors[1:] if s != t]
    motions += [{"mode": f"{o}/{grasp}", "from": s, "to": t, "rules": [{"free": [], "cost": 3}]}
                for o in ("a", "b") for s in anchors[1:] for t in anchors[1:4] if s != t]
    return scene_from_data({
        "name": "andor-warm-up",
        "objects": {"a": {"tags": ["block", "red"], "at": "l1"}, "b": {"tags": ["block", "blue"], "at": "Else"}},
        "locations": places[:3], "else_samples": places[3:], "grasps": [grasp],
        "primitives": {"grab": 1, "drop": 1}, "human": {"k": 1},
        "task": "F(at(red, l2) & at(blue, l3))",
        "costmap": {"format": "symsynth.costmap/1", "motions": motions}})


def memo_trap_warm_up() -> None:
    """Compile the trap check (only games with a trap reach it) and the
    table's rehash (only large games reach it), so that numba's cache holds
    every kernel of the search (`compiled.kernels_cached` checks them all)."""
    scene = _warm_up_scene()
    formula = task_formula(scene, None)
    tables = Tables(scene, formula, 1.0, None, 1)
    memo = Memo(tables, BoundTables(tables, formula), 1)
    memo.node(memo.key2(tables.pack(initial_state(scene)), 0, 1))
    memo.trap()
    sk._rehash(memo.rec, np.int64(memo.count), np.int64(memo.bits))


def replan_warm_up() -> None:
    """Compile the replanning bound's kernels (`packed.replies`, asked by an anytime
    answer's upper end) on the warm-up game, so that no time limit pays for them."""
    from symsynth.solvers.replan_budget import BudgetedBound

    scene = _warm_up_scene()
    bound = BudgetedBound(scene, task_formula(scene, None), 1)
    if not bound.within(int(bound.v0) + 1000):
        raise RuntimeError("internal error: the replanning bound of the AND-OR search's warm-up game was not proven")


solve_andor.prepare = prepare  # type: ignore[attr-defined]  # symsynth.solvers.prepare
