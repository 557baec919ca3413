"""Issue 32: the AND-OR search's proofs from above, "val(start) <= T?", asked after
the rounds from below have run a given time, as inside `symsynth solve --time-limit`
(where they run until `andor.ROUNDS_SHARE` of the limit), not until they reach T
(bench/above_proof.py --rounds):

    python bench/above_after_rounds.py N M K ROUNDS_SECONDS SECONDS T [T ...]

builds the pattern game (distinct blocks), runs the rounds for ROUNDS_SECONDS (0: a
fresh memo), then asks each T in turn on that memo, each with a deadline of SECONDS.
It prints, per question, the answer (None: no answer by the deadline, "memory": out
of memory), wall and CPU seconds, lo and hi at the start, nodes, peak memory and the
load average; "upper/lower" is T over the lower end the rounds reached.
"""

from __future__ import annotations

import argparse
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from hybrid_bound import searched  # noqa: E402
from symsynth.solvers import andor  # noqa: E402
from symsynth.solvers.packed import search as sk  # noqa: E402


def rounds_for(memo: andor.Memo, start: int, seconds: float) -> int:
    """The rounds from below ("val <= lo?", lo raised on a no) for `seconds`, with
    the trap every 8, 16, 32, ... rounds, as `andor._search`; how many ran."""
    until, rounds = time.perf_counter() + seconds, 0
    while seconds > 0 and time.perf_counter() <= until:
        b = memo.lo_h(start)
        rounds += 1
        ok = memo.ask(start, b, False, until)
        if ok is not False:
            break
        memo.rec[start, sk.LO_H] = max(memo.lo_h(start), b + 1)
        if rounds >= 8 and rounds & (rounds - 1) == 0:
            memo.trap()
    return rounds


def main(argv: list[str]) -> None:
    p = argparse.ArgumentParser()
    for name in ("n", "m", "k"):
        p.add_argument(name, type=int)
    p.add_argument("rounds_seconds", type=float)
    p.add_argument("seconds", type=float)
    p.add_argument("budgets", type=int, nargs="+")
    a = p.parse_args(argv)
    _, _, memo, start = searched(a.n, a.m, a.k, 0)  # the memo, no question asked yet
    clock = time.perf_counter()
    rounds = rounds_for(memo, start, a.rounds_seconds)
    lower = memo.lo_h(start)
    print(f"{a.n} x {a.m} x k = {a.k}: {rounds} rounds to lo {lower} in {time.perf_counter() - clock:.1f} s, "
          f"{memo.count} nodes", flush=True)
    for b in a.budgets:
        clock, cpu = time.perf_counter(), time.process_time()
        try:
            ok: object = memo.ask(start, b, False, clock + a.seconds)
        except MemoryError:
            ok = "memory"
        print(f"  val <= {b} (upper/lower {b / lower:.3f})? {ok} in {time.perf_counter() - clock:.1f} s "
              f"({time.process_time() - cpu:.1f} s CPU); lo {memo.lo_h(start)}, hi "
              f"{'-' if memo.hi_h(start) >= andor.INF else memo.hi_h(start)}, {memo.count} nodes, peak "
              f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024} MB, "
              f"load {open('/proc/loadavg').read().split()[0]}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
