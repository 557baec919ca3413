"""The bundled scenes executed in the physical world with randomization
(issue 29's targets), next to the kinematic world running the same strategy.

    python bench/physics_bench.py scenes/push.yaml --random 20 --adversarial 5 -o bench/results/physics-push.json

Per scene and human (random: `--random` runs, seeds 0..; adversarial:
`--adversarial` runs): completion rate, runs with every object within the
observation's tolerance at the end, soundness divergences, placement error
(mean, max), mean measured cost next to E_p, and the mean wall seconds of a
run in each world (the ratio physics / kinematic is the simulation's cost).
The costmap comes from the cache or is computed first (not timed).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

from symsynth.execution.observe import POSITION
from symsynth.execution.physics import Randomization
from symsynth.files import atomic_output
from symsynth.problem import CostmapRequest, load_problem, simulate, with_costmap

RANDOMIZE = "friction=0.2,mass=0.2,pose=0.005"


def measure(scene: Path, human: str, runs: int, randomize: str) -> dict:
    problem = with_costmap(load_problem(scene), CostmapRequest("recursive", None, None, True, False))
    row: dict = {"scene": problem.scene.name, "human": human, "runs": runs}
    for world in ("kinematic", "physics"):
        randomization = Randomization.parse(randomize) if world == "physics" else None
        done = simulate(problem, human, runs=runs, seed=0, world=world, randomization=randomization,
                        progress=False)
        rs = done.runs
        errors = [r.placement_error or 0.0 for r in rs]
        row[world] = {
            "completed": sum(r.completed for r in rs),
            "within_tolerance": sum(r.completed and (r.placement_error or 0.0) <= POSITION for r in rs),
            "unsound": sum(not r.sound for r in rs),
            "state_divergences": sum(d.kind == "state" for r in rs for d in r.divergences),
            "placement_error_mean": statistics.fmean(errors), "placement_error_max": max(errors),
            "cost_mean": statistics.fmean(r.cost for r in rs), "cost_max": max(r.cost for r in rs),
            "E_p": done.bound, "seconds_mean": statistics.fmean(r.seconds for r in rs),
            "failures": [{"seed": r.seed, "reason": r.reason} for r in rs if not r.completed],
        }
    row["seconds_ratio"] = row["physics"]["seconds_mean"] / row["kinematic"]["seconds_mean"]
    return row


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--random", type=int, default=20)
    parser.add_argument("--adversarial", type=int, default=5)
    parser.add_argument("--randomize", default=RANDOMIZE)
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args(argv)
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    rows = [measure(args.scene, human, n, args.randomize)
            for human, n in (("random", args.random), ("adversarial", args.adversarial)) if n > 0]
    result = {"commit": commit, "randomize": args.randomize, "rows": rows}
    text = json.dumps(result, indent=2)
    if args.output:
        with atomic_output(args.output, "results") as path:
            Path(path).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
