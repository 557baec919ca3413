"""The guaranteed expected cost (semantics §9) as step functions of the
budget: `expected_steps` computes X (robot turns) and Y (human turns) at
every budget a turn can be reached with, storing for each turn only the
budgets where its value changes.

X_b(i) and Y_b(t) never increase with b (more budget allows more moves,
and the moves' values fall too), and most of them stop falling well below
the largest budget a turn can be reached with (at 4 x 6 of the game
family, 7% of the (turn, budget) pairs are such breakpoints).  So the
levels b = 0..B are swept as before, but a turn is looked at on a level
only when something it reads changed:

- a robot turn i at its first level (xlo = V(i)): every move allowed
  there, each target's Y read at b - c (looked up in its breakpoints);
- then, on a level b, X(i) = min(X(i) at b - 1, c + Y_{b-c}(t) for the
  moves whose target t changed at b - c): X never increases, so the moves
  whose target did not change give what they gave at b - 1 (an *event*
  (i, move, value) is queued for level b + c when Y(t) changes at b; a
  move that becomes allowed at b is one whose target's first value is at
  b - c; a move that wins at cost c is an event at level c);
- Y(t) is summed again on a level where its pass's or a move's X changed.

In a layer of a level, the zero-cost moves read Y on the same level: the
changes are propagated by a work list until no value falls (from above, as
§9 asks: a turn starts the level at its value of the level below, which is
at least the level's own).  Where no move costs 0 each value is the same
sum and min of the same numbers as the level-by-level sweep, so the same
float; elsewhere the limit is reached from a different start, within the
tests' 1e-9.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from symsynth.solvers.objectives.kernels import _by_target

# numba's disk cache checks only this file's source, and these kernels compile
# in the code of kernels.py's: its SHA-256 (first 16 hex digits) stands here, so
# that a change there changes this file too and no stale machine code is
# loaded (tests/test_numba_cache.py fails until it is updated).
COMPILED_WITH = {"kernels.py": "fcb8f3f46ec55374"}

INF = np.int64(1 << 60)


@dataclass(frozen=True)
class Steps:
    """Each turn's values by breakpoints: robot turn i's are xlev[xo[i]:xo[i + 1]]
    (ascending budgets), with the value xval and the move xch (absolute edge
    index) from there on; human turn t's likewise in yo, ylev, yval."""

    xo: np.ndarray
    xlev: np.ndarray
    xval: np.ndarray
    xch: np.ndarray
    yo: np.ndarray
    ylev: np.ndarray
    yval: np.ndarray

    def choice(self, i: int, b: int) -> int:
        """The move at robot turn i with budget b left (-1: none)."""
        k = _at(self.xo, self.xlev, i, b)
        return -1 if k < 0 else int(self.xch[k])

    def y(self, t: int, b: int) -> float:
        """Y_b at human turn t (inf: not computed there)."""
        k = _at(self.yo, self.ylev, t, b)
        return np.inf if k < 0 else float(self.yval[k])

    @property
    def breakpoints(self) -> int:
        return len(self.xlev) + len(self.ylev)


def _at(off: np.ndarray, lev: np.ndarray, i: int, b: int) -> int:
    lo, hi = int(off[i]), int(off[i + 1])
    k = lo + int(np.searchsorted(lev[lo:hi], b, side="right")) - 1
    return k if k >= lo else -1


@njit(cache=True)
def dense_choice(steps_xo, xlev, xch, xo, xlo):
    """The moves as one array over the box of (turn, budget) pairs that
    `kernels.has_cycle` and `kernels.truncated` read: turn i's budgets xlo[i]..
    from xo[i]."""
    n = len(xo) - 1
    out = np.full(xo[n], -1, np.int32)
    for i in range(n):
        k = steps_xo[i]
        for s in range(xo[i], xo[i + 1]):
            b = xlo[i] + s - xo[i]
            while k + 1 < steps_xo[i + 1] and xlev[k + 1] <= b:
                k += 1
            if k < steps_xo[i + 1] and xlev[k] <= b:
                out[s] = xch[k]
    return out


@njit(cache=True)
def _grow_i(a, size):
    out = np.empty(max(size, 2 * len(a)), a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def _grow_f(a, size):
    out = np.empty(max(size, 2 * len(a)), a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def _grow_rows(a):
    out = np.empty((2 * len(a), a.shape[1]), a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def _lookup(last, lev, val, prev, t, b):
    """The value of turn t's chain of records at budget b (inf: none there)."""
    r = last[t]
    while r >= 0 and lev[r] > b:
        r = prev[r]
    return np.inf if r < 0 else val[r]


@njit(cache=True)
def _csr(last, lev, val, ch, prev, n, with_choice):
    """The records of every turn as CSR arrays sorted by budget."""
    off = np.zeros(n + 1, np.int64)
    for i in range(n):
        r = last[i]
        while r >= 0:
            off[i + 1] += 1
            r = prev[r]
    for i in range(n):
        off[i + 1] += off[i]
    olev = np.empty(off[n], np.int64)
    oval = np.empty(off[n], np.float64)
    och = np.empty(off[n] if with_choice else 0, np.int64)
    for i in range(n):
        k = off[i + 1] - 1
        r = last[i]
        while r >= 0:
            olev[k] = lev[r]
            oval[k] = val[r]
            if with_choice:
                och[k] = ch[r]
            k -= 1
            r = prev[r]
    return off, olev, oval, och


@njit(cache=True)
def _preds(off, tgt, n, lo, hi, weight):
    """The moves of a CSR graph grouped by target, each with what a change
    at the target needs of it, in the order it is read: its source, the
    move, the move's weight (cost or probability) and the source's budgets
    lo..hi."""
    start, edges, sources = _by_target(off, tgt, n)
    w = np.empty(len(edges), weight.dtype)
    plo = np.empty(len(edges), np.int64)
    phi = np.empty(len(edges), np.int64)
    for p in range(len(edges)):
        w[p] = weight[edges[p]]
        plo[p] = lo[sources[p]]
        phi[p] = hi[sources[p]]
    return start, edges, sources, w, plo, phi


@njit(cache=True)
def expected_steps(B, layer, hflag, r_off, r_tgt, r_units, rval, vh, dr, dh, stay, h_off, h_tgt, h_prob,
                   xorder, yorder):
    """X and Y by breakpoints (module doc) for budgets up to B: robot turn
    i's from xlo = V(i) to B - dr(i), human turn t's from vh(t) to B - dh(t).
    `xorder` / `yorder`: the robot turns / human turns sorted by (layer,
    first budget).  Returns the CSR arrays of `Steps`."""
    n = len(layer)
    xlo = rval
    ylo = vh
    xhi = B - dr
    yhi = B - dh
    K = 0
    W = 1
    for i in range(n):
        K = max(K, layer[i])
    for e in range(len(r_units)):
        W = max(W, min(r_units[e], B) + 1)
    rs, re_, rsrc, rcost, rlo, rhi = _preds(r_off, r_tgt, n, xlo, xhi, r_units)  # robot moves into human turns
    hs, _, hsrc, hprob, hlo, hhi = _preds(h_off, h_tgt, n, ylo, yhi, h_prob)  # human moves into robot turns
    # the records: chains from each turn's last record back
    cap = 2 * n + 16
    xr_lev = np.empty(cap, np.int64)
    xr_val = np.empty(cap, np.float64)
    xr_ch = np.empty(cap, np.int64)
    xr_prev = np.empty(cap, np.int64)
    xlast = np.full(n, -1, np.int64)
    nx = 0
    yr_lev = np.empty(cap, np.int64)
    yr_val = np.empty(cap, np.float64)
    yr_prev = np.empty(cap, np.int64)
    ylast = np.full(n, -1, np.int64)
    ny = 0
    xcur = np.full(n, np.inf)
    xch = np.full(n, -1, np.int64)
    ycur = np.full(n, np.inf)
    yact = np.zeros(n, np.uint8)  # Y summed once: from then on it follows its moves' changes
    # events (turn, move, value) for a level (ring of W) and a layer: linked lists, a free list
    head = np.full(W * (K + 1), -1, np.int64)
    ev = np.empty((1 << 16, 4))  # one row an event: turn, move, value, next (one cache line read per event)
    free = -1
    nev = 0
    # wins at a cost above the turn's first budget are allowed from that cost on
    for i in range(n):
        for e in range(r_off[i], r_off[i + 1]):
            c = r_units[e]
            if r_tgt[e] < 0 and xlo[i] < c <= xhi[i]:
                if nev == len(ev):
                    ev = _grow_rows(ev)
                slot = (c % W) * (K + 1) + layer[i]
                ev[nev, 0], ev[nev, 1], ev[nev, 2], ev[nev, 3] = i, e, float(c), head[slot]
                head[slot] = nev
                nev += 1
    # per layer: the next turn to activate, in xorder / yorder
    xcut = np.zeros(K + 2, np.int64)
    ycut = np.zeros(K + 2, np.int64)
    for a in range(len(xorder)):
        xcut[layer[xorder[a]] + 1] += 1
    for a in range(len(yorder)):
        ycut[layer[yorder[a]] + 1] += 1
    for h in range(K + 1):
        xcut[h + 1] += xcut[h]
        ycut[h + 1] += ycut[h]
    xnext = xcut[:K + 1].copy()
    ynext = ycut[:K + 1].copy()
    # work lists: X changed (to record and pass on), Y changed (likewise); the next layer's Y changed
    xq = np.empty(n, np.int64)
    xin = np.zeros(n, np.uint8)
    yq = np.empty(n, np.int64)
    yin = np.zeros(n, np.uint8)
    pend = np.empty(n, np.int64)
    npend = 0
    pend_next = np.empty(n, np.int64)
    for b in range(B + 1):
        if nx + n > len(xr_lev):  # a turn adds at most one record a level
            xr_lev = _grow_i(xr_lev, nx + n)
            xr_val = _grow_f(xr_val, nx + n)
            xr_ch = _grow_i(xr_ch, nx + n)
            xr_prev = _grow_i(xr_prev, nx + n)
        if ny + n > len(yr_lev):
            yr_lev = _grow_i(yr_lev, ny + n)
            yr_val = _grow_f(yr_val, ny + n)
            yr_prev = _grow_i(yr_prev, ny + n)
        for h in range(K + 1):
            nxq = 0
            nyq = 0
            for a in range(npend):  # the human turns whose moves changed on the layer below
                t = pend[a]
                yin[t] = 1
                yq[nyq] = t
                nyq += 1
            npend_n = 0
            # robot turns whose first budget is b: every move allowed
            while xnext[h] < xcut[h + 1] and xlo[xorder[xnext[h]]] <= b:
                i = xorder[xnext[h]]
                xnext[h] += 1
                if xlo[i] < b or b > xhi[i]:
                    continue  # never reached with a budget this low (or at all)
                best = np.inf
                pick = -1
                for e in range(r_off[i], r_off[i + 1]):
                    c = r_units[e]
                    t = r_tgt[e]
                    if t < 0:
                        y = float(c) if c <= b else np.inf
                    elif c + vh[t] <= b:
                        y = c + (ycur[t] if c == 0 else _lookup(ylast, yr_lev, yr_val, yr_prev, t, b - c))
                    else:
                        y = np.inf
                    if y < best:
                        best, pick = y, e
                xcur[i] = best
                xch[i] = pick
                xin[i] = 1
                xq[nxq] = i
                nxq += 1
            # the events of this level and layer
            slot = (b % W) * (K + 1) + h
            x = head[slot]
            head[slot] = -1
            while x >= 0:
                i = int(ev[x, 0])
                v = ev[x, 2]
                old = xcur[i]
                if v < old:
                    xcur[i] = v
                    xch[i] = int(ev[x, 1])
                    if not xin[i]:
                        xin[i] = 1
                        xq[nxq] = i
                        nxq += 1
                    nyq = _follow_pass(i, v, old, b, hflag, ylo, yhi, yact, stay, h_off, h_tgt, h_prob, xcur,
                                       ycur, yin, yq, nyq, False)
                    npend_n = _follow_up(i, v - old, b, hs, hsrc, hprob, hlo, hhi, ycur, yin, pend_next, npend_n)
                nx_ = int(ev[x, 3])
                ev[x, 3] = free
                free = x
                x = nx_
            # human turns whose first budget is b: summed once
            while ynext[h] < ycut[h + 1] and ylo[yorder[ynext[h]]] <= b:
                t = yorder[ynext[h]]
                ynext[h] += 1
                if ylo[t] == b and b <= yhi[t]:
                    ycur[t] = _sum(t, stay, h_off, h_tgt, h_prob, xcur)
                    if ycur[t] == np.inf:
                        continue  # a zero-cost move not settled yet: summed again when it is
                    yact[t] = 1
                    if not yin[t]:
                        yin[t] = 1
                        yq[nyq] = t
                        nyq += 1
            # pass the changes on: X -> the Y reading it (their sums follow), Y -> X by events, and by
            # the zero-cost moves on this level until nothing falls
            while nxq > 0 or nyq > 0:
                while nxq > 0:
                    nxq -= 1
                    i = xq[nxq]
                    xin[i] = 0
                    r = xlast[i]
                    if r >= 0 and xr_lev[r] == b:
                        xr_val[r] = xcur[i]
                        xr_ch[r] = xch[i]
                    else:
                        xr_lev[nx], xr_val[nx], xr_ch[nx], xr_prev[nx] = b, xcur[i], xch[i], r
                        xlast[i] = nx
                        nx += 1
                while nyq > 0:
                    nyq -= 1
                    t = yq[nyq]
                    yin[t] = 0
                    y = ycur[t]
                    r = ylast[t]
                    if r >= 0 and yr_lev[r] == b:
                        yr_val[r] = y
                    else:
                        yr_lev[ny], yr_val[ny], yr_prev[ny] = b, y, r
                        ylast[t] = ny
                        ny += 1
                    for p in range(rs[t], rs[t + 1]):
                        c = rcost[p]
                        L = b + c
                        if L > rhi[p] or (L <= rlo[p] if c > 0 else L < rlo[p]):
                            continue  # beyond the turn's budgets, or read by its first level
                        i = rsrc[p]
                        if c == 0:
                            old = xcur[i]
                            if y < old:
                                xcur[i] = y
                                xch[i] = re_[p]
                                if not xin[i]:
                                    xin[i] = 1
                                    xq[nxq] = i
                                    nxq += 1
                                nyq = _follow_pass(i, y, old, b, hflag, ylo, yhi, yact, stay, h_off, h_tgt, h_prob,
                                                   xcur, ycur, yin, yq, nyq, True)
                                npend_n = _follow_up(i, y - old, b, hs, hsrc, hprob, hlo, hhi, ycur, yin,
                                                     pend_next, npend_n)
                            continue
                        if c + y >= xcur[i]:
                            continue  # no better than i's value now, which its value on level L is at most
                        if free < 0:
                            if nev == len(ev):
                                ev = _grow_rows(ev)
                            free = nev
                            ev[nev, 3] = -1
                            nev += 1
                        x = free
                        free = int(ev[x, 3])
                        slot = (L % W) * (K + 1) + h
                        ev[x, 0], ev[x, 1], ev[x, 2], ev[x, 3] = i, re_[p], c + y, head[slot]
                        head[slot] = x
            for a in range(npend_n):  # the next layer's changed human turns
                yin[pend_next[a]] = 0
            pend, pend_next = pend_next, pend
            npend = npend_n
        npend = 0
    xo, xlev, xval, xchs = _csr(xlast, xr_lev, xr_val, xr_ch, xr_prev, n, True)
    yo, ylev, yval, _ = _csr(ylast, yr_lev, yr_val, yr_prev, yr_prev, n, False)
    return xo, xlev, xval, xchs, yo, ylev, yval


@njit(cache=True)
def _follow_up(j, delta, b, hs, hsrc, hprob, hlo, hhi, ycur, yin, pend, npend):
    """Robot turn j's X fell by -delta on level b: the human turns of the
    layer above whose moves lead to j follow (those summed already), and
    are listed as changed for that layer."""
    for p in range(hs[j], hs[j + 1]):
        if hlo[p] < b <= hhi[p] and hprob[p] > 0.0:
            t = hsrc[p]
            ycur[t] += hprob[p] * delta
            if not yin[t]:
                yin[t] = 2
                pend[npend] = t
                npend += 1
    return npend


@njit(cache=True)
def _sum(t, stay, h_off, h_tgt, h_prob, xcur):
    """Y at human turn t from the X of its pass and moves (inf while one is)."""
    y = stay[t] * xcur[t] if stay[t] > 0.0 else 0.0
    for e in range(h_off[t], h_off[t + 1]):
        j = h_tgt[e]
        if j >= 0 and h_prob[e] > 0.0:
            y += h_prob[e] * xcur[j]
    return y


@njit(cache=True)
def _follow_pass(i, new, old, b, hflag, ylo, yhi, yact, stay, h_off, h_tgt, h_prob, xcur, ycur, yin, yq, nyq,
                 whole):
    """Robot turn i's X fell from old to new on level b: the human turn at
    the same node, whose pass leads to it, follows, listed as changed (the
    length of the list).  It is summed whole when it could not be summed
    before (a zero-cost move unsettled then), and with `whole`: inside the
    zero-cost iteration, where adding the differences would let the values
    creep down by roundings instead of settling."""
    if not hflag[i] or not ylo[i] <= b <= yhi[i]:
        return nyq
    if yact[i] and not whole:
        if stay[i] > 0.0:
            ycur[i] += stay[i] * (new - old)
    else:
        y = _sum(i, stay, h_off, h_tgt, h_prob, xcur)
        if y == np.inf:
            return nyq
        ycur[i] = y
        yact[i] = 1
    if not yin[i]:
        yin[i] = 1
        yq[nyq] = i
        nyq += 1
    return nyq
