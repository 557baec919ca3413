"""`symsynth simulate --objective expected|best-effort`: the objective's
strategy (semantics §9) played in the game against humans, run by run,
next to what the solver computed.

By default the runs are in the abstraction (the game's own moves and
quantized costs).  Humans: `random` is the model (`--human-model`, else the
scene's, else random(--move-probability)); `adversarial` answers with the
reply of largest worst-case value; `cooperative` (best effort) with the
reply on a cheapest cooperative play.  For `expected`, every play against
every human is also checked (the most any human can make it cost).

With `--in-world` (a physical scene) the strategy is run in the world
(`--world kinematic|physics`, `execution.simulate`), solved on the explicit
solver's graph: the expected-cost strategy with its budget counter
(`execution.objective_policy`), against no human, the model's random
human or (expected) the adversary, which takes the reply after which the
strategy may still pay the most (`BudgetPolicy.still_to_pay`); each run's
measured cost is reported next to EX, E_p and B.
"""

from __future__ import annotations

import argparse
import json
import math
import random
from typing import TYPE_CHECKING, Any

from symsynth.cli.objective import OBJECTIVES, human_model
from symsynth.errors import InputError

if TYPE_CHECKING:  # the solvers load numba: imported when an objective is solved, not at start-up
    from symsynth.game.human_model import HumanModel
    from symsynth.problem import Problem
    from symsynth.scene import Scene
    from symsynth.solvers.objectives import ObjectiveSolution

Z95 = 1.959963984540054  # the normal quantile of a two-sided 95% interval
#: The humans an objective's strategy is run against in the abstraction.
OBJECTIVE_HUMANS: dict[str, tuple[str, ...]] = {"expected": ("random", "adversarial"),
                                                "best-effort": ("random", "adversarial", "cooperative")}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--objective", choices=OBJECTIVES, default="worst",
                        help="worst (default): the worst-case strategy in the world; expected or best-effort: "
                             "that objective's strategy (semantics §9), run in the abstraction against "
                             "--human (random: the human model; adversarial; cooperative for best-effort)")
    parser.add_argument("--in-world", action="store_true",
                        help="--objective: run the strategy in the world (--world) instead of the abstraction, "
                             "against --human none, random (the model) or, for expected, adversarial (the "
                             "reply after which the strategy may still pay the most); physical scenes only")
    parser.add_argument("--human-model", metavar="NAME:ARGS",
                        help="--objective: the model of the random human (default: the scene's human.model, "
                             "else random:--move-probability)")


def objective_humans(args: argparse.Namespace, scene: Scene) -> HumanModel:
    """The model of the random human, after checking that `--human` (and,
    in the world, the model) fits the objective: read before any costmap
    is computed, so that a wrong option costs no planning."""
    from symsynth.game.human_model import RandomModel, parse_model

    model = human_model(scene, args.human_model) or parse_model(f"random:{args.move_probability!r}")
    wanted: tuple[str, ...]
    if args.in_world:
        wanted = ("none", "random", "adversarial") if args.objective == "expected" else ("none", "random")
        if args.human not in wanted:
            raise InputError(f"--in-world --objective {args.objective} runs against --human {', '.join(wanted)}, "
                             f"not {args.human!r}")
        if not isinstance(model, RandomModel):
            raise InputError(f"--in-world: the world's random human is random(P); the model {model.name} is not")
        return model
    wanted = OBJECTIVE_HUMANS[args.objective]
    if args.human not in (*wanted, "none"):
        raise InputError(f"--objective {args.objective} runs against {', '.join(wanted)} (or none: all of them), "
                         f"not {args.human!r}")
    return model


def run_objective_simulation(args: argparse.Namespace, problem: Problem, model: HumanModel) -> int:
    from symsynth.solvers.objectives import solve_objective

    scene = problem.scene
    wanted = OBJECTIVE_HUMANS[args.objective]
    solution = solve_objective(scene, problem.formula, objective=args.objective, model=model,
                               budget=args.budget, solver=args.solver if args.solver in ("explicit", "compiled")
                               else "auto")
    which = wanted if args.human == "none" else (args.human,)
    out = _runs(solution, which, args.runs, args.seed)
    if args.json:
        print(json.dumps(solution.to_json() | {"runs": out, "scene": scene.name}, indent=2))
        return 0
    _print(solution, out)
    return 0 if all(r.get("above_budget", 0) == 0 for r in out.values()) else 1


def _runs(s: ObjectiveSolution, humans: tuple[str, ...], count: int, seed: int) -> dict[str, Any]:
    from symsynth.solvers.objectives.play import ExpectedStrategy, best_effort_choice, check_expected, exact, run

    out: dict[str, Any] = {}
    if s.arena is None or (s.objective == "expected" and s.expected_cost is None):
        return out
    arena, r = s.arena, s.resolution
    budget = int(s.budget_units or 0)
    coop = s.tables[0] if s.objective == "best-effort" and s.tables is not None else None
    for human in humans:
        rng = random.Random(f"objective/{human}/{seed}")
        plays = [run(s.strategy(), budget, {"random": "model", "adversarial": "worst"}.get(human, human), rng,
                     coop=coop) for _ in range(count)]
        costs = [c * r for c, won in plays if won]
        row: dict[str, Any] = {"runs": count, "finished": sum(won for _, won in plays) / count}
        if costs:
            mean = sum(costs) / len(costs)
            sd = math.sqrt(sum((c - mean) ** 2 for c in costs) / (len(costs) - 1)) if len(costs) > 1 else 0.0
            row |= {"mean_cost": mean, "ci95": Z95 * sd / math.sqrt(len(costs)), "max_cost": max(costs)}
        if s.objective == "expected":
            row["above_budget"] = sum(c > budget for c, _ in plays)
        out[human] = row
    if s.objective == "expected":
        strategy = s.strategy()
        assert isinstance(strategy, ExpectedStrategy)  # the objective is expected
        out["every human"] = {"max_cost": check_expected(strategy, budget) * r}
        out["worst-case strategy"] = {"expected_cost": exact(arena, arena.wchoice, False) * r}
    elif s.tables is not None and "random" in out:
        rc, _, moves, _ = s.tables
        out["random"]["finish_probability"] = exact(arena, best_effort_choice(arena, moves, rc), True)
    return out


def _print(s: ObjectiveSolution, out: dict[str, Any]) -> None:
    print(f"objective  {s.objective}" + (f", human model {s.human_model}" if s.human_model else ""))
    print(f"E_p        {'infinite' if s.cost_bound is None else f'{s.cost_bound:g}'}")
    if s.objective == "expected":
        if s.expected_cost is None:
            print("EX         undefined (no B-safe strategy): nothing to run")
            return
        print(f"budget     {s.budget:g}")
        print(f"EX         {s.expected_cost:.10g} (in the abstraction)")
    else:
        c = "infinite" if s.cooperative_cost is None else f"{s.cooperative_cost:g}"
        print(f"class      {s.position_class}; C {c}")
    for human, row in out.items():
        parts = [f"{k} {v:.6g}" if isinstance(v, float) else f"{k} {v}" for k, v in row.items()]
        print(f"{human + ':':<21}{', '.join(parts)}")


def run_objective_world(args: argparse.Namespace, problem: Problem, model: HumanModel) -> int:
    """`simulate --objective ... --in-world`: the objective's strategy in
    the world against no human or the model's random human."""
    from symsynth.execution.human import HUMANS, HumanContext
    from symsynth.execution.objective_policy import BudgetPolicy
    from symsynth.execution.policy import Policy
    from symsynth.execution.simulate import Simulator
    from symsynth.game.graph import GameGraph
    from symsynth.game.human_model import RandomModel
    from symsynth.planning.registry import planner_class
    from symsynth.problem import simulation_planner
    from symsynth.solvers.objectives import solve_objective
    from symsynth.solvers.objectives.files import objective_table, to_pay_by_position

    scene = problem.scene
    assert isinstance(model, RandomModel)  # objective_humans checked it
    planner = planner_class(simulation_planner(scene, args.planner))(scene)
    s = solve_objective(scene, problem.formula, objective=args.objective, model=model, budget=args.budget,
                        solver="explicit")
    if args.objective == "expected" and s.expected_cost is None:
        print(f"EX         undefined (no B-safe strategy; E_p {s.cost_bound}): nothing to run")
        return 1
    table = objective_table(scene, problem.task, problem.formula, s)
    policy = Policy(table.positions, {}, None)
    budget = policy.budget
    if args.objective == "expected":  # the adversary chooses by what the strategy may still pay
        to_pay = to_pay_by_position(s) if args.human == "adversarial" else None
        policy = budgeted = BudgetPolicy(table, GameGraph(scene, problem.formula, s.resolution), to_pay)
        budget = budgeted.still_to_pay
    simulator = Simulator(scene, problem.formula, policy, planner, resolution=s.resolution, world=args.world,
                          randomization=args.randomize)
    runs = [simulator.run(HUMANS[args.human](HumanContext(args.seed + i, float(model.probability), budget, scene)),
                          args.seed + i) for i in range(args.runs)]
    out = _world_summary(s, runs)
    if args.json:
        print(json.dumps(s.to_json() | {"scene": scene.name, "world": args.world, "human": args.human,
                                        "summary": out, "runs": [r.to_json(scene.object_names) for r in runs]},
                         indent=2))
    else:
        _print(s, {f"{args.human} human, {args.world} world": out})
    return 0 if out["completed"] == len(runs) and not out.get("above_budget") and out["sound"] == len(runs) else 1


def _world_summary(s: ObjectiveSolution, runs: list) -> dict[str, Any]:
    """The runs' completion, measured and abstract costs (mean with its 95%
    interval), and for `expected` how many went above B (none should)."""
    from symsynth.execution.runs import SLACK

    costs = [r.cost for r in runs]
    out: dict[str, Any] = {"runs": len(runs), "completed": sum(r.completed for r in runs),
                           "sound": sum(r.sound for r in runs), "mean_cost": sum(costs) / len(costs),
                           "max_cost": max(costs), "max_abstract_cost": max(r.abstract_cost for r in runs)}
    if len(costs) > 1:
        mean = out["mean_cost"]
        out["ci95"] = Z95 * math.sqrt(sum((c - mean) ** 2 for c in costs) / (len(costs) - 1) / len(costs))
    if s.objective == "expected" and s.budget is not None:
        out["above_budget"] = sum(c > s.budget + SLACK for c in costs)
    return out
