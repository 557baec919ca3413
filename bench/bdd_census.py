"""Where the symbolic solver's BDD nodes are: state levels or budget levels.

    python bench/bdd_census.py N M [--colours C] [--k K] [--sift]

Solves the pattern family's scene (bench/gamefamily.py; `--colours 2`, the
sorting variant, solves on the class encoding) with the cost-bounded
attractor, then counts the nodes of its final sets, of the robot relation,
and of one mid-run frontier, its budget shifted, its unquantified product
with the relation and the image, each split into nodes labelled by state,
DFA or h bits and nodes labelled by cost or budget bits (the bottom of the
order).  With `--sift`, CUDD's sifting then reorders every live node and
the sizes are printed again.

Why it matters: X(v, e) = [e >= V(v)], so below each node at a state level
the budget part is a function of the value alone, and an ADD/MTBDD holding
V with values as terminals has exactly X's state-level nodes; the budget
levels are what such a representation could save (bench/results/game-notes.md).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gamefamily import pattern_scene  # noqa: E402


def census(u, low_levels):
    """(nodes at state/DFA/h levels, nodes at cost/budget levels) of `u`."""
    seen, high, low = set(), 0, 0
    stack = [u]
    while stack:
        f = stack.pop()
        if f.var is None:
            continue
        regular = ~f if f.negated else f
        if int(regular) in seen:
            continue
        seen.add(int(regular))
        if f.level in low_levels:
            low += 1
        else:
            high += 1
        stack += [f.low, f.high]
    return high, low


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("n", type=int)
    p.add_argument("m", type=int)
    p.add_argument("--colours", type=int, default=0, help="the sorting variant (default 0: distinct blocks)")
    p.add_argument("--k", type=int, default=3)
    p.add_argument("--sift", action="store_true", help="also reorder by sifting and count again")
    args = p.parse_args(argv)

    from symsynth.automata.bdd import and_exists
    from symsynth.game.solution import task_formula
    from symsynth.game.symmetry import interchangeable
    from symsynth.solvers.bdd.arena import Arena
    from symsynth.solvers.bdd.classes import ClassArena
    from symsynth.solvers.bdd.fixpoint import attractor

    scene = pattern_scene(args.n, args.m, k=args.k, colours=args.colours or None)
    formula = task_formula(scene, None)
    classes = interchangeable(scene, formula)
    arena = ClassArena(scene, formula, args.k, 1.0, classes) if classes else Arena(scene, formula, args.k, 1.0)
    bdd = arena.bdd
    qualitative = attractor(arena, with_costs=False)
    arena.declare_budget((qualitative.action_bound * arena.max_units).bit_length())
    clock = time.process_time()
    solved = attractor(arena, with_costs=True)
    print(f"{args.n} x {args.m}, k = {args.k}, {'classes' if classes else 'objects'}: attractor "
          f"{time.process_time() - clock:.1f} CPU s, rounds per layer {solved.rounds}")
    low_levels = {bdd.level_of_var(v) for v in set(arena.c.bits) | set(arena.budget().bits)}
    relation = bdd.false
    for rel in arena.robot.values():
        relation |= rel
    wins = solved.wins
    frontier = wins[len(wins) // 2] & ~wins[len(wins) // 2 - 1]
    shifted = bdd.let(arena.robot_substitution(True), frontier) & arena.affordable()
    product = relation & shifted
    image = and_exists(bdd, relation, shifted, set(arena.next_bits) | set(arena.c.bits))
    rows = [("X, final (every h)", solved.win), ("R, final", solved.robot_win), ("robot relation", relation),
            ("a mid-run frontier", frontier), ("  its budget shifted", shifted),
            ("  product with the relation", product), ("  image", image)]
    print(f"{'set':<30} {'nodes':>10} {'state levels':>13} {'budget levels':>14}")
    for name, u in rows:
        high, low = census(u, low_levels)
        print(f"{name:<30} {len(u):>10,} {high:>13,} {low:>14,}")
    if args.sift:
        import dd.cudd
        clock = time.process_time()
        dd.cudd.reorder(bdd)
        print(f"after sifting every live node ({time.process_time() - clock:.1f} CPU s): "
              + ", ".join(f"{name.strip()} {len(u):,}" for name, u in rows[:3]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
