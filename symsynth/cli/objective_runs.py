"""`symsynth simulate --objective expected|best-effort`: the objective's
strategy (semantics §9) played in the game against humans, run by run,
next to what the solver computed.

The runs are in the abstraction (the game's own moves and quantized
costs), not in the PyBullet world: the world's runner follows a strategy
keyed by positions alone, and these strategies also remember the budget
left and their turns.  Humans: `random` is the model (`--human-model`, else
the scene's, else random(--move-probability)); `adversarial` answers with
the reply of largest worst-case value; `cooperative` (best effort) with the
reply on a cheapest cooperative play.  For `expected`, every play against
every human is also checked (the most any human can make it cost).
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
    from symsynth.problem import Problem
    from symsynth.solvers.objectives import ObjectiveSolution

Z95 = 1.959963984540054  # the normal quantile of a two-sided 95% interval


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--objective", choices=OBJECTIVES, default="worst",
                        help="worst (default): the worst-case strategy in the world; expected or best-effort: "
                             "that objective's strategy (semantics §9), run in the abstraction against "
                             "--human (random: the human model; adversarial; cooperative for best-effort)")
    parser.add_argument("--human-model", metavar="NAME:ARGS",
                        help="--objective: the model of the random human (default: the scene's human.model, "
                             "else random:--move-probability)")


def run_objective_simulation(args: argparse.Namespace, problem: Problem) -> int:
    from symsynth.game.human_model import parse_model
    from symsynth.solvers.objectives import solve_objective

    scene = problem.scene
    model = human_model(scene, args.human_model) or parse_model(f"random:{args.move_probability!r}")
    humans = {"expected": ("random", "adversarial"), "best-effort": ("random", "adversarial", "cooperative")}
    wanted = humans[args.objective]
    if args.human not in (*wanted, "none"):
        raise InputError(f"--objective {args.objective} runs against {', '.join(wanted)} (or none: all of them), "
                         f"not {args.human!r}")
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
    from symsynth.solvers.objectives.play import best_effort_choice, check_expected, exact, run

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
        out["every human"] = {"max_cost": check_expected(s.strategy(), budget) * r}
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
