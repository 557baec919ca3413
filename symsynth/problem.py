"""The application layer: one manipulation problem composed once, for the
command line and for comparison runs alike.

A `Problem` is a scene with its costmap (given with the scene, or obtained
from the cache or a planner), its task parsed once and checked against
the scene, and where the costmap came from.  `solve(problem, ...)` solves
its game with a registered solver over the horizon `k` can use
(`game.horizon`).  Below it, every layer takes what it needs as values:
the solvers a scene and a formula, the planners a physical scene.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from dataclasses import dataclass
from pathlib import Path

from symsynth.errors import InputError
from symsynth.game.horizon import solve_game
from symsynth.scene.propositions import interpret_all
from symsynth.game.solution import Solution, task_formula
from symsynth.logic import ast, parse_ltlf
from symsynth.planning.build import Obtained, obtain_costmap
from symsynth.scene import Scene, load_scene
from symsynth.solvers import DEFAULT_SOLVER, SOLVERS


@dataclass(frozen=True)
class Problem:
    """A scene (with its costmap), its task as written and parsed, and how
    the costmap was obtained (None: it came with the scene)."""

    scene: Scene
    task: str
    formula: ast.Formula
    obtained: Obtained | None = None


@dataclass(frozen=True)
class CostmapRequest:
    """How to obtain a physical scene's costmap (`symsynth costmap`'s
    options): method, planner (None: the scene's), seed (None: the
    scene's), whether the cache is used, whether progress is shown."""

    method: str = "recursive"
    planner: str | None = None
    seed: int | None = None
    use_cache: bool = True
    progress: bool = True


def load_problem(path: str | Path, *, task: str | None = None, task_source: str = "--task",
                 costmap: str | Path | None = None, k: int | None = None,
                 request: CostmapRequest | None = None) -> Problem:
    """The problem of a scene file: `costmap` (a file) instead of the
    scene's; `task` instead of the scene's (checked against the scene,
    errors named after `task_source`); `k` instead of the scene's; a
    physical scene's costmap obtained as `request` says."""
    scene = load_scene(path, costmap=costmap)
    if k is not None:
        scene = dataclasses.replace(scene, k=k)
    return with_costmap(with_task(scene, task, task_source, path), request or CostmapRequest())


def with_task(scene: Scene, task: str | None, task_source: str = "--task", path: str | Path | None = None) -> Problem:
    """`scene` with `task` (else its own, which its loader checked) parsed."""
    if task is not None:
        formula = parse_ltlf(task, source=task_source)
        try:
            interpret_all(formula, scene)
        except InputError as error:
            raise InputError(f"{task_source}: {error}") from None
        return Problem(scene, task, formula)
    if scene.task is None:
        raise InputError(f"scene {scene.name!r} has no task: give --task FORMULA or a 'task:' entry"
                         + (f" in {path}" if path is not None else ""))
    return Problem(scene, scene.task, task_formula(scene, None))


def with_costmap(problem: Problem, request: CostmapRequest) -> Problem:
    """The problem with its physical scene's costmap obtained (from the
    cache or the planner); an abstract scene, or one that has a costmap,
    as it is."""
    scene = problem.scene
    if scene.costmap is not None or scene.geometry is None:
        return problem
    got = obtain_costmap(scene, request.method, request.planner, request.seed,
                 use_cache=request.use_cache, progress=request.progress)
    return dataclasses.replace(problem, scene=dataclasses.replace(scene, costmap=got.costmap), obtained=got)


def solve(problem: Problem, solver: str = DEFAULT_SOLVER, *, budget: float | None = None,
          resolution: float = 1.0, k: int | None = None, time_limit: float | None = None) -> Solution:
    """E_p, a strategy and plays for the problem's game with a registered
    solver (`symsynth.solvers`), over the horizon its k can use.

    With `time_limit` (seconds), a solver that accepts one answers anytime
    (`Solution.exact` false: E_p bracketed); the whole k is then solved
    at once, since the horizon's shortcuts read exact values."""
    if solver not in SOLVERS:
        raise InputError(f"unknown solver {solver!r}; installed solvers: {', '.join(SOLVERS)}")
    if time_limit is None:
        return solve_game(SOLVERS[solver], problem.scene, problem.formula, k=k, budget=budget,
                          resolution=resolution)
    if not time_limit > 0 or math.isinf(time_limit):
        raise InputError(f"time limit must be a positive number of seconds, found {time_limit}")
    function = SOLVERS[solver]
    if "time_limit" not in inspect.signature(function).parameters:
        raise InputError(f"the {solver} solver does not stop at a time limit; "
                         "use --solver forward or auto for an anytime answer")
    return function(problem.scene, problem.formula, k=k, budget=budget, resolution=resolution,
                    time_limit=time_limit)
