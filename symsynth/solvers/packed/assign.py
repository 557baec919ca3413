"""The assignment bound's kernels (`packed.lower` states the bound A(v) and
proves it; `packed.search._tighten` raises a node's lower bounds to it when
the node is first expanded)."""

from __future__ import annotations

import numpy as np
from numba import njit

from symsynth.solvers.packed.kernels import INF

# numba's disk cache checks only this file's source (tests/test_numba_cache.py)
COMPILED_WITH = {"kernels.py": "e4a5b3789bf06122"}


@njit(cache=True)
def _assignment(x, n, m, pb, ee, grip, held, aimed, lb_place, lb_carry, lb_held, lb_grab, lb_drop, goal, dist, work,
                occupant):
    """`packed.lower`'s assignment bound A(x) (its terms and their proof are
    there); occupant: filled by `search._occupancy`."""
    pmask = (1 << pb) - 1
    k = n + 2
    dem, sup, mark, dem_obj, sup_obj = work[:k], work[k:2 * k], work[2 * k:3 * k], work[3 * k:4 * k], work[4 * k:5 * k]
    r = 0  # demands
    s = 0  # supplies
    total = INF - INF
    extra = 0  # pauses known: a held object's goal taken, cycles
    start = -1  # s0's row of dist; -1 when the hand holds an object with a goal
    if held >= 0:
        start = m if ee == 0 else ee - 1
    elif aimed >= 0:
        start = (x >> (aimed * pb)) & pmask
    else:
        start = m + 1
    for i in range(n):
        g = goal[i]
        mark[i] = 0
        if g < 0:
            continue
        l = lb_place[g]
        p = (x >> (i * pb)) & pmask
        if p == l:
            mark[i] = 1  # in place
            continue
        sup[s] = l
        sup_obj[s] = i
        s += 1
        if i == held:
            start = -1
            over = m if ee == 0 else ee - 1
            c = lb_held[i, over, grip - 1, g]
            if occupant[l] >= 0:  # dropped elsewhere first, grabbed again
                extra += 1
        else:
            c = lb_carry[i, p, g] + lb_grab
            dem[r] = p
            dem_obj[r] = i
            r += 1
        if c >= INF:
            return INF
        total += lb_drop + c
    if start >= 0:
        sup[s] = start
        sup_obj[s] = -1
        s += 1
    for i in range(n):  # cycles: each object on a location points at the one on its goal
        if mark[i] != 0 or goal[i] < 0 or i == held:
            continue
        j = i
        while True:
            mark[j] = 2
            p = (x >> (j * pb)) & pmask
            if p >= m:
                break
            j = occupant[lb_place[goal[j]]] if goal[j] >= 0 else -1
            if j < 0 or goal[j] < 0 or mark[j] == 1:
                break
            if j == i:
                extra += 1
                break
            if mark[j] == 2:
                break
    here = start if start <= m else -1
    pause = lb_drop + lb_grab
    backwards = _min_assignment(dem, dem_obj, r, sup, sup_obj, s, here, pause, dist, work[5 * k:])
    if extra == 0:  # (a) is the plain assignment then, never above (b)
        return total + backwards
    known = _min_assignment(dem, dem_obj, r, sup, sup_obj, s, here, 0, dist, work[5 * k:]) + extra * pause
    return total + (known if known > backwards else backwards)


@njit(cache=True)
def _min_assignment(dem, dem_obj, r, sup, sup_obj, s, here, pause, dist, w):
    """The least over injections of demands into supplies (r <= s) of the sum
    of `packed.lower`'s pair costs (`pause` on pairs backwards in time, 0
    from the start, the last supply, at its own place `here`): the Hungarian
    method by shortest augmenting paths, 1-based.  w: scratch, 5 (s + 1)."""
    if r == 0:
        return INF - INF
    big = np.int64(1) << 50
    c = s + 1
    u, v, match, way, minv = w[:c], w[c:2 * c], w[2 * c:3 * c], w[3 * c:4 * c], w[4 * c:5 * c]
    u[:] = 0
    v[:] = 0
    match[:] = 0  # the demand (1-based) a supply serves, 0: none
    for d in range(1, r + 1):
        match[0] = d
        j0 = 0
        minv[:] = big
        way[:] = 0
        used = np.int64(1)  # supplies visited, as bits (s < 62)
        while True:
            used |= np.int64(1) << j0
            i0 = match[j0]
            delta = big
            j1 = 0
            for j in range(1, c):
                if (used >> j) & 1:
                    continue
                a = 0 if j == s and sup[j - 1] == here else dist[sup[j - 1], dem[i0 - 1]]
                if sup_obj[j - 1] >= 0 and (sup[j - 1] == dem[i0 - 1] or sup_obj[j - 1] == dem_obj[i0 - 1]):
                    a += pause
                cur = (big if a >= big else a) - u[i0] - v[j]
                if cur < minv[j]:
                    minv[j] = cur
                    way[j] = j0
                if minv[j] < delta:
                    delta = minv[j]
                    j1 = j
            for j in range(c):
                if (used >> j) & 1:
                    u[match[j]] += delta
                    v[j] -= delta
                else:
                    minv[j] -= delta
            j0 = j1
            if match[j0] == 0:
                break
        while j0 != 0:
            j1 = way[j0]
            match[j0] = match[j1]
            j0 = j1
    total = -v[0]
    return INF if total >= big else total
