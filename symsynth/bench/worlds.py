"""How a strategy fares in a world: the measurements of the `worlds` axis
(`worker.in_world`, one run per seed) and of `bench/physics_bench.py`
(many runs of one scene, both worlds side by side), made by one function.

`measured(runs)`: how many completed, how many also ended with every
object within the observation's tolerance of the place the abstraction
puts it at, soundness bugs, `state` divergences, the placement error
(mean, max, metres), the measured cost (mean, max) and the wall and
processor seconds of a run (mean).  `ratio(physics, kinematic)`: the
physical runs' mean seconds over the kinematic ones' of the same strategy.
"""

from __future__ import annotations

import statistics
from collections.abc import Sequence
from typing import Any

#: The randomization of a run in the physical world.
RANDOMIZE = "friction=0.2,mass=0.2,pose=0.005"


def measured(runs: Sequence[Any]) -> dict[str, Any]:
    """The measurements of `runs` (`execution.runs.Run`s) together."""
    from symsynth.execution.observe import POSITION

    errors = [r.placement_error or 0.0 for r in runs]
    return {
        "runs": len(runs),
        "completed": sum(r.completed for r in runs),
        "within_tolerance": sum(r.completed and (r.placement_error or 0.0) <= POSITION for r in runs),
        "soundness_bugs": sum(bool(d.soundness) for r in runs for d in r.divergences),
        "state_divergences": sum(d.kind == "state" for r in runs for d in r.divergences),
        "placement_error": statistics.fmean(errors), "placement_error_max": max(errors),
        "cost": statistics.fmean(r.cost for r in runs), "cost_max": max(r.cost for r in runs),
        "seconds_simulation": statistics.fmean(r.seconds for r in runs),
        "cpu_seconds_simulation": statistics.fmean(r.cpu_seconds for r in runs),
        "failures": [{"seed": r.seed, "reason": r.reason} for r in runs if not r.completed],
    }


def ratio(physics: dict[str, Any], kinematic: dict[str, Any], key: str = "seconds_simulation") -> float:
    """Physical over kinematic mean seconds of a run (`measured` rows): wall
    seconds, or `cpu_seconds_simulation` (the processor's, which other
    jobs on a shared machine do not stretch)."""
    return physics[key] / kinematic[key]
