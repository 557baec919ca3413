#!/usr/bin/env python3
"""How far the AND-OR search's lower bound at h = 0 is below the exact no-human value V_0.

    python bench/h0_bound_gap.py N M K [--seconds S] [--samples P] [--seed R]

On the pattern family's N x M x k = K scene (distinct blocks): the AND-OR search's rounds from
below run for S seconds (`andor._search`, the bound `packed.lower` builds), then P of the h = 0
nodes it made are drawn at random and each one's exact V_0 is computed by a search of its own
(a k = 0 memo).  Both bounds are evaluated at each: `solvers.bound`'s L0 alone ("old") and
max(L0, the assignment bound) ("new", `packed.lower`).  Prints one JSON line: the quantiles of
V_0 / bound for both, how often each is exact, and how many samples any bound exceeds V_0
(none may: the bounds are admissible).  Measured in bench/results/h0-assignment-bound.md.
"""

from __future__ import annotations

import argparse
import json
import random
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gamefamily import pattern_scene  # noqa: E402

from symsynth.game.abstraction import initial_state  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers import andor  # noqa: E402
from symsynth.solvers.packed import search as sk  # noqa: E402
from symsynth.solvers.packed.lower import BoundTables  # noqa: E402
from symsynth.solvers.packed.tables import Tables  # noqa: E402


def bounds(probe: andor.Memo, x: int, q: int) -> tuple[int, int]:
    """(old, new) bound at h = 0, robot turn, of packed state x with DFA state q: the
    bound a node gets when made (`search._node`), and after `search._tighten`."""
    j = probe.node(probe.key2(x, q, 0))
    old = int(probe.rec[j, sk.LO_R])
    sk._tighten(np.int64(j), sk.INF, probe.P, probe.B, probe.rec, probe.S()[10])
    return old, int(probe.rec[j, sk.LO_R])


def quantiles(ratios: list[float]) -> dict[str, float]:
    a = np.array(ratios)
    return {f"q{q}": round(float(np.quantile(a, q / 100)), 3) for q in (10, 50, 90, 99)} | {
        "exact": round(float((a <= 1.0).mean()), 3)}


def main(n: int, m: int, k: int, seconds: float, samples: int, seed: int) -> dict:
    andor.prepare()
    scene = pattern_scene(n, m, k)
    formula = task_formula(scene, None)
    tables = Tables(scene, formula, 1.0, None, k)
    bt = BoundTables(tables, formula)
    memo = andor.Memo(tables, bt, k)
    v0 = initial_state(scene)
    q0 = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v0))
    start = memo.node(memo.key2(tables.pack(v0), q0, k))
    andor._search(memo, start, time.perf_counter() + seconds, time.perf_counter() + seconds)
    rec = memo.rec[:memo.count]
    at_h0 = np.flatnonzero((rec[:, sk.KEY] & ((1 << memo.hb) - 1)) == 0)
    rng = random.Random(seed)
    chosen = rng.sample(list(at_h0), min(samples, len(at_h0)))
    exact_memo, probe = andor.Memo(tables, bt, 0), andor.Memo(tables, bt, 0)
    probe.tighten()
    rows = []
    clock = time.perf_counter()
    for i in chosen:
        x, q = memo.position(int(rec[i, sk.KEY]))
        j = exact_memo.node(exact_memo.key2(x, q, 0))
        lower, upper, _ = andor._search(exact_memo, j, None)
        value = upper
        if value is None:
            continue
        rows.append((value, *bounds(probe, x, q)))
    took = time.perf_counter() - clock
    return {"size": f"{n}x{m}x{k}", "search_s": seconds, "h0_nodes": len(at_h0), "samples": len(rows),
            "exact_s": round(took, 1), "median_v0": float(np.median([r[0] for r in rows])),
            "old": quantiles([r[0] / max(1, r[1]) for r in rows]),
            "new": quantiles([r[0] / max(1, r[2]) for r in rows]),
            "new_above_old": round(float(np.mean([r[2] > r[1] for r in rows])), 3),
            "above_v0": sum(1 for r in rows if max(r[1], r[2]) > r[0])}


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", type=int)
    ap.add_argument("m", type=int)
    ap.add_argument("k", type=int)
    ap.add_argument("--seconds", type=float, default=5.0)
    ap.add_argument("--samples", type=int, default=300)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    print(json.dumps(main(a.n, a.m, a.k, a.seconds, a.samples, a.seed)))
