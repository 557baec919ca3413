"""`--solver auto` (the default): one of the built-in solvers, chosen by the
time limit, the game's size and the task's shape, with the reason printed.

The rule follows side-by-side measurements on this project's game families
(docs/solving.md, bench/results/game.md and game-sort.md), not a guess:

1. a time limit: the forward search, the only solver that answers anytime
   (a proven interval and a strategy for its upper end);
2. a game the compiled solver can hold (at most 16 task atoms, a position
   in 62 bits): the compiled solver, the fastest wherever it fits (side by
   side on a quiet machine, pattern family 5 x 7: 0.43 s against 27.6 s for
   the forward search and 50 s for the symbolic one; sorting family 7 x 10:
   2.6 s against 191 s for the symbolic one and 327 s for the explicit one;
   the arch: 0.02 s of search);
3. otherwise a task of the form F(conjunction of atoms), which the forward
   solver's lower bound guides: the forward search;
4. any other task (the bound is 0 there, and the forward search slows
   down): the symbolic solver, whose BDDs represent sets of positions at
   once.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection

from symsynth.game.graph import GameGraph
from symsynth.game.solution import OutOfReach, Solution, check_parameters, task_formula
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.bound import LowerBound

COMPILED = ("the game fits the compiled solver (at most 16 task atoms, a position in 62 bits), "
            "the fastest measured wherever it fits")


def choose(scene: Scene, formula: ast.Formula, time_limit: float | None = None,
           refused: Collection[str] = ()) -> tuple[str, str]:
    """(solver name, the reason in a sentence), skipping the solvers in
    `refused` (each said the game is out of its reach, `OutOfReach`)."""
    if time_limit is not None and "forward" not in refused:
        return "forward", "a time limit: the forward search is the solver that answers anytime"
    if "compiled" not in refused:
        return "compiled", COMPILED
    if "forward" not in refused and LowerBound(GameGraph(scene, formula, 1.0), formula).enabled:
        return "forward", ("the task is F(conjunction of atoms), which the forward search's lower "
                           "bound guides, and the game is too large for the compiled solver")
    if "symbolic" not in refused:
        return "symbolic", ("the forward search's lower bound does not guide this task and the game is "
                            "too large for the compiled solver; the symbolic solver's BDDs handle sets "
                            "of positions at once")
    return "explicit", "every other solver refused the game"


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
        name, reason = choose(scene, formula, time_limit, refused)
        options = {} if time_limit is None or name != "forward" else {"time_limit": time_limit}
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
