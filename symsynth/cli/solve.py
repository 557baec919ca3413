"""`symsynth solve`: solve a scene's manipulation game and show why the bound is what it is."""

from __future__ import annotations

import argparse
import json
import sys
import math
from pathlib import Path

from symsynth.cli import options
from symsynth.cli.options import check_writable
from symsynth.game.abstraction import Move, State, costmap_of, initial_state, motions, robot_moves, slides
from symsynth.game.solution import Solution, Step
from symsynth.game.strategy import format_state, write_strategy
from symsynth.game.symmetry import Symmetry
from symsynth.logic import ast
from symsynth.planning.build import Obtained
from symsynth.planning.methods import METHODS
from symsynth.problem import CostmapRequest, solve, with_costmap, with_task
from symsynth.scene import Scene, load_scene
from symsynth.scene.model import ELSE
from symsynth.solvers import DEFAULT_SOLVER, SOLVERS

HELP = "solve a scene's game: the cost the robot can guarantee against the human"
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

Exit status: 0 when the game is solved, whatever the verdict (read it in
the output, or "realizable" in --json); 2 on bad input."""

_MAX_REASONS = 3  # missing motions listed per action when the robot is stuck


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("solve", help=HELP, description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="the scene file (YAML)")
    parser.add_argument("--task", metavar="FORMULA", help="LTLf task instead of the scene's")
    parser.add_argument("--k", type=options.count, metavar="K",
                        help="human moves per play instead of the scene's human.k (>= 0)")
    parser.add_argument("--budget", type=options.amount, metavar="E",
                        help="cost budget: say whether E_p <= E (costmap units, >= 0)")
    parser.add_argument("--costmap", type=Path, metavar="FILE",
                        help="costmap file (symsynth.costmap/1) instead of the scene's")
    parser.add_argument("--method", choices=tuple(METHODS), default="recursive",
                        help="physical scenes: costmap method, sg (Alg. 2) or recursive (Alg. 3; default)")
    parser.add_argument("--planner", metavar="NAME",
                        help="physical scenes: planner plugin (default: the scene's planner.name)")
    parser.add_argument("--seed", type=options.count, metavar="S",
                        help="physical scenes: roadmap seed (default: the scene's planner.seed)")
    parser.add_argument("--no-cache", action="store_true",
                        help="physical scenes: compute the costmap even if a cached one exists")
    parser.add_argument("--solver", choices=tuple(SOLVERS), default=DEFAULT_SOLVER,
                        help=f"game solver (default: {DEFAULT_SOLVER})")
    parser.add_argument("--time-limit", type=options.positive, metavar="S",
                        help="seconds of search; if E_p is not proven by then, print a proven interval "
                             "[lower, upper] and a strategy that guarantees the upper end (solvers "
                             "forward and auto)")
    parser.add_argument("--resolution", type=options.positive, default=1.0, metavar="R",
                        help="round each action's cost up to a multiple of R (default: 1)")
    parser.add_argument("--json", action="store_true", help="print the solution as JSON")
    parser.add_argument("-o", "--output", type=Path, metavar="FILE",
                        help="write the strategy to FILE (symsynth.strategy/1)")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.output is not None:  # before the solve, which may take minutes
        check_writable(args.output, "strategy file")
    request = CostmapRequest(args.method, args.planner, args.seed, not args.no_cache, progress=not args.json)
    scene = load_scene(args.scene, costmap=args.costmap)
    problem = with_costmap(with_task(scene, args.task, "--task", args.scene), request)
    scene, task, obtained = problem.scene, problem.task, problem.obtained
    solution = solve(problem, args.solver, k=args.k, budget=args.budget, resolution=args.resolution,
                     time_limit=args.time_limit)
    written = None if args.output is None else write_strategy(args.output, scene, task, solution)
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
        out["seconds"] = dict(got.stats.seconds)
    return out


def costmap_report(got: Obtained) -> None:
    origin = ("reused from the cache" if got.cached else "computed" if got.stats is None else
              f"computed in {sum(got.stats.seconds.values()):.1f} s")
    rules = sum(1 for _ in got.costmap.all_rules())
    count = len(got.costmap.slides)
    slides = f"{count} slide{'s' * (count != 1)}, " if count else ""
    print(f"costmap    {got.method}, planner {got.planner}, seed {got.seed}: "
          f"{len(got.costmap.motions)} motions, {slides}{rules} rules, {origin}")
    if got.path is not None:
        print(f"           {got.path}")


def _report(scene: Scene, task: str, solver: str, solution: Solution, formula: ast.Formula) -> None:
    where = f" ({scene.source})" if scene.source else ""
    r = solution.resolution
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
    print(f"verdict    {_verdict(solution)}")
    if not solution.exact:
        lower = solution.lower_bound
        assert lower is not None  # set whenever the answer is not exact (Solution.lower_units)
        print(f"E_p        in [{_num(lower)}, "
              f"{'unknown' if solution.cost_bound is None else _num(solution.cost_bound)}]: "
              "not proven within the time limit")
        print("           lower end proven by refuting every cheaper strategy; "
              + ("no strategy found in time" if solution.cost_bound is None else
                 f"upper end guaranteed by the strategy below, checked against every human reply "
                 f"(gap {_num(solution.cost_bound - lower)})"))
    elif solution.cost_bound is None:
        print("E_p        infinite")
    elif r == 1:
        print(f"E_p        {_num(solution.cost_bound)}")
    else:
        print(f"E_p        {_num(solution.cost_bound)} ({solution.units} units of resolution "
              f"{_num(r)}, each cost rounded up)")
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
    print()
    if not solution.exact and solution.cost_bound is None:
        print("No strategy was found within the time limit, and none was ruled out: "
              "give more time for an upper bound.")
    elif not solution.exact:
        print("A play of the strategy found in time, against the human's replies of largest proven cost.")
        _print_play(solution.principal_play, solution.objects)
        print(f"total cost {_num(sum(s.cost for s in solution.principal_play))} "
              f"<= {_num(solution.cost_bound)}, the upper end")
    elif solution.cost_bound is None:
        _counter_report(scene, solution)
    elif not solution.principal_play:
        print("The task holds in the initial state: the robot has nothing to do.")
    else:
        print("Principal play: the strategy against the human's worst replies.")
        _print_play(solution.principal_play, solution.objects)
        print(f"total cost {_num(sum(s.cost for s in solution.principal_play))} = E_p")


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
    total = 0.0
    for n, step in enumerate(play, 1):
        if step.who == "robot":
            total += step.cost
            cost = f"+{_num(step.cost)} = {_num(total)}"
        else:
            cost = ""
        print(f"{n:3}. {step.who:<5}  {step.action:<{width}}  {cost:<14} {format_state(step.state, objects)}")


def _counter_report(scene: Scene, solution: Solution) -> None:
    play = solution.counter_play or ()
    print("No strategy wins: no robot strategy completes the task against every human behaviour.")
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


def stuck_reasons(scene: Scene, v: State) -> list[str]:
    """Why each action the robot could take in `v` is unavailable (semantics §4, §5)."""
    held = v.held()
    wanted = motions(scene, v)
    reasons: list[str] = []
    if held is None and not wanted:
        reasons.append("there is no object to reach")
    if held is not None:
        o = scene.object_names[held]
        if v.ee == ELSE:  # with ee at a (free) location, drop would be available
            reasons.append(f"drop({o},...): {o} is held but not aligned with a location")
        if not wanted:
            reasons.append(f"transfer: {o} is held and every other location is occupied")
    if held is None and isinstance(v.ee, tuple) and v.ee[1] in scene.contacts:
        reasons += _why_no_slide(scene, v)
    return reasons + [_why(scene, m) for m in wanted]


def _why_no_slide(scene: Scene, v: State) -> list[str]:
    """Why the robot, at contact `a` of `o`, cannot slide `o` to each place
    it cannot (semantics §4b); nothing for the slides it can make."""
    if not isinstance(v.ee, tuple):  # the hand is at no contact
        return []
    o, a = v.ee
    start = v.at[scene.object_names.index(o)]
    name = f"slide({o},{a},...)"
    if start not in scene.locations:
        return [f"{name}: {o} is at {ELSE}, and only an object at a location of interest is slid"]
    targets = [l for l in scene.locations if l not in v.at]
    if not targets:
        return [f"{name}: every other location is occupied"]
    available = {m.location for m in slides(scene, v) if m.cost != math.inf}
    unruled = [l for l in targets if not costmap_of(scene).slide_rules(a, start, l)]
    blocked = [l for l in targets if l not in unruled and l not in available]
    reasons = []
    if unruled:
        reasons.append(f"{name}: the costmap has no slide rule for {a} from {start} to {', '.join(unruled)}")
    if blocked:
        reasons.append(f"{name}: the costmap's slide rules for {a} from {start} to {', '.join(blocked)} "
                       "all need a location free that is occupied")
    return reasons


def _why(scene: Scene, m: Move) -> str:
    action, mode = m.action, m.mode
    if mode is None:  # motions() gives transits and transfers, which have a mode
        raise ValueError(f"{action} is no motion")
    if not m.goals:
        return f"{action}: the object is at {ELSE} and the scene has no else_samples"
    if not m.starts:
        return f"{action}: the hand is at {ELSE} and the scene has no else_samples"
    missing = [f"{s} -> {t}" for s in m.starts for t in m.goals
               if s != t and not costmap_of(scene).rules(mode, s, t)]
    if not missing:
        return (f"{action}: the costmap's rules for {mode} to {', '.join(m.goals)} all need "
                "a location free that is occupied")
    more = f" (and {len(missing) - _MAX_REASONS} more)" if len(missing) > _MAX_REASONS else ""
    return (f"{action}: the costmap has no motion for mode {mode} from "
            f"{', '.join(missing[:_MAX_REASONS])}{more}")


def _num(x: float | None) -> str:
    """12.0 -> '12', 7.25 -> '7.25'; None (no bound, no budget) -> 'infinite'."""
    return "infinite" if x is None else f"{x:.10g}"
