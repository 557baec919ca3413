"""Issue 32: the replanning strategy σ's bound asked as a question
(symsynth/solvers/replan_budget.py), on the pattern family (distinct blocks):

    python bench/replan_budget.py within N M K T [T ...]   "B_k(start) <= T?" in turn, one process
    python bench/replan_budget.py repairing N M K T [T ...]   the same for σ', the strategy that
                                                           may repair (solvers/replan_repair.py)
    python bench/replan_budget.py spare N M K T [T ...]    the same for σ_Z, the spare-places
                                                           strategy (solvers/replan_spare.py), with
                                                           solvers/rise.py's bound R; --no-children,
                                                           --no-class: without that shortcut
    python bench/replan_budget.py least N M K LO HI        B_k(start) exactly, given LO <= B_k <= HI
    python bench/replan_budget.py interval N M K S         solve_andor(time_limit=S): the certified
                                                           interval, the upper end from σ when the
                                                           search proves none lower

One line of JSON per question or run, with the seconds and the peak memory of the process.
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
from symsynth.solvers.packed import search as sk  # noqa: E402
from symsynth.solvers.replan_budget import BudgetedBound  # noqa: E402
from symsynth.solvers.replan_repair import RepairingBound  # noqa: E402
from symsynth.solvers.replan_spare import SpareBound  # noqa: E402
from symsynth.solvers.rise import rise_bounds  # noqa: E402


def _peak_mb() -> float:
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, 1)


def _counts(bound: BudgetedBound) -> dict:
    mine = {"repaired, replanned at h >= 2": [bound.repaired, bound.replanned]} if isinstance(bound, RepairingBound) else {}
    if isinstance(bound, SpareBound):
        mine = {"children at h = 1 certified by R, exact": bound.children.tolist(),
                "replies at h = 1 by their class": bound.by_class, "V_0 (the scene's) found": len(bound._values0)}
    return mine | {"V_0 found": len(bound._values), "replies settled": bound.settled, "nodes": bound.memo.count,
            "search steps": int(bound.memo.st[sk.ST_CALLS]),
            "by memo, repair, plan followed, search": bound.counts.tolist(), "peak_mb": _peak_mb()}


def within(n: int, m: int, k: int, targets: list[int], mode: str = "within", off: tuple[str, ...] = ()) -> None:
    scene = pattern_scene(n, m, k, 0)
    formula = task_formula(scene, None)
    clock = time.perf_counter()
    if mode == "spare":
        rises = rise_bounds(scene, formula)
        if rises is None:
            raise SystemExit("no spare places (or no rise bound) in this scene")
        bound: BudgetedBound = SpareBound(scene, formula, k, rises, shortcut="--no-children" not in off,
                                          by_class="--no-class" not in off)
        told = {"Z": rises.spares, "R other, c5": [rises.other, rises.c5]}
    else:
        bound, told = (RepairingBound if mode == "repairing" else BudgetedBound)(scene, formula, k), {}
    print(json.dumps({"size": f"{n}x{m}", "k": k, "V_0 (σ's plans' game)": bound.v0} | told
                     | {"seconds": round(time.perf_counter() - clock, 2)}, ensure_ascii=False), flush=True)
    for target in targets:
        clock = time.perf_counter()
        answer = bound.within(target)
        print(json.dumps({"T": target, "B_k <= T": answer, "seconds": round(time.perf_counter() - clock, 2)}
                         | _counts(bound)), flush=True)


def least(n: int, m: int, k: int, lo: int, hi: int) -> None:
    scene = pattern_scene(n, m, k, 0)
    clock = time.perf_counter()
    bound = BudgetedBound(scene, task_formula(scene, None), k)
    value = bound.least(lo, hi)
    print(json.dumps({"size": f"{n}x{m}", "k": k, "V_0": bound.v0, "B_k": value,
                      "seconds": round(time.perf_counter() - clock, 2)} | _counts(bound)), flush=True)


def interval(n: int, m: int, k: int, limit: float) -> None:
    scene = pattern_scene(n, m, k, 0)
    clock = time.perf_counter()
    found = solve_andor(scene, k=k, time_limit=limit)
    lower = found.units if found.exact else found.lower_units
    print(json.dumps({"size": f"{n}x{m}", "k": k, "limit": limit, "lower": lower, "upper": found.units,
                      "ratio": None if found.units is None or not lower else round(found.units / lower, 4),
                      "exact": found.exact, "upper_by": found.stats.get("upper_by", "search"),
                      "replanning_seconds": found.stats.get("replanning_seconds"),
                      "seconds": round(time.perf_counter() - clock, 1), "peak_mb": _peak_mb()}), flush=True)


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    prepare()
    mode, n, m, k, rest = argv[0], int(argv[1]), int(argv[2]), int(argv[3]), argv[4:]
    if mode in ("within", "repairing", "spare"):
        within(n, m, k, [int(a) for a in rest if not a.startswith("--")], mode,
               tuple(a for a in rest if a.startswith("--")))
    elif mode == "least":
        least(n, m, k, int(rest[0]), int(rest[1]))
    else:
        interval(n, m, k, float(rest[0]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
