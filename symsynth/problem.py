"""The application layer: one manipulation problem composed once, for the
command line and for comparison runs alike.

A `Problem` is a scene with its costmap (given with the scene, or obtained
from the cache or a planner), its task parsed once and checked against
the scene, where the costmap came from, and a strategy file given with it
(whose task and k are then the problem's).  `solve(problem, ...)` solves
its game with a registered solver over the horizon `k` can use
(`game.horizon`); `simulate(problem, ...)` runs a strategy (the file's, or
one solved now) in the PyBullet world against a simulated human.  Below
it, every layer takes what it needs as values: the solvers a scene and a
formula, the planners a physical scene, the simulator a scene, a formula
and a policy.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple
from pathlib import Path

from tqdm import tqdm

from symsynth.errors import InputError
from symsynth.game.horizon import solve_game
from symsynth.game.strategy import StrategyFile, certify, check_header, read_strategy, strategy_table
from symsynth.scene.propositions import interpret_all
from symsynth.game.solution import Position, Solution, task_formula, verdict
from symsynth.logic import ast, parse_ltlf
from symsynth.planning.build import Obtained, obtain_costmap
from symsynth.planning.registry import planner_class
from symsynth.planning.verify import installed_planner
from symsynth.scene import Scene, load_scene
from symsynth.solvers import DEFAULT_SOLVER, SOLVERS

if TYPE_CHECKING:  # the simulator (pybullet, the renderer) is imported only when simulating
    from symsynth.execution.human import ScriptedHuman
    from symsynth.execution.physics import Randomization
    from symsynth.execution.runs import Run
    from symsynth.execution.world import SimWorld


@dataclass(frozen=True)
class GivenStrategy:
    """A strategy file given with the problem: where it was read from, and
    what it says (its header checked against the scene; what it claims is
    certified once the costmap gives the costs, by `simulate`)."""

    path: Path
    table: StrategyFile


@dataclass(frozen=True)
class Problem:
    """A scene (with its costmap), its task as written and parsed, how the
    costmap was obtained (None: it came with the scene), and a strategy
    file given with it (None: solve to get one)."""

    scene: Scene
    task: str
    formula: ast.Formula
    obtained: Obtained | None = None
    strategy: GivenStrategy | None = None


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


def with_strategy(scene: Scene, path: Path, *, k: int | None = None) -> Problem:
    """The problem a strategy file poses on `scene`: the file's task and k
    (its header checked against the scene before any costmap is computed;
    `k`, if given, must be the file's).  The task is parsed once, here."""
    table = read_strategy(path)
    try:
        formula = check_header(scene, table)
    except InputError as error:
        raise InputError(f"{path}: not a strategy for scene {scene.name!r}: {error}") from None
    if k is not None and k != table.k:
        raise InputError(f"--k {k}: the strategy {path} was solved for k = {table.k} (--k is for solving here)")
    return Problem(dataclasses.replace(scene, k=table.k), table.task, formula, strategy=GivenStrategy(path, table))


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
                         "use --solver auto, compiled, andor or forward for an anytime answer")
    return function(problem.scene, problem.formula, k=k, budget=budget, resolution=resolution,
                    time_limit=time_limit)


# -- simulation ----------------------------------------------------------------------------

@dataclass(frozen=True)
class Simulation:
    """What `simulate` did: the task and E_p of the strategy that ran,
    the positions of its table (a strategy file, or the one made for the
    adversary; None when the solver's strategy was looked up where the
    runs went), whether a guarantee held, the runs, and the frames
    recorded.  `stopped` says why nothing ran (no guarantee, and no
    best effort asked for)."""

    task: str
    bound: float | None
    positions: int | None
    guarantee: bool
    budget: float | None
    runs: tuple[Run, ...] = ()
    frames: int = 0
    stopped: str | None = None

    @property
    def ok(self) -> bool:
        """Every run completed within E_p and the budget, without a soundness
        divergence (False when nothing ran)."""
        from symsynth.execution.runs import SLACK

        return self.stopped is None and all(
            r.completed and r.sound and r.within_bound is not False
            and (self.budget is None or r.cost <= self.budget + SLACK) for r in self.runs)


def simulate(problem: Problem, human: str | ScriptedHuman = "none", *, planner: str | None = None,
             solver: str = DEFAULT_SOLVER, budget: float | None = None, best_effort: bool = False,
             runs: int = 1, seed: int = 0, move_probability: float = 0.3, record: Path | None = None,
             size: tuple[int, int] = (480, 360), gui: bool = False, progress: bool = True,
             world: str = "kinematic", randomization: Randomization | None = None) -> Simulation:
    """Runs of the problem's strategy (its strategy file, certified first, or
    the strategy `solver` finds now) in the PyBullet world against `human`:
    a registered human's name (`symsynth.humans`) or a script
    (`execution.human.read_script`, read against the problem's scene); run
    i uses seed `seed + i`.  The planner is `simulation_planner`'s.  When
    E_p is infinite or above `budget`, nothing runs unless `best_effort`
    (where the strategy has no action, the explicit solver's action with
    fewer human moves left is played).  `record`: a GIF of the first run.
    `world`: kinematic or physics (`execution.physics`, with `randomization`
    drawn by each run's seed)."""
    from symsynth.execution.human import HUMANS, HumanContext, ScriptedHuman, human_needs
    from symsynth.execution.record import Recorder
    from symsynth.execution.policy import Policy
    from symsynth.execution.simulate import Simulator

    scene = problem.scene
    if scene.geometry is None:
        raise InputError(f"scene {scene.name!r} is abstract (no 'robot' key): it has no world to simulate")
    planner_type = planner_class(simulation_planner(scene, planner))
    if isinstance(human, str) and human not in HUMANS:
        raise InputError(f"unknown human {human!r}; installed humans: {', '.join(HUMANS)}")
    needs = frozenset() if isinstance(human, ScriptedHuman) else human_needs(human)
    solution, bound, units, resolution, actions, budgets, positions = _played(problem, solver, budget, needs)
    guarantee = bound is not None and (budget is None or verdict(units, resolution, budget) is True)
    task = problem.task.strip()
    if not guarantee and not best_effort:
        return Simulation(task, bound, positions, guarantee, budget, stopped=no_guarantee(bound, budget))
    if bound is None and "budgets" in needs:  # strategy_table explores nothing then
        raise InputError(f"--human {human}: no strategy wins against every human (E_p is infinite), so "
                         f"there are no budgets for this human to choose its moves by; run best effort "
                         f"against a human that needs none (none, random) or a script")
    # a finite E_p over the budget still has its strategy everywhere it leads
    fallback = None if bound is not None else _fallback(problem, solver, solution)
    policy = Policy(actions, budgets, bound, fallback)
    simulator = Simulator(scene, problem.formula, policy, planner_type(scene), resolution=resolution,
                          world=world, randomization=randomization)

    made: list[Recorder] = []

    def recorder(world: SimWorld) -> Recorder:  # of the first run, when asked
        assert record is not None
        made.append(Recorder(world, record, width=size[0], height=size[1]))
        return made[-1]

    done = []
    with tqdm(range(runs), desc="runs", unit=" run", disable=None if progress and runs > 1 else True) as bar:
        for i in bar:
            if isinstance(human, ScriptedHuman):
                player = ScriptedHuman(human.entries)  # from its first entry
            else:
                player = HUMANS[human](HumanContext(seed + i, move_probability, policy.budget, scene))
            done.append(simulator.run(player, seed + i, recorder=recorder if i == 0 and record else None, gui=gui))
    frames = made[0].save() if made else 0
    return Simulation(task, bound, positions, guarantee, budget, tuple(done), frames)


def _fallback(problem: Problem, solver: str, solution: Solution | None) -> Mapping[Position, str]:
    """The explicit solver's strategy, played where the strategy has no
    action: it covers every reachable position of finite value, also when
    the initial one has none (the symbolic solver stops early then)."""
    if solution is not None and solver == "explicit":
        return solution.strategy  # solved just now, with the same task, k and resolution
    return solve(problem, "explicit").strategy


class _Played(NamedTuple):
    """The strategy the runs play, and what it guarantees."""

    solution: Solution | None  # None: a strategy file
    bound: float | None  # E_p
    units: int | None
    resolution: float
    actions: Mapping  # position -> action (or (position, budget) -> action)
    budgets: Mapping  # position -> budget, where a human needs them
    positions: int | None  # positions tabled (None: looked up as the runs go)


def _played(problem: Problem, solver: str, budget: float | None, needs: frozenset[str]) -> _Played:
    """The strategy the runs play: the problem's strategy file, certified
    against the scene now that the costmap gives the costs, or the one
    `solver` finds (as a table when the human `needs` every position's
    budget)."""
    given, table, solution = problem.strategy, None, None
    scene = problem.scene
    if given is not None:  # what it claims is checked now that the costmap gives the costs
        table = given.table
        try:
            certify(scene, table, problem.formula)
        except InputError as error:
            raise InputError(f"{given.path}: not a strategy for scene {scene.name!r}: {error}") from None
    else:
        solution = solve(problem, solver, budget=budget)
        if "budgets" in needs:  # e.g. the adversary weighs its moves by the budgets of every position reached
            table = strategy_table(scene, problem.task, solution, formula=problem.formula)
    if table is not None:
        return _Played(solution, table.cost_bound, table.units, table.resolution, table.positions, table.budgets,
                       len(table.positions))
    assert solution is not None  # solved above: no strategy file was given
    # The solver's strategy, looked up only where a run goes (none when
    # none wins).  Unlike strategy_table's exploration, this does not
    # check up front that every reachable position has an available
    # action: a strategy that lacks one ends that run with the reason.
    bound = solution.cost_bound
    return _Played(solution, bound, solution.units, solution.resolution, {} if bound is None else solution.strategy,
                   {}, None)


def simulation_planner(scene: Scene, given: str | None) -> str:
    """The planner that simulates: the one the scene's costmap records as its
    builder, else `given` (--planner) or the scene's.  Another planner than
    the recorded one is an error, not a warning: evidence paths start and
    end at the building planner's inverse kinematics solutions for the
    anchors, but a motion planned at run time ends at the simulating
    planner's, so the next evidence motion would begin with a jump its
    rule's cost leaves out (up to 0.7 rad between ompl-fcl's and
    pybullet's on the bundled scenes), and the runs' cost and evidence
    verdicts would be about that jump, not the abstraction."""
    built = None if scene.costmap is None else scene.costmap.provenance
    if built is not None:
        installed_planner(built.name, "the scene's costmap")
    if built is not None and given is not None and given != built.name:
        raise InputError(f"--planner {given}: the scene's costmap was built by planner {built.name!r} (its key "
                         f"'planner'), and its evidence paths start and end at {built.name}'s inverse kinematics "
                         f"solutions for the anchors; {given}'s differ, so the robot would jump onto each path "
                         f"at a cost the costmap leaves out. Leave --planner out to simulate with {built.name}")
    if built is not None:
        return built.name
    if given is not None:
        return given
    if scene.geometry is None:
        raise InputError(f"scene {scene.name!r} is abstract (no 'robot' key): it names no planner")
    return scene.geometry.planner.name


def no_guarantee(bound: float | None, budget: float | None) -> str:
    """Why no guarantee holds: E_p infinite, or above the budget."""
    if bound is None:
        return "No guarantee: no strategy wins against every human (E_p is infinite)"
    return f"No guarantee: E_p = {bound:.12g} exceeds the budget {budget:.12g}"
