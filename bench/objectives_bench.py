"""The objectives of semantics §9 against the worst-case solve, side by side
in one process, on the game family (bench/gamefamily.py).

    python bench/objectives_bench.py 5x7 [--colours C] [--seed S] [--P 0.3]
    python bench/objectives_bench.py scenes [--P 0.3]

Prints, for `pattern_scene(n, m, k=3, seed=S)` (with `colours=C`: the
sorting variant), or for the bundled physical scenes (the arch and the line with
their cached recursive costmaps, at their k), the compiled worst-case solve,
best effort and expected (B = E_p; on the scenes also 1.5 E_p; random(P)) with their
seconds and the ratios to the worst-case solve.  The kernels of all three
are compiled (or loaded) before any clock starts.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from fractions import Fraction
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.gamefamily import pattern_scene  # noqa: E402
from bench.provenance import commit  # noqa: E402
from symsynth.game.human_model import RandomModel  # noqa: E402
from symsynth.solvers.compiled import compile_kernels, solve_compiled  # noqa: E402
from symsynth.solvers.objectives import prepare, solve_objective  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("size", help="NxM: blocks x locations; or 'scenes': the arch and the line")
    parser.add_argument("--colours", type=int, default=None)
    parser.add_argument("--seed", type=int, default=0, help="the game family's seed (its layout and costs)")
    parser.add_argument("--P", default="0.3")
    args = parser.parse_args()
    compile_kernels()
    prepare()
    print(f"commit {commit()}, load {os.getloadavg()[0]:.2f}")
    if args.size == "scenes":
        from bench.objectives_showcase import problem

        for name in ("arch", "line"):
            p = problem(name, "recursive")
            print(f"{name} (recursive costmap, k = {p.scene.k})")
            side_by_side(p.scene, p.formula, args.P, (1.0, 1.5))
    else:
        n, m = map(int, args.size.split("x"))
        print(f"pattern_scene({n}, {m}, k=3, seed={args.seed}, colours={args.colours})")
        side_by_side(pattern_scene(n, m, k=3, seed=args.seed, colours=args.colours), None, args.P, (1.0,))
    print(f"load at end {os.getloadavg()[0]:.2f}")


def side_by_side(scene, formula, P: str, factors: tuple[float, ...]) -> None:
    clock = time.perf_counter()
    worst = solve_compiled(scene, formula)
    tw = time.perf_counter() - clock
    print(f"worst        E_p {worst.cost_bound}, {worst.states} positions, {tw:.3f} s {worst.seconds}")
    clock = time.perf_counter()
    best = solve_objective(scene, formula, objective="best-effort", solver="compiled")
    tb = time.perf_counter() - clock
    print(f"best-effort  {best.position_class}, C {best.cooperative_cost}, {tb:.3f} s ({tb / tw:.2f}x) {best.seconds}")
    for factor in factors:
        budget = None if factor == 1.0 or worst.cost_bound is None else round(worst.cost_bound * factor, 6)
        clock = time.perf_counter()
        exp = solve_objective(scene, formula, objective="expected", model=RandomModel(Fraction(P)),
                              solver="compiled", budget=budget)
        te = time.perf_counter() - clock
        print(f"expected     B {exp.budget}: EX {exp.expected_cost}, {exp.stats}, {te:.3f} s ({te / tw:.2f}x) "
              f"{exp.seconds}")


if __name__ == "__main__":
    main()
