#!/usr/bin/env python3
"""What free h = 0 values would give the AND-OR search (`--solver andor`), for counting.

    python bench/andor_h0_oracle.py N M K MODE

On the pattern family's N x M x k = K scene: the layered solver explores and solves the game
(`compiled.explore_packed`), every position of its h = 0 layer becomes a search node with its
exact value V0, then the search's rounds run (`andor._search`).  MODE 0: no oracle (the
search as it is); 1: lo = V0 at h = 0 (a perfect lower bound); 2: lo = hi = V0 (both bounds);
3: hi = V0 (a perfect upper bound, the lower bound today's).  No strategy stands behind an
oracle's hi, so only the counts and the value mean anything.  Prints one
JSON line: the search's seconds, the nodes expanded by h, the moves generated, peak MB.
Measured in bench/results/game-notes.md (issue 32, exact h = 0 values).
"""

from __future__ import annotations

import json
import resource
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gamefamily import pattern_scene  # noqa: E402

from symsynth.game.abstraction import initial_state  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers import andor  # noqa: E402
from symsynth.solvers.compiled import compile_kernels, explore_packed  # noqa: E402
from symsynth.solvers.packed import search as sk  # noqa: E402
from symsynth.solvers.packed.lower import BoundTables  # noqa: E402


@njit
def _fill(keys, rval, lo, hi, hb, mode, P, B, M, S):
    """The layered nodes lo..hi (h = 0) as search nodes, their value as lo, hi or both (MODE)."""
    rec = M[1]
    for i in range(lo, hi):
        j = sk._node(keys[i] << hb, P, B, M, S)
        if mode != 3:
            rec[j, sk.LO_R] = rval[i]
            rec[j, sk.LO_H] = rval[i]
        if mode >= 2:
            rec[j, sk.HI_R] = rval[i]


def main(n: int, m: int, k: int, mode: int) -> dict:
    andor.prepare()
    compile_kernels()
    scene = pattern_scene(n, m, k)
    formula = task_formula(scene, None)
    packed = explore_packed(scene, formula, k, 1.0)
    tables = packed.tables
    keys, lo0, hi0 = packed.explored[0], int(packed.explored[2][0]), int(packed.explored[3][0])
    memo = andor.Memo(tables, BoundTables(tables, formula), k, nodes=hi0 - lo0 + 16 if mode else 1 << 12)
    if mode:
        while 2 * (hi0 - lo0 + memo.room) > len(memo.table) or hi0 - lo0 + memo.room > len(memo.rec):
            memo.rec = andor._grown(memo.rec, 2 * len(memo.rec))
            memo._grow()
        _fill(keys, packed.rval, lo0, hi0, np.int64(memo.hb), mode, memo.P, memo.B, memo.M(), memo.S())
    filled = memo.count
    del packed
    v0 = initial_state(scene)
    q0 = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v0))
    start = memo.node(memo.key2(tables.canon(tables.pack(v0)), q0, k))
    clock = time.perf_counter()
    _, value, rounds = andor._search(memo, start, None)
    seconds = time.perf_counter() - clock
    rec = memo.rec[:memo.count]
    h = rec[:, sk.KEY] & ((1 << memo.hb) - 1)
    return {"size": f"{n}x{m}x{k}", "mode": mode, "value": value, "rounds": rounds, "search_s": round(seconds, 2),
            "h0_filled": filled, "nodes": memo.count, "questions": int(memo.st[sk.ST_CALLS]),
            "robot_expanded_by_h": [int(((rec[:, sk.R_OFF] >= 0) & (h == x)).sum()) for x in range(k + 1)],
            "human_expanded_by_h": [int(((rec[:, sk.H_OFF] >= 0) & (h == x)).sum()) for x in range(k + 1)],
            "robot_moves": int(memo.st[sk.ST_NE]), "human_moves": int(memo.st[sk.ST_NH]),
            "peak_mb": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)}


if __name__ == "__main__":
    print(json.dumps(main(*(int(a) for a in sys.argv[1:5]))))
