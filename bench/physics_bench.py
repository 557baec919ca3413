"""The bundled scenes executed in the physical world with randomization
(issue 29's targets), next to the kinematic world running the same strategy.

    python bench/physics_bench.py scenes/push.yaml --random 20 --adversarial 5 -o bench/results/physics-push.json

Per scene and human (random: `--random` runs, seeds 0..; adversarial:
`--adversarial` runs), each world measured by `symsynth.bench.worlds.measured`
(the `symsynth bench` worlds axis's measurements): completed, within the
observation's tolerance at the end, soundness bugs, state divergences,
placement error, measured cost next to E_p, wall and processor seconds of a
run; and the ratios of the physical run's seconds to the kinematic one's (the kinematic
runs first, then the physical ones: the load average before and after is
recorded).  The costmap comes from the cache or is computed first (not
timed).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

from symsynth.bench.worlds import RANDOMIZE, measured, ratio
from symsynth.execution.physics import Randomization
from symsynth.files import atomic_output
from symsynth.problem import CostmapRequest, load_problem, simulate, with_costmap


def measure(scene: Path, human: str, runs: int, randomize: str) -> dict:
    problem = with_costmap(load_problem(scene), CostmapRequest("recursive", None, None, True, False))
    done, bound = {}, None
    for world in ("kinematic", "physics"):
        randomization = Randomization.parse(randomize) if world == "physics" else None
        simulation = simulate(problem, human, runs=runs, seed=0, world=world, randomization=randomization,
                              progress=False)
        done[world], bound = simulation.runs, simulation.bound
    row: dict = {"scene": problem.scene.name, "human": human, "runs": runs, "E_p": bound}
    row |= {world: measured(found) for world, found in done.items()}
    row["seconds_ratio"] = ratio(row["physics"], row["kinematic"])
    row["cpu_seconds_ratio"] = ratio(row["physics"], row["kinematic"], "cpu_seconds_simulation")
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
    load = os.getloadavg()
    rows = [measure(args.scene, human, n, args.randomize)
            for human, n in (("random", args.random), ("adversarial", args.adversarial)) if n > 0]
    result = {"commit": commit, "randomize": args.randomize, "load_before": load, "load_after": os.getloadavg(),
              "rows": rows}
    text = json.dumps(result, indent=2)
    if args.output:
        with atomic_output(args.output, "results") as path:
            Path(path).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
