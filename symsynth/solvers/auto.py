"""`--solver auto`: one of the built-in solvers, chosen by the task's shape,
the scene and the time limit, with the reason printed.

The rule follows side-by-side measurements on this project's game families
(docs/solving.md, bench/results/game.md and game-sort.md), not a guess:

1. a time limit: the forward search, the only solver that answers anytime
   (a proven interval and a strategy for its upper end);
2. a task of the form F(conjunction of atoms), which the forward solver's
   lower bound guides: the forward search.  On the pattern family it was
   the fastest at every size (1.7x the explicit solver at 5 x 7, the only
   one to finish 6 x 8), and on the sorting family it ties with the
   explicit solver, both on canonical positions, 8x faster than the
   symbolic one at 6 x 8;
3. any other task (the bound is 0 there, and the forward search is then
   slower than the explicit one, e.g. on the bundled arch): the symbolic
   solver, whose BDDs represent sets of positions at once (0.35 s on the
   arch against 0.48 s for the explicit one on canonical positions).
"""

from __future__ import annotations

import dataclasses

from symsynth.game.graph import GameGraph
from symsynth.game.solution import Solution, check_parameters, task_formula
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.bound import LowerBound


def choose(scene: Scene, formula: ast.Formula, time_limit: float | None = None) -> tuple[str, str]:
    """(solver name, the reason in a sentence)."""
    if time_limit is not None:
        return "forward", "a time limit: the forward search is the solver that answers anytime"
    if LowerBound(GameGraph(scene, formula, 1.0), formula).enabled:
        return "forward", ("the task is F(conjunction of atoms), which the forward search's lower "
                           "bound guides (fastest on the pattern and sorting families)")
    return "symbolic", ("the forward search's lower bound does not guide this task; the symbolic "
                        "solver's BDDs handle sets of positions at once")


def solve_auto(scene: Scene, formula: str | ast.Formula | None = None, *, k: int | None = None,
               budget: float | None = None, resolution: float = 1.0,
               time_limit: float | None = None) -> Solution:
    """The chosen solver's solution (`choose`), with `stats["auto"]` naming
    it and `stats["auto_reason"]` saying why."""
    from symsynth.solvers import SOLVERS  # the registry, which lists this module too

    check_parameters(scene, k, resolution)
    formula = task_formula(scene, formula)
    name, reason = choose(scene, formula, time_limit)
    options = {} if time_limit is None else {"time_limit": time_limit}
    solution = SOLVERS[name](scene, formula, k=k, budget=budget, resolution=resolution, **options)
    return dataclasses.replace(solution, stats=dict(solution.stats) | {"auto": name, "auto_reason": reason})
