"""Issue 32: what the hybrid strategy τ_j pays (symsynth/solvers/hybrid.py) on
the pattern family, asked as "W_j <= b?" after the AND-OR search's rounds from
below:

    python bench/hybrid_bound.py N M K LOWER J [B ...]

runs the rounds on the k-move game until the lower end reaches LOWER (or 240 s
pass), then asks τ_J's question at each budget B (default LOWER .. LOWER + 8,
stopping at the first yes), each with a 900 s deadline.  One line per
question: the answer, its seconds, σ's leaf questions and the process's peak
memory.
"""

from __future__ import annotations

import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.abstraction import initial_state  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers import andor  # noqa: E402
from symsynth.solvers.hybrid import Hybrid  # noqa: E402
from symsynth.solvers.packed import search as sk  # noqa: E402
from symsynth.solvers.packed.lower import BoundTables  # noqa: E402
from symsynth.solvers.packed.tables import Tables  # noqa: E402
from symsynth.solvers.replan_budget import BudgetedBound, Deadline  # noqa: E402

ROUNDS_SECONDS, QUESTION_SECONDS = 240, 900


def rounds(memo: andor.Memo, start: int, lower: int) -> None:
    """The search's rounds from below until lo(start) >= lower (or the time is up)."""
    clock = time.perf_counter()
    while memo.lo_h(start) < lower:
        b = memo.lo_h(start)
        if memo.ask(start, b, False, clock + ROUNDS_SECONDS) is not False:
            return
        memo.rec[start, sk.LO_H] = max(memo.lo_h(start), b + 1)


def searched(n: int, m: int, k: int, lower: int):
    """(scene, formula, memo, start node) of the pattern game after the rounds to `lower`,
    the rounds' end printed."""
    andor.prepare()
    scene = pattern_scene(n, m, k)
    formula = task_formula(scene, None)
    clock = time.perf_counter()
    tables = Tables(scene, formula, 1.0, None, k)
    memo = andor.Memo(tables, BoundTables(tables, formula), k)
    x = tables.pack(initial_state(scene))
    start = memo.node(memo.key2(x, tables.step(tables.dfa_index[tables.dfa.initial], x), k))
    rounds(memo, start, lower)
    print(f"{n} x {m} x k = {k}: rounds to lo {memo.lo_h(start)} in {time.perf_counter() - clock:.1f} s; "
          f"memo {memo.count} nodes", flush=True)
    return scene, formula, memo, start


def main(argv: list[str]) -> None:
    n, m, k, lower, j = map(int, argv[:5])
    budgets = [int(b) for b in argv[5:]] or list(range(lower, lower + 9))
    scene, formula, memo, start = searched(n, m, k, lower)
    hybrid = Hybrid(memo, BudgetedBound(scene, formula, k), j, start)
    for b in budgets:
        clock = time.perf_counter()
        try:
            ok: bool | None = hybrid.within(b, clock + QUESTION_SECONDS)
        except Deadline:
            ok = None
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
        print(f"W_{j} <= {b}? {ok} in {time.perf_counter() - clock:.1f} s; {hybrid.leaves} leaves asked, "
              f"{len(hybrid.leaf)} certified; peak {peak} MB", flush=True)
        if ok:
            return


if __name__ == "__main__":
    main(sys.argv[1:])
