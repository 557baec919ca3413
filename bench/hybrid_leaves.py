"""Issue 32: where the hybrid strategy's question "W_j <= b?" spends its leaves
(symsynth/solvers/hybrid.py), counted, not guessed:

    python bench/hybrid_leaves.py N M K LOWER B SECONDS

runs the AND-OR search's rounds from below on the pattern game until its lower
end reaches LOWER, then asks τ_1's question at budget B for at most SECONDS, σ's
questions on the search's own memo (as `symsynth solve` asks them).  It prints:

- leaf calls (`Hybrid._leaf`), σ's questions asked (`within_from`), distinct leaf
  nodes and distinct (node, budget) pairs, the budgets per leaf node;
- how σ's questions ended: V_0 above the budget, read from σ's kept answers, or
  worked out (its plan's replies settled in machine code: by the memo's bounds,
  a repair, σ's plan followed, a search);
- the seconds in σ's questions, of which V_0 (the no-human searches), σ's plans
  read back, and the replies' kernel;
- at the robot turns certified, which of the actions tried (in the search's
  order) answered, and how many robot turns were refuted;
- after a yes, how many of the leaf nodes asked the certificate uses.
"""

from __future__ import annotations

import collections
import resource
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from hybrid_bound import searched  # noqa: E402
from symsynth.solvers.hybrid import Hybrid  # noqa: E402
from symsynth.solvers.replan import NoHumanValue  # noqa: E402
from symsynth.solvers.replan_budget import BudgetedBound, Deadline  # noqa: E402


class Timed:
    """Seconds and calls of some methods of an object, wrapped in place."""

    def __init__(self, obj, names):
        self.seconds = collections.Counter()
        self.calls = collections.Counter()
        for name in names:
            setattr(obj, name, self._wrap(name, getattr(obj, name)))

    def _wrap(self, name, f):
        def timed(*args, **kwargs):
            clock = time.perf_counter()
            try:
                return f(*args, **kwargs)
            finally:
                self.seconds[name] += time.perf_counter() - clock
                self.calls[name] += 1
        return timed


class Counted(Hybrid):
    """The hybrid with its leaves and robot turns counted."""

    def __init__(self, *args):
        super().__init__(*args)
        self.leaf_calls = 0
        self.pairs: set[tuple[int, int]] = set()
        self.asked_nodes: set[int] = set()
        self.sigma_outcome = collections.Counter()
        self.answered_at = collections.Counter()  # index of the option that certified a robot turn
        self.stack: list[list[int]] = []  # per human turn being asked: [σ's questions of its own moves]
        self.refuted = collections.Counter()  # human turns above the leaves refuted: by a move / by the pass
        self.spent = collections.Counter()  # σ's questions of the moves of those turns, by the same causes

    def _leaf(self, i, b):
        self.leaf_calls += 1
        before = self.leaves
        ok = super()._leaf(i, b)
        if self.leaves > before:
            self.pairs.add((i, b))
            self.asked_nodes.add(i)
        if self.stack:
            self.stack[-1][0] += self.leaves > before
            self.stack[-1][1] = ok
        return ok

    def _human(self, i, b):
        known = self.no_h.get(i, -1) >= b or self.hi_h.get(i, 1 << 62) <= b or b < self.memo.lo_h(i)
        self.stack.append([0, True])
        try:
            ok = super()._human(i, b)
        finally:
            own, last = self.stack.pop()
        if not ok and not known and self._h(i) - 1 == self.j:
            cause = "a move" if not last else "the pass"
            self.refuted[cause] += 1
            self.spent[cause] += own
        return ok

    def _robot(self, i, b):
        hi = self.hi_r.get(i)
        ok = super()._robot(i, b)
        if ok and (hi is None or hi[0] > b):
            e = self.hi_r[i][1]
            off, count = self.memo.expand(i, True)
            bits = self.memo.t.code_bits
            order = sorted(range(off, off + count), key=lambda f: (
                (int(self.memo.rm_move[f]) >> bits) + (0 if self.memo.rm_tgt[f] < 0 else self.memo.lo_h(
                    int(self.memo.rm_tgt[f]))), int(self.memo.rm_move[f]) >> bits, int(self.memo.rm_tgt[f]), f))
            self.answered_at[min(order.index(e), 3)] += 1
        return ok


def proof_leaves(h: Counted) -> int:
    """Leaf nodes of the certificate kept (after a yes): from the start along the
    kept actions and every human reply."""
    memo, seen, leaves = h.memo, set(), set()
    todo = [h.start]
    while todo:
        i = todo.pop()
        if i in seen:
            continue
        seen.add(i)
        off, count = memo.expand(i, False)
        for t in [int(t) for t in memo.hm_tgt[off:off + count] if t >= 0]:
            if h._h(i) - 1 == h.j:
                leaves.add(t)
            else:
                after = int(memo.rm_tgt[h.hi_r[t][1]])
                if after >= 0:
                    todo.append(after)
        after = int(memo.rm_tgt[h.hi_r[i][1]])
        if after >= 0:
            todo.append(after)
    return len(leaves)


def main(argv: list[str]) -> None:
    n, m, k, lower, b, seconds = map(int, argv[:6])
    scene, formula, memo, start = searched(n, m, k, lower)
    bound = BudgetedBound(scene, formula, k, 1.0, NoHumanValue(scene, formula, 1.0, memo))
    timed = Timed(bound, ["within_from", "value", "_turns", "_settle", "_fits"])
    hybrid = Counted(memo, bound, 1, start)
    clock = time.perf_counter()
    try:
        ok: bool | None = hybrid.within(b, clock + seconds)
    except Deadline:
        ok = None
    took = time.perf_counter() - clock
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024
    print(f"W_1 <= {b}? {ok} in {took:.1f} s; peak {peak} MB; memo {memo.count} nodes")
    per_node = collections.Counter(collections.Counter(i for i, _ in hybrid.pairs).values())
    print(f"leaf calls {hybrid.leaf_calls}; σ's questions {hybrid.leaves} ({hybrid.leaves / took:.0f} a second); "
          f"distinct leaf nodes {len(hybrid.asked_nodes)}; distinct (node, budget) {len(hybrid.pairs)}; "
          f"leaf nodes by budgets asked {sorted(per_node.items())[:8]}")
    print(f"σ's answers: yes {sum(1 for _ in hybrid.leaf)} nodes, no {len(hybrid.no_leaf)} nodes; "
          f"_fits calls {timed.calls['_fits']} (worked out: {timed.calls['_turns']} plans read, "
          f"{timed.calls['_settle']} kernel calls); V_0 searches {bound.oracle.questions}; replies settled "
          f"{bound.settled}: memo / repair / followed / search {bound.counts.tolist()}")
    print("seconds: " + ", ".join(f"{name} {timed.seconds[name]:.1f}" for name in timed.seconds)
          + f"; the rest of the question {took - timed.seconds['within_from']:.1f}")
    print(f"robot turns certified by the option tried first / second / third / later: "
          f"{[hybrid.answered_at[r] for r in range(4)]}; refuted robot turns {len(hybrid.no_r)}, "
          f"human turns {len(hybrid.no_h)}")
    print(f"human turns refuted, by cause: {dict(hybrid.refuted)}; σ's questions of their own moves: "
          f"{dict(hybrid.spent)}")
    if ok:
        print(f"leaf nodes in the certificate kept: {proof_leaves(hybrid)} of {len(hybrid.asked_nodes)} asked")


if __name__ == "__main__":
    main(sys.argv[1:])
