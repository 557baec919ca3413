"""Costmap speed: the paper's scenarios through every planner plugin.

    python bench/planner_bench.py [--planners ompl-fcl pybullet] [--out bench/results/planners.md]

For each planner: the arch with the recursive method and the line with
start-goal and recursive, each computed from scratch (no cache) with the
scene's own settings; where the time goes (anchors, roadmaps, edge checks,
graph searches); E_p at the scene's k.  Then the collision-check rate of the
planner's `contacts()` at random configurations against the raw rate of its
collision library on two boxes, measured side by side in the same run.

Targets (issue 4; the paper took 485 s, 79 s and 450 s with MoveIt on a UR5):
arch recursive under 30 s, line start-goal under 10 s, roadmaps included.

The costmap table alone, as a comparison run: `symsynth bench
experiments/planners.yaml`.
"""

from __future__ import annotations

import argparse
import dataclasses
import platform
import time
from pathlib import Path

import numpy as np

from symsynth.game.solution import task_formula
from symsynth.solvers import SOLVERS
from symsynth.planning.build import compute_costmap
from symsynth.planning.protocol import Mode
from symsynth.planning.registry import planner_class, planner_names
from symsynth.scene import load_scene

ROOT = Path(__file__).resolve().parent.parent
RUNS = (("arch", "recursive", 30.0), ("line", "sg", 10.0), ("line", "recursive", None))


def costmap_run(planner: str, scene_name: str, method: str) -> dict:
    scene = load_scene(ROOT / "scenes" / f"{scene_name}.yaml")
    start = time.perf_counter()
    costmap, stats = compute_costmap(scene, method, planner, progress=False)
    seconds = time.perf_counter() - start
    solved = dataclasses.replace(scene, costmap=costmap)
    bound = SOLVERS["symbolic"](solved, task_formula(solved, None), k=scene.k).cost_bound
    return {"seconds": seconds, "phases": stats.seconds, "edges": stats.edges, "vertices": stats.vertices,
            "rules": stats.rules, "bound": bound, "k": scene.k}


def contact_rate(planner_name: str, seconds: float = 2.0) -> float:
    scene = load_scene(ROOT / "scenes" / "arch.yaml")
    planner = planner_class(planner_name)(scene)
    limits = np.asarray(planner.limits)
    rng = np.random.default_rng(0)
    configs = [tuple(rng.uniform(limits[:, 0], limits[:, 1])) for _ in range(2000)]
    calls, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        planner.contacts(Mode(), configs[calls % len(configs)])
        calls += 1
    return calls / (time.perf_counter() - start)


def raw_fcl_rate(seconds: float = 1.0) -> float:
    import fcl

    a = fcl.CollisionObject(fcl.Box(0.1, 0.1, 0.1), fcl.Transform(np.eye(3), [0, 0, 0]))
    b = fcl.CollisionObject(fcl.Box(0.1, 0.1, 0.1), fcl.Transform(np.eye(3), [0.05, 0, 0]))
    request, calls, start = fcl.CollisionRequest(), 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        fcl.collide(a, b, request, fcl.CollisionResult())
        calls += 1
    return calls / (time.perf_counter() - start)


def raw_bullet_rate(seconds: float = 1.0) -> float:
    from symsynth import bullet

    client = bullet.client()
    box = client.createCollisionShape(bullet.pybullet.GEOM_BOX, halfExtents=[0.05] * 3)
    a = client.createMultiBody(0, box, basePosition=[0, 0, 0])
    b = client.createMultiBody(0, box, basePosition=[0.05, 0, 0])
    calls, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        client.getClosestPoints(a, b, 0.0)
        calls += 1
    rate = calls / (time.perf_counter() - start)
    client.disconnect()
    return rate


RAW = {"ompl-fcl": ("fcl.collide", raw_fcl_rate), "pybullet": ("getClosestPoints", raw_bullet_rate)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--planners", nargs="+", default=list(planner_names()))
    parser.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "planners.md")
    args = parser.parse_args()
    lines = [f"# Costmap benchmark ({platform.processor() or platform.machine()}, "
             f"{time.strftime('%Y-%m-%d')})", "",
             "| planner | scene | method | total s | anchors | roadmaps | edge checks | searches | "
             "vertices | edges | rules | E_p (k) |", "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    verdicts = []
    for planner in args.planners:
        for scene, method, target in RUNS:
            r = costmap_run(planner, scene, method)
            p = r["phases"]
            bound = "inf" if r["bound"] is None else f"{r['bound']:g}"
            lines.append(f"| {planner} | {scene} | {method} | {r['seconds']:.1f} | {p['anchors']:.1f} | "
                         f"{p['roadmaps']:.1f} | {p['edge checks']:.1f} | {p['searches']:.2f} | "
                         f"{r['vertices']} | {r['edges']} | {r['rules']} | {bound} ({r['k']}) |")
            print(lines[-1], flush=True)
            if target is not None:
                ok = r["seconds"] < target
                verdicts.append(f"{'PASS' if ok else 'FAIL'} {planner} {scene} {method}: "
                                f"{r['seconds']:.1f} s (target < {target:g} s)")
    lines += ["", "| planner | contacts() per s (random configurations, arch) | raw check | raw per s | ratio |",
              "|---|---:|---|---:|---:|"]
    for planner in args.planners:
        rate = contact_rate(planner)
        name, raw = RAW.get(planner, ("-", None))
        raw_rate = raw() if raw else float("nan")
        lines.append(f"| {planner} | {rate:,.0f} | {name} (two boxes) | {raw_rate:,.0f} | "
                     f"{raw_rate / rate:.0f}x |")
        print(lines[-1], flush=True)
    lines += [""] + [f"- {v}" for v in verdicts]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(verdicts))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
