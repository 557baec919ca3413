"""`symsynth solve`: solve a scene's manipulation game and show why the bound is what it is."""

from __future__ import annotations

import argparse
import json
import sys
from decimal import Decimal
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.cli import objective, options
from symsynth.cli.options import check_writable
from symsynth.game.abstraction import initial_state, robot_moves
from symsynth.errors import InputError
from symsynth.game.horizon import TooManyMoves
from symsynth.game.solution import Solution, Step
from symsynth.game.strategy import format_state, write_strategy
from symsynth.game.stuck import stuck_reasons
from symsynth.game.symmetry import Symmetry
from symsynth.logic import ast
from symsynth.planning.build import Obtained, Stats
from symsynth.problem import solve, with_costmap, with_task
from symsynth.scene import Scene, load_scene
from symsynth.scene.load import where
from symsynth.solvers import DEFAULT_SOLVER, SOLVERS

DESCRIPTION = """\
Solve the manipulation game of a scene.

The human moves first, then robot and human take turns.  On its turn the
human passes or moves one object, at most k times in a play; the robot
transits, grabs, transfers or drops at the costs of the scene's costmap.
The robot wins as soon as the trace of abstract states satisfies the LTLf
task.  E_p is the min over robot strategies of the max over human
behaviours of the total cost (infinite when the human can keep the robot
from winning).  The task is realizable within budget E iff E_p <= E.
Costs are rounded up to multiples of --resolution, so E_p stays sound.

Output: the verdict, E_p, the game positions the solver represented, the
seconds per phase, then the principal play: the strategy against the
human's worst replies, with each action's cost and the running total.
Without a winning strategy, the counter play shows how the human defeats
the robot.  --json prints realizable, cost_bound (null when infinite),
budget, k, states, seconds, units, resolution, principal_play,
counter_play, scene, task, solver and peak_mb (the process's peak
resident memory, MB).  -o FILE writes the strategy for the
simulator (format symsynth.strategy/1: every position it can reach).

--objective expected | best-effort (with --human-model random:P for
expected) solves the objectives beyond the worst case of semantics §9;
--json then adds objective, human_model, expected_cost (EX, null when
undefined), class and cooperative_cost.

Exit status: 0 when the game is solved, whatever the verdict (read it in
the output, or "realizable" in --json); 2 on bad input."""

def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("solve", help=COMMANDS["solve"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="the scene file (YAML)")
    parser.add_argument("--task", metavar="FORMULA", help="LTLf task instead of the scene's")
    parser.add_argument("--k", type=options.count, metavar="K",
                        help="human moves per play instead of the scene's human.k (>= 0)")
    parser.add_argument("--budget", type=options.exact_amount, metavar="E",
                        help="cost budget: say whether E_p <= E (costmap units, >= 0; compared exactly as "
                             "the decimal written)")
    parser.add_argument("--costmap", type=Path, metavar="FILE",
                        help="costmap file (symsynth.costmap/1) instead of the scene's")
    parser.add_argument("--solver", choices=tuple(SOLVERS), default=DEFAULT_SOLVER,
                        help=f"game solver (default: {DEFAULT_SOLVER})")
    parser.add_argument("--time-limit", type=options.positive, metavar="S",
                        help="seconds of search; if E_p is not proven by then, print a proven interval "
                             "[lower, upper] and a strategy that guarantees the upper end (solvers "
                             "auto, compiled, andor and forward)")
    parser.add_argument("--resolution", type=options.positive, default=1.0, metavar="R",
                        help="round each action's cost up to a multiple of R (default: 1)")
    parser.add_argument("--json", action="store_true", help="print the solution as JSON")
    parser.add_argument("-o", "--output", type=options.output_file, metavar="FILE",
                        help="write the strategy to FILE (symsynth.strategy/1)")
    options.add_costmap_options(parser)
    objective.add_arguments(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.output is not None:  # before the solve, which may take minutes
        check_writable(args.output, "strategy file", inputs=(args.scene, args.costmap))
    request = options.costmap_request(args, progress=not args.json)
    scene = load_scene(args.scene, costmap=args.costmap)
    if args.output is not None and scene.costmap is not None:  # the scene's own costmap file, too
        check_writable(args.output, "strategy file", inputs=(scene.costmap.source,))
    problem = with_costmap(with_task(scene, args.task, "--task", args.scene), request)
    if args.objective != "worst":  # semantics §9
        return objective.run_objective(args, problem)
    scene, task, obtained = problem.scene, problem.task, problem.obtained
    try:
        solution = solve(problem, args.solver, k=args.k, budget=args.budget, resolution=args.resolution,
                         time_limit=args.time_limit)
    except TooManyMoves as error:  # where that k was given
        raise InputError(f"{'--k' if args.k is not None else where(args.scene, ('human', 'k'))}: {error}") from None
    written = None if args.output is None else write_strategy(args.output, scene, task, solution,
                                                              formula=problem.formula)
    if args.json:
        out = solution.to_json() | {"scene": scene.name, "task": task.strip(), "solver": args.solver,
                                    "peak_mb": peak_mb()}
        if scene.costmap is not None and scene.costmap.absent:
            out["absent"] = sorted(scene.costmap.absent)
        if obtained is not None:
            out["costmap"] = costmap_json(obtained)
        if written is not None:
            out["strategy"] = {"file": str(args.output), "positions": written}
        print(json.dumps(out, indent=2))
        return 0
    if obtained is not None:
        costmap_report(obtained)
    _report(scene, task, args.solver, solution, problem.formula)
    if written is not None:
        print(f"\nwrote {args.output} ({written} positions)")
    return 0


# -- the human-readable report -------------------------------------------------

def peak_mb() -> float | None:
    """This process's peak resident set in MB (None where the system does not say)."""
    try:
        import resource
    except ImportError:  # not on Windows
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return round(peak / (1 << 20 if sys.platform == "darwin" else 1 << 10), 1)  # bytes on macOS, KiB elsewhere


def costmap_json(got: Obtained) -> dict:
    out = {"method": got.method, "planner": got.planner, "seed": got.seed, "cached": got.cached,
           "file": None if got.path is None else str(got.path)}
    if got.stats is not None:
        out["seconds"] = dict(got.stats.seconds)  # per phase, summed over the processes that worked
        out["wall_seconds"] = got.stats.wall
        out["cpu_seconds"] = sum(got.stats.seconds.values())
    return out


def costmap_report(got: Obtained) -> None:
    origin = ("reused from the cache" if got.cached else "computed" if got.stats is None else
              f"computed in {elapsed(got.stats)}")
    rules = sum(1 for _ in got.costmap.all_rules())
    count = len(got.costmap.slides)
    slides = f"{count} slide{'s' * (count != 1)}, " if count else ""
    print(f"costmap    {got.method}, planner {got.planner}, seed {got.seed}: "
          f"{len(got.costmap.motions)} motions, {slides}{rules} rules, {origin}")
    if got.path is not None:
        print(f"           {got.path}")


def elapsed(stats: Stats) -> str:
    """'12.3 s', and the work summed over the processes when several worked
    (longer than the wall time: it is not what the user waited)."""
    work = sum(stats.seconds.values())
    if stats.workers <= 1:
        return f"{stats.wall:.1f} s"
    return f"{stats.wall:.1f} s ({work:.1f} s of work on {stats.workers} processes)"


def _report(scene: Scene, task: str, solver: str, solution: Solution, formula: ast.Formula) -> None:
    _report_problem(scene, task, solver, solution)
    print(f"verdict    {_verdict(solution)}")
    _report_value(scene, solution)
    _report_work(scene, solution, formula)
    print()
    _report_play(scene, solution)


def _report_problem(scene: Scene, task: str, solver: str, solution: Solution) -> None:
    """The scene, the task, the human and the solver, as solved."""
    where = f" ({scene.source})" if scene.source else ""
    print(f"scene      {scene.name}{where}")
    print(f"task       {task.strip()}")
    if scene.costmap is not None and scene.costmap.absent:
        print(f"absent     {', '.join(sorted(scene.costmap.absent))}: anchors with no robot configuration "
              "(the costmap's `absent`); no motion goes to or from them")
    print(f"human      k = {solution.k} move{'s' if solution.k != 1 else ''}, human first")
    if "solved_with_k" in solution.stats:
        print(f"           {_horizon(solution)}")
    if "auto" in solution.stats:
        print(f"solver     auto: {solution.stats['auto']}, as {solution.stats['auto_reason']}")
    else:
        print(f"solver     {solver}")
    if "handed_over" in solution.stats:  # the compiled solver under a time limit
        print(f"           {solution.stats['handed_over']}")


def _upper_strategy(solution: Solution) -> str:
    if solution.stats.get("upper_by") == "replanning" and solution.stats.get("replanning_strategy", "σ") != "σ":
        return (f"replanning strategy {solution.stats['replanning_strategy']} (while the human has a move left, "
                "the least-cost plan that puts nothing down on the spare places; after the last move, the "
                "least-cost plan; what it pays at most, proven by asking 'does it pay at most T?' with a proven "
                "bound on what one move raises the plan's cost: solvers/replan_spare.py)")
    if solution.stats.get("upper_by") == "replanning":
        return ("replanning strategy (after each human move, the least-cost plan with no human move "
                "left; what it pays at most, proven by asking 'does it pay at most T?': solvers/replan_budget.py)")
    return "strategy below"


def _report_value(scene: Scene, solution: Solution) -> None:
    """E_p, or the proven interval around it, and what it means."""
    r = solution.resolution
    if not solution.exact:
        lower = solution.lower_bound
        assert lower is not None  # set whenever the answer is not exact (Solution.lower_units)
        print(f"E_p        in [{_num(lower)}, "
              f"{'unknown' if solution.cost_bound is None else _num(solution.cost_bound)}]: "
              "not proven within the time limit")
        print("           lower end proven by refuting every cheaper strategy; "
              + ("no strategy found in time" if solution.cost_bound is None else
                 f"upper end guaranteed by the {_upper_strategy(solution)}, checked against every human reply "
                 f"(gap {_num(solution.cost_bound - lower)})"))
    elif solution.cost_bound is None:
        print("E_p        infinite")
    elif r == 1:
        print(f"E_p        {_num(solution.cost_bound)}")
    else:
        print(f"E_p        {_num(solution.cost_bound)} ({solution.units} units of resolution "
              f"{_num(r)}, each cost rounded up)")
    if solution.cost_bound is not None or not solution.exact:
        print(f"           {_meaning(scene, solution.k)}")


def _report_work(scene: Scene, solution: Solution, formula: ast.Formula) -> None:
    """The positions the solver looked at, its seconds and, for BDDs, their size."""
    if "interchangeable" in solution.stats:
        print(f"positions  {solution.states} canonical game positions (interchangeable objects: "
              f"{solution.stats['interchangeable']}; one position per renaming of them)")
    else:
        print(f"positions  {solution.states} game positions")
        symmetry = Symmetry.of(scene, formula)
        if symmetry is not None:
            print(f"           interchangeable objects {symmetry.describe()}: this solver does not "
                  "reduce by them (the explicit and forward ones do)")
    phases = ", ".join(f"{name} {s:.4f}" for name, s in solution.seconds.items())
    print(f"seconds    {sum(solution.seconds.values()):.4f} ({phases})")
    stats = solution.stats
    if "peak_nodes" in stats:
        rounds = [f"{stats[key]} {label}" for key, label in
                  (("qualitative_iterations", "qualitative"), ("iterations", "cost-bounded"))
                  if key in stats]
        print(f"bdd        {stats['peak_nodes']} peak nodes; fixpoint rounds: {', '.join(rounds)}")


def _report_play(scene: Scene, solution: Solution) -> None:
    """The principal play (or the strategy found in time, or why there is none)."""
    if not solution.exact and solution.cost_bound is None:
        print("No strategy was found within the time limit, and none was ruled out: "
              "give more time for an upper bound.")
    elif not solution.exact:
        print("A play of the strategy found in time, against the human's replies of largest proven cost.")
        _print_play(solution.principal_play, solution.objects)
        print(f"total cost {_num(_total(solution.principal_play))} "
              f"<= {_num(solution.cost_bound)}, the upper end")
    elif solution.cost_bound is None:
        _counter_report(scene, solution)
    elif not solution.principal_play:
        print("The task holds in the initial state: the robot has nothing to do.")
    else:
        print("Principal play: the strategy against the human's worst replies.")
        _print_play(solution.principal_play, solution.objects)
        print(f"total cost {_num(_total(solution.principal_play))} = E_p")


def _meaning(scene: Scene, k: int) -> str:
    """What E_p is, and its unit."""
    unit = ("costmap units: radians of joint travel x per_radian "
            f"({_num(scene.geometry.per_radian)}), grab, drop and the other primitives at their fixed costs"
            if scene.geometry is not None else "the units of the scene's costmap, grab and drop costs")
    return (f"(E_p: the least total cost the robot can guarantee against every human with at most "
            f"{k} move{'s' * (k != 1)}; in {unit})")


def _horizon(solution: Solution) -> str:
    """Why the game with k moves was solved with fewer (game.horizon)."""
    h = solution.stats["solved_with_k"]
    if solution.units is None:
        return f"solved with k = {h}: the human already wins with {h} moves, so with more too"
    return (f"solved with k = {h}: against its strategy a play can use at most "
            f"{solution.stats['moves_usable']} human moves (E_p over the cheapest action), "
            f"so more moves change nothing")


def _verdict(solution: Solution) -> str:
    if not solution.exact:
        budget = None if solution.budget is None else _num(solution.budget)
        if solution.realizable is True:
            return f"realizable within budget {budget} (the strategy found in time guarantees it)"
        if solution.realizable is False:
            return f"not realizable within budget {budget} (E_p is proven above it)"
        if budget is not None:
            return f"undecided within the time limit: budget {budget} lies between the bounds"
        return "undecided within the time limit (E_p bracketed below)"
    if solution.cost_bound is None:
        return "no winning strategy"
    if solution.realizable is None:
        return "solved (no --budget given: realizable within E iff E_p <= E)"
    budget = _num(solution.budget)
    if solution.realizable:
        return f"realizable within budget {budget}"
    return f"not realizable within budget {budget}"


def _print_play(play: tuple[Step, ...], objects: tuple[str, ...]) -> None:
    width = max(len(s.action) for s in play)
    total: float = 0  # (an int while the costs are: exact)
    for n, step in enumerate(play, 1):
        if step.who == "robot":
            total += step.cost
            cost = f"+{_num(step.cost)} = {_num(total)}"
        else:
            cost = ""
        print(f"{n:3}. {step.who:<5}  {step.action:<{width}}  {cost:<14} {format_state(step.state, objects)}")


def _counter_report(scene: Scene, solution: Solution) -> None:
    print("No strategy wins: no robot strategy completes the task against every human behaviour.")
    if solution.counter_play is None:  # lost, proven by a search that builds no counter play
        print(f"Counter play {solution.stats.get('counter_play', 'not built')}.")
        return
    play = solution.counter_play
    if play:
        print("Counter play: a play the robot never wins, with the human's moves that defeat it "
              "(the robot takes its cheapest action).")
        _print_play(play, solution.objects)
    last = play[-1].state if play else initial_state(scene)
    if robot_moves(scene, last):
        print("The play then comes back to a position already visited: "
              "it can go on in circles without the task ever being completed.")
        return
    print(f"The play ends in  {format_state(last, solution.objects)}")
    print("with no action available from this state:")
    for reason in stuck_reasons(scene, last):
        print(f"  - {reason}")


def _total(play: tuple[Step, ...]) -> float:
    """The robot's costs in `play` added up (ints exactly, also past a float's range)."""
    return sum((s.cost for s in play if s.who == "robot"), start=0)


def _num(x: float | Decimal | None) -> str:
    """12.0 -> '12', 7.25 -> '7.25'; an int (exact costs stay ints) or a
    Decimal (a budget as written) in full; None (no bound, no budget) ->
    'infinite'."""
    if x is None:
        return "infinite"
    if isinstance(x, (int, Decimal)):
        return str(x)
    return f"{x:.10g}"
