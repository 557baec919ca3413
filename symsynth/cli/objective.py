"""`symsynth solve --objective expected|best-effort` (semantics §9): the
options, the human model they read, and the report."""

from __future__ import annotations

import argparse
import json
import math

from typing import TYPE_CHECKING

from symsynth.cli import options
from symsynth.errors import InputError

if TYPE_CHECKING:  # the solvers load numba: imported when an objective is solved, not at start-up
    from symsynth.game.human_model import HumanModel
    from symsynth.problem import Problem
    from symsynth.scene import Scene
    from symsynth.solvers.objectives import ObjectiveSolution

OBJECTIVES = ("worst", "expected", "best-effort")
EPSILON = 1e-6  # the default of --epsilon (symsynth.solvers.objectives.EPSILON)

OBJECTIVE_HELP = """\
what the robot optimizes (semantics §9): worst (default) the cost against the
worst human, E_p; expected the least expected cost against --human-model
among the strategies that stay within --budget (default E_p) against every
human, EX; best-effort the class of the start (winning, cooperative: some
play wins if the human helps, losing) and the cooperative cost C.  expected
and best-effort are computed by the solvers compiled and explicit (auto:
compiled where it fits)"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--objective", choices=OBJECTIVES, default="worst", help=OBJECTIVE_HELP)
    parser.add_argument("--human-model", metavar="NAME:ARGS",
                        help="the human model of --objective expected, e.g. random:0.3 (each turn the "
                             "human moves with probability 0.3, uniformly among its legal moves); "
                             "default: the scene's human.model, e.g. random(0.3)")
    parser.add_argument("--epsilon", type=options.positive, default=EPSILON, metavar="EPS",
                        help="--objective expected: where EX is only approached by waiting on "
                             "zero-cost moves, how close (costmap units) the waiting bound n must come "
                             f"(default {EPSILON:g})")


def human_model(scene: Scene, given: str | None) -> HumanModel | None:
    """The model of `--human-model` (it wins), else the scene's, else None."""
    from symsynth.game.human_model import parse_model

    if given is not None:
        return parse_model(given, "--human-model")
    if scene.human_model is not None:
        return parse_model(scene.human_model, scene.human_model_where)
    return None


def run_objective(args: argparse.Namespace, problem: Problem) -> int:
    from symsynth.solvers.objectives import solve_objective

    if args.time_limit is not None:
        raise InputError(f"--time-limit applies to --objective worst, not {args.objective}")
    model = human_model(problem.scene, args.human_model) if args.objective == "expected" else None
    solution = solve_objective(problem.scene, problem.formula, objective=args.objective, model=model, k=args.k,
                               budget=args.budget, resolution=args.resolution, solver=args.solver,
                               epsilon=args.epsilon)
    written = None if args.output is None else write_table(args, problem, model, solution)
    if args.json:
        out = solution.to_json() | {"scene": problem.scene.name, "task": problem.task.strip()}
        if written is not None:
            out["strategy"] = {"file": str(args.output), "entries": written}
        print(json.dumps(out, indent=2))
        return 0
    report(problem, solution)
    if written is not None:
        print(f"\nwrote {args.output} ({written} entries), read back and certified")
    return 0


def write_table(args: argparse.Namespace, problem: Problem, model: HumanModel | None,
                solution: ObjectiveSolution) -> int:
    """Write the strategy file (`symsynth.objective-strategy/1`), from the
    explicit solver's graph, whose positions have names; read it back and
    certify it as a reader would."""
    from symsynth.game.objective_strategy import certify_objective, read_objective_strategy, write_objective_strategy
    from symsynth.solvers.objectives import solve_objective
    from symsynth.solvers.objectives.files import objective_table

    if solution.arena is None or not solution.arena.positions:
        solution = solve_objective(problem.scene, problem.formula, objective=args.objective, model=model,
                                   k=args.k, budget=args.budget, resolution=args.resolution, solver="explicit",
                                   epsilon=args.epsilon)
    table = objective_table(problem.scene, problem.task, problem.formula, solution)
    written = write_objective_strategy(args.output, table)
    certify_objective(problem.scene, read_objective_strategy(args.output))
    return written


def report(problem: Problem, s: ObjectiveSolution) -> None:
    scene = problem.scene
    print(f"scene      {scene.name}{f' ({scene.source})' if scene.source else ''}")
    print(f"task       {problem.task.strip()}")
    print(f"human      k = {s.k} move{'s' if s.k != 1 else ''}, human first")
    print(f"solver     {s.solver}")
    print(f"objective  {s.objective}")
    print(f"E_p        {'infinite' if s.cost_bound is None else _num(s.cost_bound)}")
    if s.objective == "best-effort":
        print(f"class      {s.position_class}"
              + {"winning": ": a strategy wins against every human (within E_p)",
                 "cooperative": ": no strategy wins against every human, but a play wins if the human helps",
                 "losing": ": no play wins, whatever the human does"}[s.position_class or "losing"])
        print(f"C          {'infinite' if s.cooperative_cost is None else _num(s.cooperative_cost)}"
              " (the least robot cost of a winning play, robot and human choosing together)")
    else:
        print(f"model      {s.human_model}")
        print(f"budget     {'none' if s.budget is None else _num(s.budget)}"
              + (" (E_p, the default)" if s.budget is not None and s.budget == s.cost_bound else ""))
        if s.expected_cost is None:
            print("EX         undefined: " + ("no strategy wins against every human (E_p infinite)"
                                             if s.cost_bound is None else "the budget is below E_p"))
        else:
            print(f"EX         {_num(s.expected_cost)} (the least expected cost under the model of the "
                  "strategies that stay within the budget against every human)")
            if s.attained is False:
                n = "more than 10^6" if s.waiting is None else str(s.waiting)
                print(f"           an infimum, approached by waiting on zero-cost moves for the human to move; "
                      f"waiting at most {n} robot turns and then playing the worst-case strategy "
                      f"guarantees {_num(s.waiting_bound or math.inf)} (epsilon {s.epsilon:g})")
    phases = ", ".join(f"{name} {t:.4f}" for name, t in s.seconds.items())
    print(f"positions  {s.states} game positions")
    print(f"seconds    {sum(s.seconds.values()):.4f} ({phases})")


def _num(x: float) -> str:
    return f"{x:.10g}" if not float(x).is_integer() else str(int(x))
