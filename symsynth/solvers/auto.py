"""`--solver auto` (the default): one of the built-in solvers, chosen by the
time limit, the game's size and the task's shape, with the reason printed.

The rule follows side-by-side measurements on this project's game families
(docs/solving.md, bench/results/game.md and game-sort.md), not a guess:

1. a time limit: the exact solver of rule 2 when it is expected to take at
   most half the limit (from `position_bound`, compile included), else,
   where the compiled solver can hold the game and its kernels (the AND-OR
   search's too) are compiled, or their cold compile takes at most half
   the limit, the compiled solver with the limit: its layered solve when
   that is predicted to end in time (`packed.deadline`), else the AND-OR
   search (`andor`, the forward search's algorithm on the same tables) in
   the time left, which answers anytime (a proven interval and a strategy
   for its upper end; pattern family 6 x 8 x k = 3 with 60 s: `andor`
   exact, 649, in 19.9 s; `forward` [641, no upper end] at the limit;
   bench/results/game-anytime.md); else the forward search.  The compiled
   solver is given the limit in every case;
2. a game the compiled solver can hold (at most 16 task atoms, a position
   in 62 bits): the compiled solver, the fastest wherever it fits (side by
   side on a quiet machine, pattern family 5 x 7: 0.43 s against 27.6 s for
   the forward search and 50 s for the symbolic one; sorting family 7 x 10:
   2.6 s against 191 s for the symbolic one and 327 s for the explicit one;
   the arch: 0.02 s of search) -- once its kernels are compiled.  When
   numba's cache does not hold them (`compiled.kernels_cached`: a fresh
   install, a new numba), the solve would first compile them, about 20 s
   quiet and up to 55 s on a loaded machine: a game whose positions the
   explicit solver gets through in less than that (`explicit_seconds`, from
   an upper bound on the positions) goes to the explicit solver instead;
3. otherwise a task of the form F(conjunction of atoms), which the forward
   solver's lower bound guides: the forward search;
4. any other task (the bound is 0 there, and the forward search slows
   down): the symbolic solver, whose BDDs represent sets of positions at
   once.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Collection

from symsynth.game.graph import GameGraph
from symsynth.game.solution import OutOfReach, Solution, check_parameters, task_formula
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.automata.shared import dfa_of
from symsynth.solvers.bound import LowerBound

COMPILED = ("the game fits the compiled solver (at most 16 task atoms, a position in 62 bits), "
            "the fastest measured wherever it fits")
#: Seconds a fresh install spends compiling the compiled solver's kernels (18.7 s measured
#: alone on the project's 2-core machine, 20-55 s while others worked on it)
COLD_COMPILE_SECONDS = 20.0
#: The explicit solver's seconds per position of `position_bound`, kept on the slow side:
#: measured 1.0e-5 quiet, 2.4e-5 loaded on the pattern family 4 x 6 (bound 286,512), 0.5e-5
#: loaded on scenes/arch-abstract.yaml (164,880)
EXPLICIT_SECONDS_PER_POSITION = 3e-5
#: The compiled solver's, 5-15x what was measured alone on the machine (pattern family 5 x 7:
#: 1.4e-7, 6 x 8: 2.0e-7, 7 x 10: 4.3e-7, its memory beyond the caches), so that a time limit
#: is kept on a loaded machine too
COMPILED_SECONDS_PER_POSITION = 2e-6


def choose(scene: Scene, formula: ast.Formula, time_limit: float | None = None,
           refused: Collection[str] = (), *, k: int | None = None,
           compiled_ready: bool | None = None) -> tuple[str, str]:
    """(solver name, the reason in a sentence), skipping the solvers in
    `refused` (each said the game is out of its reach, `OutOfReach`);
    `compiled_ready` says whether the compiled solver's kernels are
    compiled (None: ask numba's cache, `compiled.kernels_cached`)."""
    k = scene.k if k is None else k
    exact = _exact(scene, formula, k, refused, compiled_ready, andor=time_limit is not None)
    if time_limit is not None:
        if exact is not None and exact[2] <= time_limit / 2:
            return exact[0], (f"a time limit of {time_limit:g} s, well above what the exact solve is expected "
                              f"to take: {exact[1]}")
        ready = exact is not None and _kernels_ready(compiled_ready, andor=True)
        if exact is not None and (ready or COLD_COMPILE_SECONDS <= time_limit / 2):
            return "compiled", ("a time limit, and the game fits the compiled solver's tables: its layered solve "
                                "when that is predicted to end in time (exact), else the AND-OR search on the same "
                                "tables in the time left, which answers anytime, faster than the forward search "
                                "(measured on the pattern family)"
                                + ("" if ready else f"; its kernels are compiled first (about "
                                   f"{COLD_COMPILE_SECONDS:.0f} s, once per install)"))
        if "forward" not in refused:
            return "forward", "a time limit: the forward search is the solver that answers anytime"
    if exact is not None:
        return exact[0], exact[1]
    if "forward" not in refused and LowerBound(GameGraph(scene, formula, 1.0), formula).enabled:
        return "forward", ("the task is F(conjunction of atoms), which the forward search's lower "
                           "bound guides, and the game is too large for the compiled solver")
    if "symbolic" not in refused:
        return "symbolic", ("the forward search's lower bound does not guide this task and the game is "
                            "too large for the compiled solver; the symbolic solver's BDDs handle sets "
                            "of positions at once")
    return "explicit", "every other solver refused the game"


def _exact(scene: Scene, formula: ast.Formula, k: int, refused: Collection[str],
           compiled_ready: bool | None, andor: bool = False) -> tuple[str, str, float] | None:
    """The compiled solver, or the explicit one when the compiled kernels
    would be compiled first for longer than the explicit solver takes:
    (name, reason, expected seconds, compile included); None when the
    compiled solver refused the game.  With `andor` (a time limit, which
    may hand the game to the AND-OR search), its kernels count too."""
    if "compiled" in refused:
        return None
    compiled_ready = _kernels_ready(compiled_ready, andor)
    positions = position_bound(scene, formula, k)
    fast = positions * COMPILED_SECONDS_PER_POSITION
    if compiled_ready:
        return "compiled", COMPILED, fast
    slow = explicit_seconds(positions)
    if slow < COLD_COMPILE_SECONDS + fast and "explicit" not in refused:
        return "explicit", (f"the compiled solver's kernels are not compiled yet (about {COLD_COMPILE_SECONDS:.0f} s, "
                            f"once per install) and the game is small: at most {positions:,} positions, "
                            f"about {slow:.1g} s for the explicit solver"), slow
    return "compiled", (f"{COMPILED}; its kernels are compiled first (about {COLD_COMPILE_SECONDS:.0f} s, "
                        f"once per install), less than the explicit solver would take on up to "
                        f"{positions:,} positions (about {slow:.0f} s)"), COLD_COMPILE_SECONDS + fast


def _kernels_ready(compiled_ready: bool | None, andor: bool = False) -> bool:
    """`compiled_ready`, or numba's cache asked when it is None (with
    `andor`, for the AND-OR search's kernels too)."""
    if compiled_ready is None:
        from symsynth.solvers.compiled import kernels_cached  # imports numba: only when asked
        return kernels_cached(andor)
    return compiled_ready


def position_bound(scene: Scene, formula: ast.Formula, k: int) -> int:
    """An upper bound on the positions the explicit solver can meet: abstract
    states (objects on distinct locations or at Else, at most one in the
    hand; the end-effector at Else, a location or an object's frame when
    the hand is empty, over Else or a location with a grasp when it holds
    one), times the task DFA's states, the human's moves left (0..k) and
    whose turn it is."""
    n, m = len(scene.object_names), len(scene.locations)
    frames, grasps = len(scene.preimages), len(scene.grasps)

    def placements(count: int) -> int:  # objects on distinct locations or at Else
        return sum(math.comb(count, j) * math.perm(m, j) for j in range(min(count, m) + 1))

    states = placements(n) * (1 + m + n * frames) + n * placements(n - 1) * grasps * (m + 1)
    return states * dfa_of(formula).num_states * (k + 1) * 2


def explicit_seconds(positions: int) -> float:
    """The explicit solver's expected seconds for a game of at most `positions`."""
    return positions * EXPLICIT_SECONDS_PER_POSITION


def solve_auto(scene: Scene, formula: str | ast.Formula | None = None, *, k: int | None = None,
               budget: float | None = None, resolution: float = 1.0,
               time_limit: float | None = None) -> Solution:
    """The chosen solver's solution (`choose`), with `stats["auto"]` naming
    it and `stats["auto_reason"]` saying why; a solver that finds the game
    out of its reach hands it to the next choice, and the reason says so."""
    from symsynth.solvers import SOLVERS  # the registry, which lists this module too

    check_parameters(scene, k, resolution)
    formula = task_formula(scene, formula)
    refused: dict[str, str] = {}
    while True:
        name, reason = choose(scene, formula, time_limit, refused, k=k)
        options = {} if time_limit is None or name not in ("forward", "andor", "compiled") else {"time_limit": time_limit}
        try:
            solution = SOLVERS[name](scene, formula, k=k, budget=budget, resolution=resolution, **options)
        except OutOfReach as error:
            if name == "explicit":
                raise
            refused[name] = str(error)
            continue
        break
    reason += "".join(f" ({other} refused it: {why})" for other, why in refused.items())
    return dataclasses.replace(solution, stats=dict(solution.stats) | {"auto": name, "auto_reason": reason})


def _prepare() -> None:
    """The compiled solver's set-up, `auto`'s usual choice."""
    from symsynth.solvers import prepare

    prepare("compiled")


solve_auto.prepare = _prepare  # type: ignore[attr-defined]  # symsynth.solvers.prepare
