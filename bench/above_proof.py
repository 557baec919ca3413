"""Issue 32: the AND-OR search's proof from above, "val(start) <= B?", asked alone
and measured:

    python bench/above_proof.py N M K B SECONDS [--rounds] [--tighten] [--no-hint]
                                [--sigma T] [--detail]

asks the pattern game's start (distinct blocks) the one question at budget B with
a deadline of SECONDS, on a fresh memo, or (`--rounds`) after the rounds from
below have raised lo(start) to B (as `symsynth solve` gets there: its last round
is this question).  `--tighten` turns the assignment bound on (`Memo.tighten`)
for the question only, `--no-hint` turns off the h = 0 action first
(`search._hint_first`) for the rounds and the question, `--sigma T` asks σ's
question "B_k <= T?" on the memo before the question, and `--detail` counts the
robot turns the question expanded, by h, proven or only refuted.  It prints
the answer, the seconds, the kernel's questions, the nodes by h (created,
robot turns expanded, human turns expanded), the moves stored and the
process's peak memory.
"""

from __future__ import annotations

import argparse
import collections
import resource
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.abstraction import initial_state  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers import andor  # noqa: E402
from symsynth.solvers.packed import search as sk  # noqa: E402
from symsynth.solvers.packed.lower import BoundTables  # noqa: E402
from symsynth.solvers.packed.tables import Tables  # noqa: E402
from symsynth.solvers.replan import NoHumanValue  # noqa: E402
from symsynth.solvers.replan_budget import BudgetedBound  # noqa: E402


def by_h(memo: andor.Memo) -> dict[int, tuple[int, int, int]]:
    """h -> (nodes, robot turns expanded, human turns expanded)."""
    rec = memo.rec[:memo.count]
    h = rec[:, sk.KEY] & ((1 << memo.hb) - 1)
    out = {}
    for v in range(memo.k + 1):
        sel = h == v
        out[v] = (int(sel.sum()), int((rec[sel, sk.R_OFF] >= 0).sum()), int((rec[sel, sk.H_OFF] >= 0).sum()))
    return out


def main(argv: list[str]) -> None:
    p = argparse.ArgumentParser()
    for name in ("n", "m", "k", "b"):
        p.add_argument(name, type=int)
    p.add_argument("seconds", type=float)
    p.add_argument("--rounds", action="store_true")
    p.add_argument("--tighten", action="store_true")
    p.add_argument("--detail", action="store_true")
    p.add_argument("--no-hint", action="store_true", help="without the h = 0 action first (`search._hint_first`)")
    p.add_argument("--sigma", type=int, default=None, help="σ's question at this budget on the memo first")
    a = p.parse_args(argv)
    andor.prepare()
    scene = pattern_scene(a.n, a.m, a.k)
    formula = task_formula(scene, None)
    tables = Tables(scene, formula, 1.0, None, a.k)
    memo = andor.Memo(tables, BoundTables(tables, formula), a.k)
    memo.st[sk.ST_HINT] = 0 if a.no_hint else 1
    x = tables.pack(initial_state(scene))
    start = memo.node(memo.key2(x, tables.step(tables.dfa_index[tables.dfa.initial], x), a.k))
    clock = time.perf_counter()
    rounds = 0
    while a.rounds and memo.lo_h(start) < a.b:
        lo = memo.lo_h(start)
        rounds += 1
        if memo.ask(start, lo, False, clock + a.seconds) is not False:
            print("rounds: no answer below B", flush=True)
            return
        memo.rec[start, sk.LO_H] = max(memo.lo_h(start), lo + 1)
    if a.rounds:
        print(f"rounds: {rounds} to lo {memo.lo_h(start)} in {time.perf_counter() - clock:.1f} s, "
              f"{memo.count} nodes, {int(memo.st[sk.ST_CALLS])} questions", flush=True)
    if a.sigma is not None:
        clock = time.perf_counter()
        bound = BudgetedBound(scene, formula, a.k, 1.0, NoHumanValue(scene, formula, 1.0, memo))
        print(f"σ <= {a.sigma}? {bound.within(a.sigma)} in {time.perf_counter() - clock:.1f} s, "
              f"{memo.count} nodes", flush=True)
        memo.B = memo.bound.args()  # σ's searches tighten the memo; the question below only with --tighten
        memo.chunk = None
    before = collections.Counter({h: c[1] + c[2] for h, c in by_h(memo).items()})
    calls0, count0 = int(memo.st[sk.ST_CALLS]), memo.count
    old = np.zeros(memo.count, bool) if not a.rounds else memo.rec[:memo.count, sk.R_OFF] >= 0
    if a.tighten:
        memo.tighten()
    clock = time.perf_counter()
    try:
        ok = memo.ask(start, a.b, False, clock + a.seconds)
    except MemoryError:
        print(f"val <= {a.b}? out of memory after {time.perf_counter() - clock:.1f} s, {memo.count} nodes, "
              f"peak {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024} MB", flush=True)
        return
    took = time.perf_counter() - clock
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
    print(f"{a.n} x {a.m} x k = {a.k}: val <= {a.b}? {ok} in {took:.1f} s{' (tightened)' if a.tighten else ''}; "
          f"{int(memo.st[sk.ST_CALLS]) - calls0} questions, {memo.count - count0} new nodes ({memo.count} in all), "
          f"robot moves {int(memo.st[sk.ST_NE])}, human moves {int(memo.st[sk.ST_NH])}, "
          f"hi(start) {memo.hi_h(start)}, peak {peak} MB", flush=True)
    for h, (nodes, rob, hum) in by_h(memo).items():
        print(f"  h = {h}: {nodes} nodes, {rob} robot turns and {hum} human turns expanded "
              f"({rob + hum - before[h]} new expansions)", flush=True)
    proven = np.flatnonzero(memo.rec[:memo.count, sk.HI_R] < andor.INF)
    print(f"  robot turns with a proven hi: {len(proven)}", flush=True)
    if a.detail:
        detail(memo, old)


def detail(memo: andor.Memo, old: np.ndarray) -> None:
    """Expanded robot turns by h, proven or only refuted; at the proven ones of h >= 1, the
    chosen action's rank in the search's order (by the final lo) and whether the node at h = 0
    of the same (state, DFA state) chose the same action."""
    rec = memo.rec[:memo.count]
    h = rec[:, sk.KEY] & ((1 << memo.hb) - 1)
    exp = rec[:, sk.R_OFF] >= 0
    exp[:len(old)] &= ~old  # expanded by the question asked
    ok = rec[:, sk.HI_R] < andor.INF
    for v in range(memo.k + 1):
        print(f"  h = {v}: robot turns newly expanded {int((exp & (h == v)).sum())}, of them proven "
              f"{int((exp & ok & (h == v)).sum())}", flush=True)
    ranks, same = collections.Counter(), collections.Counter()
    bits = memo.t.code_bits
    for i in np.flatnonzero(exp & ok & (h > 0)):
        off, cnt = int(rec[i, sk.R_OFF]), int(sk._small(memo.rec, np.int64(i), np.int64(0)))
        e = int(sk._small(memo.rec, np.int64(i), np.int64(32))) - 1
        tg, mv = memo.rm_tgt[off:off + cnt], memo.rm_move[off:off + cnt] >> bits
        f = [int(mv[j]) + (0 if tg[j] < 0 else memo.lo_h(int(tg[j]))) for j in range(cnt)]
        ranks[min(sorted(range(cnt), key=lambda j: (f[j], j)).index(e), 5)] += 1
        j0 = memo.find(int(rec[i, sk.KEY]) >> memo.hb << memo.hb)
        if j0 is None or memo.rec[j0, sk.HI_R] >= andor.INF:
            same["no proven h = 0 node"] += 1
        else:
            same["same" if int(sk._small(memo.rec, np.int64(j0), np.int64(32))) - 1 == e else "other"] += 1
    print(f"  h >= 1 proven robot turns: rank of the chosen action {sorted(ranks.items())}; "
          f"the h = 0 node's action {dict(same)}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
