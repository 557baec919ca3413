"""Run-time planning, lazy (search, then check the path's edges) against
eager (check every edge as the roadmap grows, then search), side by side.

    python bench/runtime_bench.py [--scene line] [--planner ompl-fcl] [--roadmap 150] [--reps 3]
                                  [--move b 0.48 0.0]

A bundled scene (`scenes/NAME.yaml`), its recursive costmap (roadmap size
`--roadmap`, the scene's planner or `--planner`), and a scripted human who
puts an object down off every place before the robot's first action
(`--move OBJECT X Y`; the default is line with b at (0.48, 0), between l4
and the centre, the case where run-time planning was slowest when the
simulator was reviewed): the robot plans at run time to reach
it and, off every anchor, to carry it and the blocks it finds in its way.  The same runs are played with `motion.runtime_motion` (lazy) and with
the eager method it replaced (`eager_runtime_motion` below, built from the
same pieces), alternating, in one process.  Reported: the time spent inside
run-time planning per run (best and median of `--reps`), the run-time
motions planned, the edge checks each method made, and whether the two
traces (every step's action, state, source, measured cost, and every
run-time path) are identical.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

from symsynth.execution import motion
from symsynth.execution.human import ScriptedHuman
from symsynth.execution.policy import Policy
from symsynth.execution.simulate import Simulator
from symsynth.game.solution import task_formula
from symsynth.game.strategy import strategy_table
from symsynth.solvers.symbolic import solve_symbolic
from symsynth.planning.build import compute_costmaps
from symsynth.planning.methods import RoadmapSearch
from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import PlannerError
from symsynth.planning.registry import planner_class
from symsynth.scene import load_scene
from symsynth.scene.geometry import Pose

ROOT = Path(__file__).resolve().parent.parent


def eager_runtime_motion(world, planner, mode, goal, resolution, seed):
    """Run-time planning as it was: every edge checked while the roadmap grows."""
    start = world.config
    valid, free = motion.world_checks(world, planner, mode, resolution)
    try:
        if tuple(start) == tuple(goal):
            return motion.Motion((tuple(start),), "none")
        if free(start, goal):
            return motion.Motion((tuple(start), tuple(goal)), "runtime")
        if not valid(goal):
            raise motion.MotionFailed(f"the goal configuration collides in the world ({motion._what(world)})")
        roadmap = build_roadmap(planner.limits, valid, free, {"start": start, "goal": goal},
                                motion.RUNTIME_SIZE, seed, resolution)
        search = RoadmapSearch(roadmap, [frozenset()] * len(roadmap.edges), ())
        found = search.best_path(search.vertex("start"), search.vertex("goal"), frozenset())
        if found is None:
            raise PlannerError("start and goal are not connected")
        return motion.Motion(motion._shortcut([search.config(v) for v in found.vertices], free), "runtime")
    except PlannerError as error:
        raise motion.MotionFailed(f"no path in mode {mode}: {error}") from None
    finally:
        world.set_config(start)


class Timed:
    """A run-time planner that keeps its time, its paths, and counts the
    segment checks of the world (`world_checks`' `free`) made inside it."""

    def __init__(self, plan) -> None:
        self.plan, self.seconds, self.paths, self.calls, self.checks = plan, 0.0, [], 0, 0

    def __call__(self, world, planner, mode, goal, resolution, seed):
        clock = time.perf_counter()
        try:
            found = self.plan(world, planner, mode, goal, resolution, seed)
        finally:
            self.seconds += time.perf_counter() - clock
        self.calls += 1
        self.paths.append(found.path)
        return found


def counting_checks(timed: list[Timed]):
    original = motion.world_checks

    def world_checks(world, planner, mode, resolution):
        valid, free = original(world, planner, mode, resolution)

        def counted(a, b):
            timed[0].checks += 1
            return free(a, b)
        return valid, counted
    return world_checks


def setup(scene_name: str, planner_name: str | None, roadmap: int) -> Simulator:
    scene = load_scene(ROOT / "scenes" / f"{scene_name}.yaml")
    planner_name = planner_name or scene.geometry.planner.name
    settings = dataclasses.replace(scene.geometry.planner, roadmap_size=roadmap, name=planner_name)
    scene = dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))
    costmaps, _ = compute_costmaps(scene, ("recursive",), planner_name, progress=False)
    scene = dataclasses.replace(scene, costmap=costmaps["recursive"])
    formula = task_formula(scene, None)
    solution = solve_symbolic(scene, formula)
    table = strategy_table(scene, scene.task, solution)
    policy = Policy(table.positions, table.budgets, table.cost_bound)
    return Simulator(scene, formula, policy, planner_class(planner_name)(scene))


def play(sim: Simulator, plan, script: list[dict]) -> tuple[Timed, list]:
    timed = Timed(plan)
    motion.runtime_motion, world_checks = timed, motion.world_checks
    motion.world_checks = counting_checks([timed])
    try:
        run = sim.run(ScriptedHuman([dict(e) for e in script]))
    finally:
        motion.runtime_motion, motion.world_checks = LAZY, world_checks
    trace = [(s.who, s.action, s.state, s.source, s.measured) for s in run.steps]
    assert run.completed, run.reason
    return timed, trace


LAZY = motion.runtime_motion


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="line")
    parser.add_argument("--planner", default=None, help="default: the scene's")
    parser.add_argument("--roadmap", type=int, default=150, help="costmap roadmap size per mode")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--move", nargs=3, action="append", metavar=("OBJECT", "X", "Y"),
                        help="a scripted move off every place, one per human turn (default: b 0.48 0.0)")
    args = parser.parse_args()
    script = [{"after": 0, "move": o, "to": Pose((float(x), float(y), 0.0))}
              for o, x, y in (args.move or [("b", "0.48", "0.0")])]
    clock = time.perf_counter()
    sim = setup(args.scene, args.planner, args.roadmap)
    print(f"{args.scene}, {sim.scene.geometry.planner.name}, costmap roadmap {args.roadmap}, "
          f"run-time roadmap {motion.RUNTIME_SIZE}, moves {[(e['move'], e['to'].xyz[:2]) for e in script]} "
          f"(set up in {time.perf_counter() - clock:.1f} s)")
    times: dict[str, list[float]] = {"eager": [], "lazy": []}
    results = {}
    for _ in range(args.reps):
        for name, plan in (("eager", eager_runtime_motion), ("lazy", LAZY)):
            timed, trace = play(sim, plan, script)
            times[name].append(timed.seconds)
            if name in results:
                assert results[name][1] == trace and results[name][0].paths == timed.paths, f"{name} not repeatable"
            results[name] = (timed, trace)
    eager, lazy = results["eager"][0], results["lazy"][0]
    print(f"run-time motions per run: {eager.calls} (eager), {lazy.calls} (lazy); "
          f"planned off the straight segment: {sum(len(p) > 2 for p in lazy.paths)}")
    for name in ("eager", "lazy"):
        t = times[name]
        print(f"{name:5}: run-time planning {min(t):.3f} s best, {statistics.median(t):.3f} s median "
              f"of {len(t)}; segment checks in the world {results[name][0].checks}")
    print(f"speed-up (best): {min(times['eager']) / min(times['lazy']):.2f}x")
    same = results["eager"][1] == results["lazy"][1] and eager.paths == lazy.paths
    print(f"traces identical (steps, states, sources, measured costs, run-time paths): {same}")


if __name__ == "__main__":
    main()
