"""The forward solver: semantics §6's value by a bounded AND-OR search from the
initial position, guided by an admissible lower bound.

Only positions that play near the optimum reaches are looked at.  The
search answers one question, "is val(p) <= b?", depth first, with a memo of
what is proven about each position:

- `lo(p)`: val(p) >= lo(p).  Initially the lower bound L(p) (`bound.LowerBound`);
  raised by every failed question: at a robot position to
  min over actions of c + lo(after), at a human position to the largest lo
  of its replies.  These are Bellman's equations applied to lower bounds, so
  lo stays a lower bound whatever the order of the search.
- `hi(p)` with the robot's action: val(p) <= hi(p), proven by a strategy
  whose every play from p costs at most hi(p).  Set when a question is
  answered yes, and only ever lowered.

"val(p) <= b?" at a robot position: no if lo(p) > b; else try the actions in
order of c + lo(after) while that is <= b, asking "val(after) <= b - c?".  At
a human position: the pass and every move must all be within b; replies are
tried largest lo first, so a failure shows early.

The initial position is asked with b = lo, then with the raised lo, until
the answer is yes: then lo = hi = E_p.  A question raises lo around a cycle
of cheap actions by the cycle's cost only, so between rounds the lower
bounds of everything generated are also raised to the least solution of
Bellman's equations there (`_tighten`), which lifts such a cycle at once.  With the bound off (0, for a task
it does not understand) that is many rounds: on the bundled arch the
forward solver is slower than the explicit one (README, game benchmark).

Why it is exact
---------------
- lo is a lower bound (above), so a "no" never hides a strategy.  A yes
  builds a strategy from the hi entries: at p, the action recorded, whose
  replies all have hi <= hi(p) - c.  So E_p = the first b that gets a yes.
- When every action of a robot position costs >= 1 unit, its questions go
  to smaller budgets, so the recursion cannot come back to a question being
  asked, and every "no" raises lo above b: the memo answers it next time.
- Zero-cost actions can lead back to a position with the same budget.  At
  such a position the question is answered for its whole *closure* at once
  (`_closure`): the robot positions reachable by zero-cost actions and
  passes form a small reachability game at budget b, solved as a least
  fixpoint; its exits (actions that cost, human moves) ask questions with
  a smaller budget or fewer human moves, which never come back.  What the
  fixpoint leaves out has val > b.
- A hi entry is replaced only by a strictly smaller one, so following the
  entries never goes in circles (an entry's replies were proven before it
  with hi no larger, and equal hi means an entry never changed since); in a
  closure, positions are proven in fixpoint order.
- Infinite values: a position with no action has lo = inf, and so does one
  whose bound is inf (a location no object can fill).  A human who keeps
  the robot circling is caught by a qualitative check after 8, 16, 32, ...
  rounds of one question (`_qualitative`): a trap the human can close,
  within the positions the search generated; the trap grows with the
  budget until it is whole.

The strategy (`Strategy`) is lazy: an entry whose hi equals its lo is
optimal; at any other position the value is searched when it is looked up.

The lower bound is `bound.LowerBound`.
"""

from __future__ import annotations

import math
import sys
import threading
import time
from collections.abc import Iterator, Mapping

from tqdm import tqdm

from symsynth.game.abstraction import in_costmap_units, initial_state
from symsynth.solvers.bound import LowerBound
from symsynth.solvers import forward_search
from symsynth.solvers.forward_search import INF, Key, OutOfTime, Search
from symsynth.game.graph import GameGraph
from symsynth.game.strategy import guaranteed_units
from symsynth.game.solution import (OutOfReach, Position, Solution, bracket_verdict, check_parameters, task_formula,
                                   verdict, won_at_start)
from symsynth.logic import ast
from symsynth.scene.model import Scene


def solve_forward(scene: Scene, formula: str | ast.Formula | None = None, *,
                  k: int | None = None, budget: float | None = None,
                  resolution: float = 1.0, symmetric: bool = True,
                  time_limit: float | None = None) -> Solution:
    """E_p, a strategy and plays for `formula` (default: the scene's task)
    against a human with `k` moves (default: the scene's k); with
    `symmetric`, on canonical positions (`game.symmetry`).

    With `time_limit` (seconds of search), an anytime answer when E_p is not
    proven in time (`_anytime`): `Solution.lower_units` and a strategy that
    guarantees `units`."""
    k = check_parameters(scene, k, resolution)
    clock = time.perf_counter()
    formula = task_formula(scene, formula)
    game = GameGraph(scene, formula, resolution, symmetric=symmetric)
    seconds = {"dfa": time.perf_counter() - clock}
    v0 = game.canon(initial_state(scene))
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):  # ρ(v0) alone is accepted
        return won_at_start(scene, k, resolution, budget,
                            seconds | {"bound": 0.0, "search": 0.0, "plays": 0.0})
    clock = time.perf_counter()
    bound = LowerBound(game, formula)
    seconds["bound"] = time.perf_counter() - clock

    clock = time.perf_counter()
    start = (v0, q0, k)
    search = Search(game, bound)
    lower, units = _searched(search, start, time_limit)
    seconds["search"] = time.perf_counter() - clock
    stats = search.stats()
    if lower is not None:
        return _bracketed(game, formula, search, start, lower, units, k, budget, seconds, stats)

    clock = time.perf_counter()
    realizable = verdict(units, resolution, budget)
    if units is None:
        strategy: Mapping = {}
        principal, counter = (), _deep(search.counter_play, start)
    else:
        strategy = Strategy(search)
        principal = _deep(search.principal_play, start, units)
        counter = principal if realizable is False else None
    seconds["plays"] = time.perf_counter() - clock
    solution = Solution(None if units is None else in_costmap_units(units, resolution), units, resolution, budget,
                        realizable, k, search.positions(), seconds, strategy, principal, counter,
                        scene.object_names, stats)
    return solution if game.symmetry is None else game.symmetry.realize(solution)


def _searched(search: Search, start: Key, time_limit: float | None) -> tuple[int | None, int | None]:
    """(None, E_p in units), or with `time_limit` `_anytime`'s (lower,
    upper) when E_p was not proven in time; a bar of the rounds (each asks
    "E_p <= b?" with b one more) on a terminal once it takes over a second."""
    with tqdm(desc="forward search", unit=" rounds", delay=1.0, leave=False, disable=None) as bar:
        def on_round(b: int) -> None:
            bar.update()
            bar.set_postfix_str(f"E_p >= {b}", refresh=False)

        search.on_round = on_round
        try:
            if time_limit is None:
                return None, _deep(search.value_human, start)
            return _anytime(search, start, forward_search.deadline_clock() + time_limit)
        finally:
            search.on_round = None


# -- anytime answers --------------------------------------------------------------------

def _anytime(search: Search, start: Key, deadline: float) -> tuple[int | None, int | None]:
    """(lower, upper) units for the start, None for lower when E_p is exact
    (then upper is E_p, None when infinite).

    Half of the time goes to the exact search from below (`_value`); if it
    is not done, the rest asks "val <= b?" for b = 5%, 10%, 20%, ... above
    lo (a generous b lets the depth-first search wander far): a yes
    builds a strategy of at most b (its proven hi is the upper bound), a no
    proves val > b and raises lo.  An interrupted question leaves the memo
    sound: lo is raised and hi set only by questions that finished."""
    now = forward_search.deadline_clock()
    search.deadline = now + (deadline - now) / 2
    i = search.id(start)
    try:
        return None, _deep(search.value_human, start)
    except OutOfTime:
        pass
    finally:
        search.deadline = None
    search.deadline = deadline
    if search.lo_h[i] == INF:
        return None, None
    slack = 0.05
    try:
        while i not in search.hi_h and search.lo_h[i] != INF:
            b = math.ceil(search.lo_h[i] * (1 + slack))
            slack *= 2
            if not _deep(search.human, i, b) and search.lo_h[i] <= b:
                search.lo_h[i] = b + 1  # the search was a proof: val > b
    except OutOfTime:
        pass
    finally:
        search.deadline = None
    lo, hi = search.lo_h[i], search.hi_h.get(i)
    if lo == INF:
        return None, None
    if hi is not None and hi <= lo:
        return None, hi
    return int(lo), hi


def _bracketed(game: GameGraph, formula: ast.Formula, search: Search, start: Key, lower: int,
               upper: int | None, k: int, budget: float | None, seconds: dict[str, float],
               stats: dict[str, object]) -> Solution:
    """The anytime solution: `lower <= E_p <= upper`, the strategy of the
    proven entries, checked against every human reply before it is returned."""
    scene, r = game.scene, game.resolution
    strategy: Mapping = ProvenStrategy(search) if upper is not None else {}
    realizable = bracket_verdict(lower, upper, r, budget)
    principal = () if upper is None else search.proven_play(start)
    solution = Solution(None if upper is None else in_costmap_units(upper, r), upper, r, budget, realizable, k,
                        search.positions(), seconds, strategy, principal, None,
                        scene.object_names, stats | {"lower_units": lower}, lower_units=lower)
    if game.symmetry is not None:
        solution = game.symmetry.realize(solution)
    if upper is not None:
        clock = time.perf_counter()
        checked = guaranteed_units(scene, formula, solution)
        if checked is None or checked > upper:
            raise RuntimeError(f"internal error: the anytime strategy spends {checked} units "
                               f"against some human, more than its proven {upper}")
        seconds["check"] = time.perf_counter() - clock
    return solution


class ProvenStrategy(Mapping):
    """The actions of the proven entries (hi): a strategy whose every play
    from a position with an entry costs at most that entry's hi, followed
    without further search.  Not optimal where hi > val."""

    def __init__(self, search: Search):
        self._search = search

    def __getitem__(self, position: Position) -> str:
        i = self._search.ids.get(position)
        if i is None or i not in self._search.hi_r:
            raise KeyError(position)
        return self._search.hi_r[i][1]

    def __iter__(self) -> Iterator[Position]:
        keys = self._search.keys
        return iter([keys[i] for i in self._search.hi_r])

    def __len__(self) -> int:
        return len(self._search.hi_r)



def _deep(function, *args):
    """`function(*args)` in a thread with a large stack and recursion limit:
    the search recurses once per action along a play, and a play within a
    large budget of small units can be long."""
    out: list = []

    def run():
        try:
            out.append((True, function(*args)))
        except BaseException as error:  # noqa: BLE001 - re-raised in the caller
            out.append((False, error))

    limit = sys.getrecursionlimit()
    size = threading.stack_size()
    sys.setrecursionlimit(max(limit, DEPTH))
    threading.stack_size(STACK)
    try:
        # a daemon: after Ctrl-C or SIGTERM in the caller (raised in join),
        # the program ends without waiting for the search to finish
        worker = threading.Thread(target=run, name="symsynth-forward", daemon=True)
        worker.start()
        worker.join()
    finally:
        threading.stack_size(size)
        sys.setrecursionlimit(limit)
    ok, value = out[0]
    if isinstance(value, RecursionError):
        # The search recurses once per move of a play within the budget: a
        # budget of many cheapest moves (E_p over the cheapest move's units
        # beyond DEPTH) is more than its stack holds.
        raise OutOfReach(f"the forward search recursed deeper than its {DEPTH:,} frames: plays within "
                         "the budget can be that many moves long (E_p is that many times the cheapest "
                         "move, in units of --resolution); use --solver explicit or symbolic, or a "
                         "coarser --resolution") from None
    if not ok:
        raise value
    return value


DEPTH = 200_000  # Python frames
STACK = 1 << 29  # bytes of C stack for the searching thread


class Strategy(Mapping):
    """The robot's action at robot-turn positions (v, q, h), optimal there:
    the search's entry when its hi meets lo (then it is val), else val is
    searched now (from lo up) and its action kept.  KeyError where the
    value is infinite.  Iterating lists the positions with an entry."""

    def __init__(self, search: Search):
        self._search = search

    def __getitem__(self, position: Position) -> str:
        search = self._search
        i = search.ids.get(position)
        entry = None if i is None else search.hi_r.get(i)
        if i is None or entry is None or entry[0] > search.lo_r[i]:  # not known to be optimal
            if _deep(search.value_robot, position) is None:
                raise KeyError(position)
            entry = search.hi_r[search.ids[position]]
        return entry[1]

    def __iter__(self) -> Iterator[Position]:
        keys = self._search.keys
        return iter([keys[i] for i in self._search.hi_r])

    def __len__(self) -> int:
        return len(self._search.hi_r)
