"""`symsynth simulate`: run a strategy in a PyBullet world against a simulated human."""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from symsynth.cli import COMMANDS
from symsynth.cli import objective_runs, options
from symsynth.cli.options import check_writable
from symsynth.cli.solve import costmap_json, costmap_report
from symsynth.errors import InputError
from symsynth.game.strategy import format_state
from symsynth.planning.registry import planner_class
from symsynth.problem import (Problem, Simulation, no_guarantee, simulate, simulation_planner, with_costmap,
                              with_strategy, with_task)
from symsynth.scene import Scene, load_scene
from symsynth.solvers import DEFAULT_SOLVER, SOLVERS

if TYPE_CHECKING:
    from symsynth.execution.runs import Run

HUMANS_GROUP = "symsynth.humans"  # none, random, adversarial, and any installed
WORLDS = ("kinematic", "physics")  # execution.simulate.WORLDS, without importing pybullet for --help
DESCRIPTION = """\
Execute a strategy in simulation (paper Sec. V-B): the robot follows the
strategy while a simulated human moves objects, and each run shows whether
the task was completed within the bound E_p.

The world is the scene in PyBullet (headless; --gui opens a window).  The
abstract state is read from it as a vision system would (object poses to
locations or Else, end-effector to anchors), and the strategy is asked for
its action whenever that state changes.  Transits and transfers follow
their costmap rule's evidence path when its assumptions hold in the world,
and are planned at run time otherwise; grab and drop are primitives (a
Cartesian approach by inverse kinematics).  Measured cost: radians
travelled x per_radian, plus the fixed grab and drop costs.

The world is physical by default (--world physics) for a scene with
objects whose every grasp the fingers can close on (no object wider across
them than they open; scenes/arch.yaml's lintel is 14 cm across the Panda's
8 cm, so it runs kinematic by default, and the report says why);
--world kinematic is the fast replay.

The physical world runs the same steps with PyBullet dynamics (gravity, a
1/240 s step, masses and friction from the scene's physics: blocks): the
joints follow the paths by position control, the fingers close on the
object (a constraint firms the grasp only once both touch it), a dropped
object settles, a pushed or pulled object moves only by contact.  After
each step the settled world is observed; an object not where the
abstraction says is a state divergence with its distance, and the
strategy goes on from what is observed.  --randomize draws each run's
friction, masses and initial poses from its seed (docs/simulation.md).

Humans (--human): none; random (on each of its turns, a random legal move
with probability --move-probability, at most k moves); adversarial (the
solver's worst case: the move after which the strategy may have to spend
the most); or a script file (YAML: which object, where, after which robot
action; see symsynth/execution/human.py).  Moves the world forbids (a
block where the hand is) are not made; a scripted one is reported.

Without --strategy the game is solved first, reusing the cached costmap
(--method, --planner, --costmap-seed, --no-cache as for solve).  When E_p
is infinite or above --budget, no guarantee holds: the command says so and
stops, unless --best-effort, which runs anyway (where the strategy has no
action, it plays the explicit solver's action for the same state with
fewer human moves left, as if the human had fewer moves left).  The
adversary needs a winning strategy's budgets: with E_p infinite it is
refused.

Each run reports completed or not, the measured cost, E_p, the trace of
abstract states and actions, and every divergence between the abstraction
and the world.  A measured cost above the abstract cost of its action, or
an evidence path that collides although its rule held, is a SOUNDNESS BUG
and is reported as one.

--objective expected | best-effort runs that objective's strategy
(semantics §9) in the abstraction instead (any scene, abstract ones too):
against the random human of --human-model (mean cost with its 95%
confidence interval next to EX), the adversary, and for best effort a
cooperating human, with the share of runs that finish.  With --in-world it
runs in the world (--world) against --human none or random (and, for
expected, adversarial: the reply after which the strategy may still pay
the most with the budget it has left): the expected-cost strategy keeps
its budget counter, and each run's measured cost is reported next to EX,
E_p and B (never above B).

Exit status: 0 when every run completed within E_p without a soundness
divergence; 1 otherwise (or when no guarantee holds and --best-effort was
not given); 2 on bad input."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("simulate", help=COMMANDS["simulate"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="a physical scene file (YAML, with a robot)")
    parser.add_argument("--strategy", type=Path, metavar="FILE",
                        help="strategy file from 'solve -o' (default: solve now)")
    parser.add_argument("--human", default="none", metavar="none|random|adversarial|SCRIPT",
                        help="the simulated human (default: none)")
    parser.add_argument("--seed", type=options.count, default=0, metavar="S",
                        help="seed of the first run (human, run-time planning); run i uses S+i (default: 0)")
    parser.add_argument("--runs", type=options.at_least_one, default=1, metavar="N", help="number of runs (default: 1)")
    parser.add_argument("--move-probability", type=options.fraction("a probability"), default=0.3, metavar="P",
                        help="random human: chance of a move on each of its turns (default: 0.3)")
    parser.add_argument("--k", type=options.count, metavar="K",
                        help="human moves per run instead of the scene's human.k "
                             "(when solving here; a --strategy file fixes k)")
    parser.add_argument("--budget", type=options.amount, metavar="E",
                        help="energy budget: a guarantee holds only if E_p <= E")
    parser.add_argument("--best-effort", action="store_true",
                        help="run even when no guarantee holds (E_p infinite or above --budget)")
    parser.add_argument("--record", type=Path, metavar="OUT.gif",
                        help="write an animated GIF of the first run (headless rendering)")
    parser.add_argument("--size", type=options.size, default=(480, 360), metavar="WxH",
                        help="size of the recording's frames in pixels (default: 480x360)")
    parser.add_argument("--trace", action="store_true",
                        help="print every run's trace (the default for a single run)")
    parser.add_argument("--gui", action="store_true", help="show the world in a window (needs a display)")
    parser.add_argument("--json", action="store_true", help="print the runs as JSON")
    parser.add_argument("--world", choices=WORLDS,
                        help="kinematic: configurations set, a held object welded to the hand, objects set "
                             "down exactly (fast replay); physics: PyBullet dynamics, the fingers close on "
                             "the object, pushes move it by contact, objects settle (default: physics for a "
                             "scene with objects the gripper can close on with every grasp, else kinematic, "
                             "and the report says why)")
    parser.add_argument("--randomize", type=options.randomization, metavar="friction=R,mass=R,pose=M",
                        help="physics: each run's world drawn by its seed: friction and masses scaled by "
                             "up to +-R (relative), initial poses shifted by up to M metres "
                             "(e.g. friction=0.2,mass=0.2,pose=0.005)")
    options.add_costmap_options(parser, seed_alias=False, planner_help="planner plugin, for the costmap and "
                                "the run (default: the one that built the scene's costmap, else the scene's)")
    parser.add_argument("--solver", choices=tuple(SOLVERS), default=DEFAULT_SOLVER,
                        help=f"game solver when solving here (default: {DEFAULT_SOLVER})")
    objective_runs.add_arguments(parser)
    parser.set_defaults(run=run)


def choose_world(args: argparse.Namespace, scene: Scene) -> None:
    """`args.world` as asked, else the scene's default (physics where the
    fingers close on every grasp), with `args.kinematic_because` saying why
    it is kinematic; --randomize needs the physical world."""
    args.kinematic_because = []
    if args.world is None:
        from symsynth.execution.world_choice import default_world

        args.world, args.kinematic_because = default_world(scene)
    if args.randomize is not None and args.world == "kinematic":
        why = (f", and {args.scene} runs in the kinematic world by default ({'; '.join(args.kinematic_because)})"
               if args.kinematic_because else "")
        raise InputError(f"--randomize draws the physical world's friction, masses and poses{why}: "
                         "add --world physics")


def run(args: argparse.Namespace) -> int:
    from symsynth.bullet import check_display
    from symsynth.execution.human import HUMANS, read_script

    if args.objective != "worst":  # semantics §9: the objective's strategy, in the game
        scene = load_scene(args.scene)
        if args.in_world:
            if scene.geometry is None:
                raise InputError(f"{args.scene}: an abstract scene (no 'robot' key) has no world: "
                                 "leave out --in-world")
            choose_world(args, scene)
        model = objective_runs.objective_humans(args, scene)  # before the costmap: a wrong option costs nothing
        problem = with_task(scene if args.k is None else dataclasses.replace(scene, k=args.k), None)
        request = options.costmap_request(args, progress=not args.json)
        problem = with_costmap(problem, request)
        if args.in_world:
            return objective_runs.run_objective_world(args, problem, model)
        return objective_runs.run_objective_simulation(args, problem, model)
    if args.record is not None:
        check_writable(args.record, "recording")
    check_display(args.gui)
    scene = load_scene(args.scene)
    if scene.geometry is None:
        raise InputError(f"{args.scene}: an abstract scene (no 'robot' key) has no world to simulate")
    choose_world(args, scene)
    # Every input is read and checked before the costmap and the solve.
    planner = simulation_planner(scene, args.planner)
    planner_class(planner)
    if args.strategy is not None:
        problem = with_strategy(scene, args.strategy, k=args.k)
    elif scene.task is None:
        raise InputError(f"scene {scene.name!r} has no task: give one (task: FORMULA)")
    else:
        problem = with_task(scene if args.k is None else dataclasses.replace(scene, k=args.k), None)
    human = args.human
    if args.human not in HUMANS:
        if not Path(args.human).is_file():
            raise InputError(f"--human: expected {', '.join(HUMANS)} or a script file, "
                             f"found {args.human!r} (no such file)")
        human = read_script(args.human, problem.scene)  # against the k of the strategy
    progress = not args.json
    problem = with_costmap(problem, options.costmap_request(args, progress))
    simulation = simulate(problem, human, planner=planner, solver=args.solver, budget=args.budget,
                          best_effort=args.best_effort, runs=args.runs, seed=args.seed,
                          move_probability=args.move_probability, record=args.record, size=args.size,
                          gui=args.gui, progress=progress, world=args.world, randomization=args.randomize)
    if simulation.stopped is not None:
        print(simulation.stopped + "; add --best-effort to run anyway")
        return 1
    if args.json:
        print(json.dumps(_json(args, problem, simulation), indent=2))
    else:
        if problem.obtained is not None:
            costmap_report(problem.obtained)
        _report(problem.scene, args, simulation.positions, simulation.bound, simulation.guarantee, simulation.runs)
        if simulation.frames:
            print(f"\nwrote {args.record} ({simulation.frames} frames, run 1)")
    return 0 if simulation.ok else 1


def _json(args: argparse.Namespace, problem: Problem, simulation: Simulation) -> dict[str, Any]:
    """`simulate --json`: the run's settings, the strategy, the costmap and every run."""
    scene, obtained = problem.scene, problem.obtained
    return {
        "scene": scene.name, "task": simulation.task, "k": scene.k, "cost_bound": simulation.bound,
        "budget": args.budget, "guarantee": simulation.guarantee, "human": args.human, "world": args.world,
        "kinematic_because": args.kinematic_because,
        "randomize": None if args.randomize is None else str(args.randomize),
        "strategy": {"file": None if args.strategy is None else str(args.strategy),
                     "positions": simulation.positions, "solver": None if args.strategy else args.solver},
        "costmap": None if obtained is None else costmap_json(obtained),
        "recording": None if args.record is None else str(args.record),
        "runs": [r.to_json(scene.object_names) for r in simulation.runs],
    }


def _report(scene: Scene, args: argparse.Namespace, positions: int | None, bound: float | None,
            guarantee: bool, runs: Sequence[Run]) -> None:
    from symsynth.execution.runs import SLACK

    source = f"from {args.strategy}" if args.strategy else f"solved by {args.solver}"
    print(f"scene      {scene.name} ({args.scene})")
    print(f"strategy   {source}: " + ("" if positions is None else f"{positions} positions, ") + f"k = {scene.k}, "
          + (f"E_p = {bound:g}" if bound is not None else "E_p infinite"))
    if not guarantee:
        print(f"guarantee  NONE. {no_guarantee(bound, args.budget)}; running best effort")
    print(f"human      {args.human}" + (f", move probability {args.move_probability:g}"
                                        if args.human == "random" else ""))
    print(f"world      {args.world}" + (f" (the default here: {'; '.join(args.kinematic_because)}; "
                                        "--world physics runs it anyway)" if args.kinematic_because else "")
          + (f", randomized {args.randomize}" if args.randomize is not None else ""))
    for i, r in enumerate(runs, 1):
        print()
        print(f"run {i} (seed {r.seed}): {_verdict(r)}")
        if args.budget is not None:
            over = r.cost > args.budget + SLACK
            print(f"           budget {args.budget:g}: " + ("EXCEEDED" if over else "kept"))
        if args.trace or len(runs) == 1:
            _trace(r, scene)
        _divergences(r)
    if len(runs) > 1:
        done = sum(r.completed for r in runs)
        worst = max(r.cost for r in runs)
        print()
        print(f"summary    {done}/{len(runs)} completed; measured cost max {worst:.1f}, "
              f"mean {sum(r.cost for r in runs) / len(runs):.1f}"
              + ("" if bound is None else f"; E_p {bound:g}; within E_p: "
                 f"{sum(bool(r.within_bound) for r in runs)}/{len(runs)}"))
        unsound = [i for i, r in enumerate(runs, 1) if not r.sound]
        if unsound:
            print(f"SOUNDNESS  runs {', '.join(map(str, unsound))} diverged: see above")


def _verdict(r) -> str:
    robot = sum(s.who == "robot" for s in r.steps)
    human = sum(s.who == "human" for s in r.steps)
    status = "completed" if r.completed else f"NOT completed ({r.reason})"
    bound = "" if r.bound is None else (f" <= E_p {r.bound:g}" if r.within_bound else
                                        f" > E_p {r.bound:g} (OVER THE BOUND)")
    extra = f", {r.best_effort} best-effort actions" if r.best_effort else ""
    return (f"{status}; measured cost {r.cost:.2f}{bound} (abstract {r.abstract_cost:.2f}); "
            f"{robot} robot actions, {human} human moves{extra}; {r.seconds:.1f} s")


def _trace(r, scene: Scene) -> None:
    width = max((len(s.action) for s in r.steps), default=6)
    print(f"  {'#':>3}  who    {'action':<{width}}  {'abstract':>8}  {'measured':>8}  {'how':<9}  state")
    for n, s in enumerate(r.steps, 1):
        abstract = "" if s.abstract is None else f"{s.abstract:8.2f}"
        measured = "" if s.measured is None else f"{s.measured:8.2f}"
        print(f"  {n:>3}  {s.who:<5}  {s.action:<{width}}  {abstract:>8}  {measured:>8}  {s.source:<9}  "
              f"{format_state(s.state, scene.object_names)}")
    for refused in r.refused:
        print(f"  refused: {refused}")


def _divergences(r) -> None:
    sound = [d for d in r.divergences if not d.soundness]
    unsound = [d for d in r.divergences if d.soundness]
    for d in unsound:
        print(f"  !!! SOUNDNESS BUG at step {d.step} ({d.kind}): {d.message}")
    for d in sound:
        print(f"  divergence at step {d.step} ({d.kind}): {d.message}")
