"""Issue 32's interval on the pattern family, with the replanning strategy's bound
(symsynth/solvers/replan.py):

    python bench/replan_interval.py exact N M K        σ's exact bound B_k (every level enumerated)
                                                       against E_p from `solve_andor` without a limit
    python bench/replan_interval.py interval N M K S   `solve_andor(time_limit=S)` (the certified
                                                       interval, the replanning bound inside it when
                                                       it is proven in time), then the conditional
                                                       bound: one level enumerated and D+ per move
                                                       below (bench/replan_repair.py; its case C5 is
                                                       not proven, so this one is not certified)

One line of JSON per run, with the seconds and peak memory of the process.
"""

from __future__ import annotations

import json
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers.andor import prepare, solve_andor  # noqa: E402
from symsynth.solvers.replan import replanning_bound  # noqa: E402


def _peak_mb() -> float:
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)


def exact(n: int, m: int, k: int) -> dict:
    scene = pattern_scene(n, m, k, 0)
    clock = time.perf_counter()
    bound = replanning_bound(scene, task_formula(scene, None), k)
    took = time.perf_counter() - clock
    clock = time.perf_counter()
    e_p = solve_andor(scene, k=k).units
    return {"size": f"{n}x{m}", "k": k, "E_p": e_p, "V_0": bound.v0, "B_k": bound.upper,
            "above": round(bound.upper / e_p - 1, 4), "questions": bound.questions, "seconds": round(took, 1),
            "andor_seconds": round(time.perf_counter() - clock, 1), "peak_mb": _peak_mb()}


def interval(n: int, m: int, k: int, limit: float) -> dict:
    from replan_repair import d_plus

    scene = pattern_scene(n, m, k, 0)
    clock = time.perf_counter()
    found = solve_andor(scene, k=k, time_limit=limit)
    took = time.perf_counter() - clock
    lower = found.units if found.exact else found.lower_units
    out = {"size": f"{n}x{m}", "k": k, "limit": limit, "lower": lower, "upper": found.units,
           "exact": found.exact, "seconds": round(took, 1), "upper_by": found.stats.get("upper_by", "search"),
           "replanning_bound": found.stats.get("replanning_bound")}
    clock = time.perf_counter()
    tail, _ = d_plus(scene)
    out["D+"] = tail
    out["D+_seconds"] = round(time.perf_counter() - clock, 1)
    bound = replanning_bound(scene, task_formula(scene, None), k, levels=1, tail=tail)
    out |= {"V_0": bound.v0, "first_rise": bound.first_rise, "conditional_upper": bound.upper,
            "conditional_seconds": round(bound.seconds, 1),
            "conditional_ratio": round(bound.upper / lower, 4), "peak_mb": _peak_mb()}
    return out


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    prepare()
    mode, n, m, k = argv[0], int(argv[1]), int(argv[2]), int(argv[3])
    result = exact(n, m, k) if mode == "exact" else interval(n, m, k, float(argv[4]))
    print(json.dumps(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
