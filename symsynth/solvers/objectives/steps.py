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


# A turn's row (`_turns`; node i is robot turn i and, if it has one, human turn i): X and
# its move, the last record (`_record`) of X and its level, likewise of Y; the pass's
# probability; the human turn's budgets; where its human moves' group (the moves of the
# layer above into robot turn i, `_human_moves`) and its robot moves' group (the robot
# moves into human turn i, `_robot_moves`) lie.  One row read per turn where twelve
# arrays were: the sweep is bound by scattered reads.
X, XCH, XLAST, XLEV, Y, YLAST, YLEV, STAY, YLO, YHI, HS, HE, RS, RE = range(14)
# a turn's flags: it has a human turn; its Y is summed (it follows its moves from then on);
# it is in the work list of X, of Y (this layer's or the next's)
HUMAN, SUMMED, XQUEUED, YQUEUED = 1, 2, 4, 8
# a robot move's row: the level key (`_preds`), its source's last budget, cost, source, the move
P_KEY, P_HI, P_COST, P_SRC, P_MOVE = range(5)
# a human move's row: the key, its source's last budget, probability, source
Q_KEY, Q_HI, Q_PROB, Q_SRC = range(4)
# an event: the robot turn, the move, the value it offers.  A list of events is a chain of
# chunks of CHUNK events (`expected_steps`' argument; tests/test_objective_steps.py makes it 1 too), each chunk's
# row 0 holding the next chunk and how many it holds: the events of a chunk are read one
# after the other, where a chain of single events made each read wait for the one before
# (13% of the sweep at 5 x 7)
E_TURN, E_MOVE, E_VALUE = range(3)
CHUNK = 32
# a record's row (its value apart): level, the record before it of the same turn, turn, move
R_LEV, R_PREV, R_TURN, R_CH = range(4)
# the sweep's counts: the X and Y work lists, the next layer's changed human turns, the X and Y
# records, the events' free list and chunks used
C_NXQ, C_NYQ, C_NPEND, C_NX, C_NY, C_FREE, C_EVENTS = range(7)


@njit(cache=True)
def _grow_f(a, size):
    out = np.empty(max(size, 2 * len(a)), a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def _grow_rows(a, size):
    out = np.empty((max(size, 2 * len(a)), a.shape[1]), a.dtype)
    out[:len(a)] = a
    return out


@njit(cache=True)
def _grow_chunks(a):
    out = np.empty((2 * len(a), a.shape[1], 3))
    out[:len(a)] = a
    return out


@njit(cache=True)
def _lookup(nd, last, rec, val, t, b):
    """The value of turn t's chain of records (its last in column `last`
    of its row) at budget b (inf: none there)."""
    r = int(nd[t, last])
    while r >= 0 and rec[r, R_LEV] > b:
        r = rec[r, R_PREV]
    return np.inf if r < 0 else val[r]


@njit(cache=True)
def _record(nd, i, last, lev, rec, val, count, b, value, move):
    """Turn i's value on level b, recorded (over its record of level b if
    it has one); the number of records."""
    if nd[i, lev] == b:
        r = int(nd[i, last])
        val[r] = value
        rec[r, R_CH] = move
        return count
    rec[count, R_LEV], rec[count, R_PREV], rec[count, R_TURN], rec[count, R_CH] = b, int(nd[i, last]), i, move
    val[count] = value
    nd[i, last] = count
    nd[i, lev] = b
    return count + 1


@njit(cache=True)
def _csr(rec, val, count, n):
    """The records (`count` of them, appended in the order of their
    levels) as CSR arrays sorted by turn and budget: (offsets, levels,
    values, moves), by a stable counting sort on the turn."""
    off = np.zeros(n + 1, np.int64)
    for r in range(count):
        off[rec[r, R_TURN] + 1] += 1
    for i in range(n):
        off[i + 1] += off[i]
    fill = off[:n].copy()
    olev = np.empty(count, np.int64)
    oval = np.empty(count, np.float64)
    och = np.empty(count, np.int64)
    for r in range(count):
        k = fill[rec[r, R_TURN]]
        fill[rec[r, R_TURN]] = k + 1
        olev[k], oval[k], och[k] = rec[r, R_LEV], val[r], rec[r, R_CH]
    return off, olev, oval, och


@njit(cache=True)
def _preds(off, tgt, n, lo, shift):
    """The moves of a CSR graph grouped by target: (start of each target's
    group, the moves, their sources, their keys), sorted within a group by
    the key `lo[source] - shift[move]`: the last level on which a change
    at the target is of no use to the source yet, so that a scan on level
    b stops at the first key >= b (most moves lead from turns first
    reached with a larger budget)."""
    start, edges, sources = _by_target(off, tgt, n)
    key = np.empty(len(edges), np.int64)
    for p in range(len(edges)):
        key[p] = lo[sources[p]] - shift[edges[p]]
    for j in range(n):  # insertion sort: the groups are short
        for p in range(start[j] + 1, start[j + 1]):
            k, e, s = key[p], edges[p], sources[p]
            q = p - 1
            while q >= start[j] and key[q] > k:
                key[q + 1], edges[q + 1], sources[q + 1] = key[q], edges[q], sources[q]
                q -= 1
            key[q + 1], edges[q + 1], sources[q + 1] = k, e, s
    return start, edges, sources, key


@njit(cache=True)
def _robot_moves(r_off, r_tgt, r_units, n, xlo, xhi):
    """The robot moves into each human turn t as rows (P_*), keyed by
    xlo - max(c, 1): a change of Y(t) on level b reaches level b + c of
    the source, which reads it there unless b + c <= xlo (its first level
    looks Y up, c > 0) or b < xlo (c = 0)."""
    start, edges, sources, key = _preds(r_off, r_tgt, n, xlo, np.maximum(r_units, 1))
    rows = np.empty((len(edges), 5), np.int64)
    for p in range(len(edges)):
        e, i = edges[p], sources[p]
        rows[p, P_KEY], rows[p, P_HI], rows[p, P_COST], rows[p, P_SRC], rows[p, P_MOVE] = key[p], xhi[i], \
            r_units[e], i, e
    return start, rows


@njit(cache=True)
def _human_moves(h_off, h_tgt, h_prob, n, ylo, yhi):
    """The human moves into each robot turn as rows (Q_*), keyed by ylo:
    the source sums every move on its first level."""
    start, edges, sources, key = _preds(h_off, h_tgt, n, ylo, np.zeros(len(h_tgt), np.int64))
    rows = np.empty((len(edges), 4))
    for p in range(len(edges)):
        rows[p, Q_KEY], rows[p, Q_HI], rows[p, Q_PROB], rows[p, Q_SRC] = key[p], yhi[sources[p]], \
            h_prob[edges[p]], sources[p]
    return start, rows


@njit(cache=True)
def _turns(hflag, stay, ylo, yhi, hs, rs):
    """Each turn's row (X, XCH, ...) before level 0, and its flags."""
    n = len(hflag)
    nd = np.empty((n, 14))
    fl = np.zeros(n, np.uint8)
    for i in range(n):
        nd[i, X], nd[i, XCH], nd[i, XLAST], nd[i, XLEV] = np.inf, -1, -1, -1
        nd[i, Y], nd[i, YLAST], nd[i, YLEV], nd[i, STAY] = np.inf, -1, -1, stay[i]
        nd[i, YLO], nd[i, YHI], nd[i, HS], nd[i, HE], nd[i, RS], nd[i, RE] = ylo[i], yhi[i], hs[i], hs[i + 1], \
            rs[i], rs[i + 1]
        if hflag[i]:
            fl[i] = HUMAN
    return nd, fl


@njit(cache=True)
def _cuts(layer, order, K):
    """Where each layer's turns begin in `order` (sorted by layer)."""
    cut = np.zeros(K + 2, np.int64)
    for a in range(len(order)):
        cut[layer[order[a]] + 1] += 1
    for h in range(K + 1):
        cut[h + 1] += cut[h]
    return cut


@njit(cache=True)
def expected_steps(B, layer, hflag, r_off, r_tgt, r_units, rval, vh, dr, dh, stay, h_off, h_tgt, h_prob,
                   xorder, yorder, chunk=CHUNK):
    """X and Y by breakpoints (module doc) for budgets up to B: robot turn
    i's from xlo = V(i) to B - dr(i), human turn t's from vh(t) to B - dh(t).
    `xorder` / `yorder`: the robot turns / human turns sorted by (layer,
    first budget); `chunk`: events a chunk.  Returns the CSR arrays of `Steps`."""
    n = len(layer)
    xhi = B - dr
    yhi = B - dh
    K = max(layer.max(), 0) if n else 0
    W = max(min(r_units.max(), B) + 1, 1) if len(r_units) else 1
    rs, rp = _robot_moves(r_off, r_tgt, r_units, n, rval, xhi)
    hs, hp = _human_moves(h_off, h_tgt, h_prob, n, vh, yhi)
    nd, fl = _turns(hflag, stay, vh, yhi, hs, rs)
    xrec, xval = np.empty((2 * n + 16, 4), np.int64), np.empty(2 * n + 16)
    yrec, yval = np.empty((2 * n + 16, 4), np.int64), np.empty(2 * n + 16)
    # events for a level (a ring of W) and a layer: lists of chunks, and a free list
    head = np.full(W * (K + 1), -1, np.int64)
    cnt = np.zeros(7, np.int64)
    ev = _wins(r_off, r_tgt, r_units, layer, rval, xhi, head, W, K, cnt, chunk)
    xcut, ycut = _cuts(layer, xorder, K), _cuts(layer, yorder, K)
    xnext, ynext = xcut[:K + 1].copy(), ycut[:K + 1].copy()
    xq, yq = np.empty(n, np.int64), np.empty(n, np.int64)
    pend, pend_next = np.empty(n, np.int64), np.empty(n, np.int64)
    for b in range(B + 1):
        if cnt[C_NX] + n > len(xrec):  # a turn adds at most one record a level
            xrec, xval = _grow_rows(xrec, cnt[C_NX] + n), _grow_f(xval, cnt[C_NX] + n)
        if cnt[C_NY] + n > len(yrec):
            yrec, yval = _grow_rows(yrec, cnt[C_NY] + n), _grow_f(yval, cnt[C_NY] + n)
        cnt[C_NPEND] = 0
        for h in range(K + 1):
            npend = cnt[C_NPEND]  # the human turns whose moves changed on the layer below
            yq[:npend] = pend[:npend]
            cnt[C_NXQ], cnt[C_NYQ], cnt[C_NPEND] = 0, npend, 0
            _first_robot(b, h, xorder, xnext, xcut, r_off, r_tgt, r_units, rval, xhi, vh, nd, fl, xq, yrec, yval,
                         cnt)
            _fire(b, head, (b % W) * (K + 1) + h, ev, nd, fl, h_off, h_tgt, h_prob, hp, xq, yq, pend_next, cnt)
            _first_human(b, h, yorder, ynext, ycut, vh, yhi, nd, fl, h_off, h_tgt, h_prob, yq, cnt)
            ev = _settle(b, h, W, K, head, ev, nd, fl, rp, hp, h_off, h_tgt, h_prob, xq, yq, pend_next, cnt,
                         xrec, xval, yrec, yval)
            pend, pend_next = pend_next, pend
    xo, xlev, xv, xch = _csr(xrec, xval, cnt[C_NX], n)
    yo, ylev, yv, _ = _csr(yrec, yval, cnt[C_NY], n)
    return xo, xlev, xv, xch, yo, ylev, yv


@njit(cache=True)
def _wins(r_off, r_tgt, r_units, layer, xlo, xhi, head, W, K, cnt, chunk):
    """The events' chunks (of `chunk` events), holding the moves that win
    at a cost c above their turn's first budget: allowed from level c on."""
    ev = np.empty((1024, chunk + 1, 3))
    cnt[C_FREE], cnt[C_EVENTS] = -1, 0
    for i in range(len(layer)):
        for e in range(r_off[i], r_off[i + 1]):
            c = r_units[e]
            if r_tgt[e] < 0 and xlo[i] < c <= xhi[i]:
                ev = _offer(ev, head, (c % W) * (K + 1) + layer[i], i, e, c, cnt)
    return ev


@njit(cache=True)
def _first_robot(b, h, xorder, xnext, xcut, r_off, r_tgt, r_units, xlo, xhi, vh, nd, fl, xq, yrec, yval, cnt):
    """The robot turns of layer h whose first budget is b: X from every
    move allowed there, each target's Y read at b - c; queued."""
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
                y = c + (nd[t, Y] if c == 0 else _lookup(nd, YLAST, yrec, yval, t, b - c))
            else:
                y = np.inf
            if y < best:
                best, pick = y, e
        nd[i, X], nd[i, XCH] = best, pick
        _queue(fl, i, XQUEUED, xq, cnt, C_NXQ)


@njit(cache=True)
def _queue(fl, i, flag, q, cnt, which):
    """Turn i onto work list q (its length in cnt[which]) unless there."""
    if not fl[i] & flag:
        fl[i] |= flag
        q[cnt[which]] = i
        cnt[which] += 1


@njit(cache=True)
def _fire(b, head, slot, ev, nd, fl, h_off, h_tgt, h_prob, hp, xq, yq, pend, cnt):
    """The events of level b and the layer (list `slot`): each lowers its
    robot turn's X if it offers less; the chunks go to the free list."""
    c = head[slot]
    head[slot] = -1
    while c >= 0:
        for k in range(1, int(ev[c, 0, 1]) + 1):
            _lower(b, int(ev[c, k, E_TURN]), ev[c, k, E_VALUE], int(ev[c, k, E_MOVE]), nd, fl, h_off, h_tgt, h_prob,
                   hp, xq, yq, pend, cnt, False)
        nxt = int(ev[c, 0, 0])
        ev[c, 0, 0] = cnt[C_FREE]
        cnt[C_FREE] = c
        c = nxt


@njit(cache=True)
def _lower(b, i, v, move, nd, fl, h_off, h_tgt, h_prob, hp, xq, yq, pend, cnt, whole):
    """X(i) := v by `move` on level b if that is lower, and what reads X(i)
    follows: the human turn at i (its pass, `_follow_pass`) and those of
    the layer above whose moves lead to i (`_follow_up`)."""
    old = nd[i, X]
    if not v < old:
        return
    nd[i, X], nd[i, XCH] = v, move
    _queue(fl, i, XQUEUED, xq, cnt, C_NXQ)
    _follow_pass(b, i, v, old, nd, fl, h_off, h_tgt, h_prob, yq, cnt, whole)
    _follow_up(b, i, v - old, nd, fl, hp, pend, cnt)


@njit(cache=True)
def _first_human(b, h, yorder, ynext, ycut, ylo, yhi, nd, fl, h_off, h_tgt, h_prob, yq, cnt):
    """The human turns of layer h whose first budget is b: summed once
    (again later if a zero-cost move is not settled yet), queued."""
    while ynext[h] < ycut[h + 1] and ylo[yorder[ynext[h]]] <= b:
        t = yorder[ynext[h]]
        ynext[h] += 1
        if ylo[t] == b and b <= yhi[t]:
            nd[t, Y] = _sum(t, nd, h_off, h_tgt, h_prob)
            if nd[t, Y] == np.inf:
                continue  # a zero-cost move not settled yet: summed again when it is
            fl[t] |= SUMMED
            _queue(fl, t, YQUEUED, yq, cnt, C_NYQ)


@njit(cache=True)
def _settle(b, h, W, K, head, ev, nd, fl, rp, hp, h_off, h_tgt, h_prob, xq, yq, pend, cnt, xrec, xval, yrec,
            yval):
    """The changes of level b and layer h passed on until none is left:
    each changed X and Y recorded; a changed Y(t) to the robot moves into
    t, by an event for level b + c (`_offer`), or at once where c = 0
    (the zero-cost moves read the same level: round the work lists until
    no value falls).  Returns the events' rows (grown, maybe)."""
    while cnt[C_NXQ] > 0 or cnt[C_NYQ] > 0:
        while cnt[C_NXQ] > 0:
            cnt[C_NXQ] -= 1
            i = xq[cnt[C_NXQ]]
            fl[i] &= ~XQUEUED
            cnt[C_NX] = _record(nd, i, XLAST, XLEV, xrec, xval, cnt[C_NX], b, nd[i, X], int(nd[i, XCH]))
        while cnt[C_NYQ] > 0:
            cnt[C_NYQ] -= 1
            t = yq[cnt[C_NYQ]]
            fl[t] &= ~YQUEUED
            y = nd[t, Y]
            cnt[C_NY] = _record(nd, t, YLAST, YLEV, yrec, yval, cnt[C_NY], b, y, -1)
            for p in range(int(nd[t, RS]), int(nd[t, RE])):
                if b <= rp[p, P_KEY]:
                    break  # this source and the rest read Y(t) on their first level
                c = rp[p, P_COST]
                if b + c > rp[p, P_HI]:
                    continue  # beyond the source's budgets
                i = rp[p, P_SRC]
                if c == 0:
                    _lower(b, i, y, rp[p, P_MOVE], nd, fl, h_off, h_tgt, h_prob, hp, xq, yq, pend, cnt, True)
                elif c + y < nd[i, X]:  # else no better than X(i) now, which X(i) on level b + c is at most
                    ev = _offer(ev, head, ((b + c) % W) * (K + 1) + h, i, rp[p, P_MOVE], c + y, cnt)
    return ev


@njit(cache=True)
def _offer(ev, head, slot, i, move, value, cnt):
    """An event (i, move, value) onto list `slot`: into its first chunk,
    or a new one from the free list; the chunks (grown, maybe)."""
    c = head[slot]
    if c < 0 or ev[c, 0, 1] == ev.shape[1] - 1:
        d = cnt[C_FREE]
        if d >= 0:
            cnt[C_FREE] = int(ev[d, 0, 0])
        else:
            if cnt[C_EVENTS] == len(ev):
                ev = _grow_chunks(ev)
            d = cnt[C_EVENTS]
            cnt[C_EVENTS] += 1
        ev[d, 0, 0], ev[d, 0, 1] = c, 0
        head[slot] = c = d
    k = int(ev[c, 0, 1]) + 1
    ev[c, k, E_TURN], ev[c, k, E_MOVE], ev[c, k, E_VALUE] = i, move, value
    ev[c, 0, 1] = k
    return ev


@njit(cache=True)
def _follow_up(b, j, delta, nd, fl, hp, pend, cnt):
    """Robot turn j's X fell by -delta on level b: the human turns of the
    layer above whose moves lead to j follow (those summed already: their
    first level is below b, and the moves are sorted by it), and are
    listed as changed for that layer."""
    for p in range(int(nd[j, HS]), int(nd[j, HE])):
        if hp[p, Q_KEY] >= b:
            break
        if b <= hp[p, Q_HI] and hp[p, Q_PROB] > 0.0:
            t = int(hp[p, Q_SRC])
            nd[t, Y] += hp[p, Q_PROB] * delta
            _queue(fl, t, YQUEUED, pend, cnt, C_NPEND)


@njit(cache=True)
def _sum(t, nd, h_off, h_tgt, h_prob):
    """Y at human turn t from the X of its pass and moves (inf while one is)."""
    y = nd[t, STAY] * nd[t, X] if nd[t, STAY] > 0.0 else 0.0
    for e in range(h_off[t], h_off[t + 1]):
        j = h_tgt[e]
        if j >= 0 and h_prob[e] > 0.0:
            y += h_prob[e] * nd[j, X]
    return y


@njit(cache=True)
def _follow_pass(b, i, new, old, nd, fl, h_off, h_tgt, h_prob, yq, cnt, whole):
    """Robot turn i's X fell from old to new on level b: the human turn at
    the same node, whose pass leads to it, follows, queued.  It is summed
    whole when it could not be summed before (a zero-cost move unsettled
    then), and with `whole`: inside the zero-cost iteration, where adding
    the differences would let the values creep down by roundings instead
    of settling."""
    if not fl[i] & HUMAN or not nd[i, YLO] <= b <= nd[i, YHI]:
        return
    if fl[i] & SUMMED and not whole:
        if nd[i, STAY] > 0.0:
            nd[i, Y] += nd[i, STAY] * (new - old)
    else:
        y = _sum(i, nd, h_off, h_tgt, h_prob)
        if y == np.inf:
            return
        nd[i, Y] = y
        fl[i] |= SUMMED
    _queue(fl, i, YQUEUED, yq, cnt, C_NYQ)
