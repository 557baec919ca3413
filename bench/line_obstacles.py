"""The line task with 0-4 obstacles between the locations (the paper's Fig. 4).

    python bench/line_obstacles.py [--seeds 0 1 2] [--planner NAME] [--roadmap N]
                                   [--out bench/results/line_obstacles.md]

For N = 0..4 (`scenes/line.yaml`, then `scenes/line-obstacles-N.yaml`) and
each roadmap seed: the start-goal and the recursive costmap, each computed
from scratch on its own (roadmaps included, no cache, so each method's time
is its whole abstraction time, as in the paper), then the game solved at the
scene's k by the symbolic solver.  Each row is one seed; the per-N summary
gives the mean over the seeds.  The paper (He et al., RA-L 2019, Sec. VI-B)
ran 10 trials per N with MoveIt on a UR5.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import statistics
import time
from pathlib import Path

from symsynth.game.solution import task_formula
from symsynth.game.solvers import SOLVERS
from symsynth.planning.build import compute_costmap
from symsynth.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
METHODS = ("sg", "recursive")
COUNTS = range(5)


def scene_path(n: int) -> Path:
    return ROOT / "scenes" / ("line.yaml" if n == 0 else f"line-obstacles-{n}.yaml")


def load(n: int, roadmap: int | None):
    scene = load_scene(scene_path(n))
    if roadmap is None:
        return scene
    settings = dataclasses.replace(scene.geometry.planner, roadmap_size=roadmap)
    return dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))


def run(scene, method: str, planner: str | None, seed: int) -> dict:
    start = time.perf_counter()
    costmap, _ = compute_costmap(scene, method, planner, seed, progress=False)
    seconds = time.perf_counter() - start
    solved = dataclasses.replace(scene, costmap=costmap)
    bound = SOLVERS["symbolic"](solved, task_formula(solved, None), k=scene.k).cost_bound
    return {"seconds": seconds, "bound": bound}


def fmt(bound) -> str:
    return "inf" if bound is None else f"{bound:g}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--planner", default=None, help="default: the scene's (ompl-fcl)")
    parser.add_argument("--roadmap", type=int, default=None, help="vertices per mode (default: the scene's, 150)")
    parser.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "line_obstacles.md")
    args = parser.parse_args()

    rows, results = [], {}
    for n in COUNTS:
        scene = load(n, args.roadmap)
        for seed in args.seeds:
            found = {method: run(scene, method, args.planner, seed) for method in METHODS}
            results[n, seed] = found
            sg, rec = found["sg"], found["recursive"]
            rows.append(f"| {n} | {seed} | {sg['seconds']:.1f} | {rec['seconds']:.1f} | {fmt(sg['bound'])} | "
                        f"{fmt(rec['bound'])} | {'yes' if sg['bound'] is not None else 'no'} | "
                        f"{'yes' if rec['bound'] is not None else 'no'} | {_no_dearer(sg, rec)} |")
            print(rows[-1], flush=True)

    summary = []
    for n in COUNTS:
        runs = [results[n, seed] for seed in args.seeds]
        cells = []
        for key in ("seconds", "bound"):
            for method in METHODS:
                values = [r[method][key] for r in runs]
                cells.append(_mean(values, 1 if key == "seconds" else 0))
        summary.append(f"| {n} | " + " | ".join(cells) + " |")

    scene = load(0, args.roadmap)
    settings = scene.geometry.planner
    lines = [
        f"# The line task with 0-4 obstacles ({platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, {time.strftime('%Y-%m-%d')})", "",
        f"`python bench/line_obstacles.py --seeds {' '.join(map(str, args.seeds))}"
        + (f" --roadmap {args.roadmap}" if args.roadmap else "") + "`: planner "
        f"{args.planner or settings.name}, {settings.roadmap_size} roadmap vertices per mode, resolution "
        f"{settings.resolution} rad, k = {scene.k}; each method computed from scratch on its own (roadmaps "
        "included), E_p by the symbolic solver.  N = 0 is `scenes/line.yaml`, N > 0 "
        "`scenes/line-obstacles-N.yaml`.", "",
        "Mean over the seeds (`inf`: no winning strategy in some run):", "",
        "| N | sg s | recursive s | sg E_p | recursive E_p |", "|---:|---:|---:|---:|---:|",
        *summary, "",
        "Every run:", "",
        "| N | seed | sg s | recursive s | sg E_p | recursive E_p | sg wins | recursive wins | recursive <= sg |",
        "|---:|---:|---:|---:|---:|---:|---|---|---|", *rows, ""]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines))
    print("\n".join(lines))
    return 0


def _no_dearer(sg: dict, rec: dict) -> str:
    if rec["bound"] is None:
        return "yes" if sg["bound"] is None else "NO"
    return "yes" if sg["bound"] is None or rec["bound"] <= sg["bound"] else "NO"


def _mean(values: list, digits: int) -> str:
    if any(v is None for v in values):
        return "inf"
    mean = statistics.fmean(values)
    spread = statistics.stdev(values) if len(values) > 1 else 0.0
    return f"{mean:.{digits}f} ± {spread:.{digits}f}" if len(values) > 1 else f"{mean:.{digits}f}"


if __name__ == "__main__":
    raise SystemExit(main())
