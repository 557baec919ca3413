"""The compiled solver's kernels: numba functions over the integer tables of
`packed.tables`, compiled on first use and cached on disk (`cache=True`).

- move generation: `_robot_moves`, `_human_moves` (docs/game-semantics.md
  §4-§5, in `game/abstraction.py`'s order), the task's letter `_letter` and
  the canonical form of interchangeable objects `_canon`;
- exploration by layers of h, the human's moves left (driven batch by
  batch from `packed.explore`): a node is a robot-turn position, flagged
  when the human turn at the same position is reached; layer k is closed
  under robot moves through an open-addressing hash table, then the
  human's moves from it seed layer k - 1.  The moves of a batch of nodes
  are generated on numba's threads (`_robot_batch`, `_human_batch`) and
  their new targets added in order by one thread (`_robot_layer`,
  `_human_layer`), so the numbering does not depend on the thread count;
- solving back up (`_solve`): the human's moves lead into a layer solved
  already, so each human turn's best reply K is a number before its own
  layer is solved; Dijkstra (a bucket queue) runs on the robot moves alone
  (`_solve_layer`).  Human moves not kept while exploring are generated again
  and their values looked up in a hash table of the layer below.

The hot loops run in functions whose arrays are never reassigned (growth
happens between calls): numba then emits no reference counting inside them.
All kernels live in this one module on purpose: numba's cache checks the
source file of the kernel it loads, not of the kernels that one calls.
"""

from __future__ import annotations

import os
import sys

import numba
import numpy as np
from numba import njit, prange, types
from numba.core.typing import signature

# Moves are generated on numba's threads (NUMBA_NUM_THREADS, default one per core).  Its
# OpenMP layer from GNU is not safe across fork (the bench and `symsynth.parallel` fork):
# "forksafe" takes TBB when installed, else numba's own workqueue.
if "NUMBA_THREADING_LAYER" not in os.environ:
    numba.config.THREADING_LAYER = "forksafe"  # type: ignore[attr-defined]  # numba.config: set at run time

INF = np.int64(1 << 60)
KIND_TRANSIT, KIND_GRAB, KIND_TRANSFER, KIND_DROP, KIND_SLIDE, KIND_PASS, KIND_MOVE = range(7)

@njit(cache=True)
def _letter(x, n, pb, atom_at, free_at, free_all):
    """The task's letter at packed state x: the atoms that hold, as a bit mask."""
    pmask = (1 << pb) - 1
    bits = 0
    gone = 0
    for i in range(n):
        p = (x >> (i * pb)) & pmask
        bits |= atom_at[i, p]
        gone |= free_at[p]
    return bits | (free_all & ~gone)


@njit(cache=True)
def _canon(x, n, m, F, pb, eb, class_members, class_offsets, place_rank, rank_place, desc):
    """The canonical state of x's orbit: in each class, the members' (place,
    frame aimed at) sorted by rank and handed out in member order (`desc`:
    scratch space for n integers)."""
    classes = len(class_offsets) - 1
    if classes == 0:
        return x
    pmask = (1 << pb) - 1
    eshift = n * pb
    ee = (x >> eshift) & ((1 << eb) - 1)
    holder, frame = -1, -1
    if ee > m:
        holder = (ee - 1 - m) // F
        frame = (ee - 1 - m) % F
    new_ee = ee
    out = x
    fb = _fbits(F)
    fmask = (1 << fb) - 1
    for c in range(classes):
        lo, hi = class_offsets[c], class_offsets[c + 1]
        size = hi - lo
        for j in range(size):
            i = class_members[lo + j]
            d = place_rank[(x >> (i * pb)) & pmask] << fb  # (rank, frame aimed at + 1): no division
            if i == holder:
                d += 1 + frame
            desc[j] = d
        for a in range(1, size):  # insertion sort
            key = desc[a]
            b = a - 1
            while b >= 0 and desc[b] > key:
                desc[b + 1] = desc[b]
                b -= 1
            desc[b + 1] = key
        for j in range(size):
            i = class_members[lo + j]
            place = rank_place[desc[j] >> fb]
            out = (out & ~(pmask << (i * pb))) | (place << (i * pb))
            f = desc[j] & fmask
            if f > 0:
                new_ee = 1 + m + i * F + (f - 1)
    return (out & ~(((1 << eb) - 1) << eshift)) | (new_ee << eshift)


@njit(cache=True)
def _rule_min(start, count, free, rule_free, rule_units):
    """The cheapest rule of a cell whose free set is inside `free` (the cell's
    rules are sorted by cost: the first one)."""
    for r in range(start, start + count):
        if (rule_free[r] & ~free) == 0:
            return rule_units[r]
    return INF


@njit(cache=True)
def _motion(mode, S, slen, T, tlen, free, rule_start, rule_count, rule_free, rule_units):
    """max over s in S[:slen], t in T[:tlen] of the cheapest satisfied rule (0 when s = t)."""
    if slen == 0 or tlen == 0:
        return INF
    worst = 0
    for a in range(slen):
        s = S[a]
        for b in range(tlen):
            t = T[b]
            if s == t:
                continue
            c = _rule_min(rule_start[mode, s, t], rule_count[mode, s, t], free, rule_free, rule_units)
            if c > worst:
                worst = c
                if c >= INF:
                    return INF
    return worst


@njit(cache=True)
def _code(kind, obj, frame, loc, n, F, m):
    return ((kind * (n + 1) + obj) * (F + 1) + frame) * (m + 2) + loc


@njit(cache=True)
def _slot(key, bits):
    return np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(64 - bits))


@njit(cache=True)
def _find(table, bits, key):
    """The index stored with `key` in the hash table, -1 if absent (the key
    sits next to its index: one cache line per probe)."""
    mask = (1 << bits) - 1
    a = _slot(key, bits)
    while True:
        k = table[a, 0]
        if k == key:
            return table[a, 1]
        if k < 0:
            return -1
        a = (a + 1) & mask


@njit(cache=True)
def _insert(table, bits, key, index):
    mask = (1 << bits) - 1
    a = _slot(key, bits)
    while table[a, 0] >= 0:
        a = (a + 1) & mask
    table[a, 0] = key
    table[a, 1] = index


@njit(cache=True)
def _grow(a, size):
    b = np.empty(size, a.dtype)
    b[:len(a)] = a
    return b


@njit(cache=True)
def _free_masks(at, n, m, samples_mask, free):
    """free[o]: the places that count as free for a move serving object o (a
    mask over L ∪ E: the locations no other object stands at, and the Else
    samples when no other object is in Else)."""
    for o in range(n):
        occupied = 0
        else_other = False
        for j in range(n):
            if j != o:
                if at[j] < m:
                    occupied |= 1 << at[j]
                elif at[j] == m:
                    else_other = True
        f = ((1 << m) - 1) & ~occupied
        if not else_other:
            f |= samples_mask
        free[o] = f


@njit(cache=True)
def _robot_moves(x, n, m, F, pb, eb, gb, anchor_at, anchor_count, home_starts, samples_mask,
                 rule_start, rule_count, rule_free, rule_units, slide_start, slide_count, is_grasp,
                 grab_units, drop_units, at, free, S, T, mv_after, mv_units, mv_code):
    """The robot's moves at packed state x (docs/game-semantics.md §4, in
    game/abstraction.py's order) into mv_*: (state after, units, code); their count."""
    pmask = (1 << pb) - 1
    eshift = n * pb
    emask = (1 << eb) - 1
    gshift = eshift + eb
    for j in range(n):
        at[j] = (x >> (j * pb)) & pmask
    ee = (x >> eshift) & emask
    grip = (x >> gshift) & ((1 << gb) - 1)
    occupied = 0
    held = -1
    for j in range(n):
        if at[j] < m:
            occupied |= 1 << at[j]
        elif at[j] == m + 1:
            held = j
    _free_masks(at, n, m, samples_mask, free)
    nm = 0
    # the anchors v may stand for
    if grip != 0 or ee > m:
        if grip != 0:
            place = m if ee == 0 else ee - 1
            f = grip - 1
        else:
            place = at[(ee - 1 - m) // F]
            f = (ee - 1 - m) % F
        slen = anchor_count[place, f]
        for a in range(slen):
            S[a] = anchor_at[place, f, a]
    else:
        slen = len(home_starts)
        for a in range(slen):
            S[a] = home_starts[a]
    if held < 0:
        for o in range(n):
            for f in range(F):
                aim = 1 + m + o * F + f
                if ee == aim:
                    continue
                tlen = anchor_count[at[o], f]
                for a in range(tlen):
                    T[a] = anchor_at[at[o], f, a]
                c = _motion(0, S, slen, T, tlen, free[o], rule_start, rule_count, rule_free, rule_units)
                if c < INF:
                    mv_after[nm] = (x & ~(emask << eshift)) | (aim << eshift)
                    mv_units[nm] = c
                    mv_code[nm] = _code(KIND_TRANSIT, o, f, 0, n, F, m)
                    nm += 1
        if ee > m:
            o = (ee - 1 - m) // F
            f = (ee - 1 - m) % F
            if is_grasp[f]:
                if grab_units < INF:
                    y = (x & ~(pmask << (o * pb))) | ((m + 1) << (o * pb))
                    spot = 1 + at[o] if at[o] < m else 0
                    y = (y & ~(emask << eshift)) | (spot << eshift)
                    y |= (1 + f) << gshift
                    mv_after[nm] = y
                    mv_units[nm] = grab_units
                    mv_code[nm] = _code(KIND_GRAB, o, f, 0, n, F, m)
                    nm += 1
            elif at[o] < m:
                for l in range(m):
                    if occupied >> l & 1:
                        continue
                    c = _rule_min(slide_start[f, at[o], l], slide_count[f, at[o], l], free[o],
                                  rule_free, rule_units)
                    if c < INF:
                        mv_after[nm] = (x & ~(pmask << (o * pb))) | (l << (o * pb))
                        mv_units[nm] = c
                        mv_code[nm] = _code(KIND_SLIDE, o, f, l, n, F, m)
                        nm += 1
    else:
        o = held
        g = grip - 1
        mode = 1 + o * F + g
        for l in range(m):
            if occupied >> l & 1 or ee == 1 + l:
                continue
            T[0] = anchor_at[l, g, 0]
            c = _motion(mode, S, slen, T, 1, free[o], rule_start, rule_count, rule_free, rule_units)
            if c < INF:
                mv_after[nm] = (x & ~(emask << eshift)) | ((1 + l) << eshift)
                mv_units[nm] = c
                mv_code[nm] = _code(KIND_TRANSFER, o, g, l, n, F, m)
                nm += 1
        if 1 <= ee <= m and not (occupied >> (ee - 1) & 1) and drop_units < INF:
            y = (x & ~(pmask << (o * pb))) | ((ee - 1) << (o * pb))
            y &= ~(((1 << gb) - 1) << gshift)
            y = (y & ~(emask << eshift)) | ((1 + m + o * F + g) << eshift)
            mv_after[nm] = y
            mv_units[nm] = drop_units
            mv_code[nm] = _code(KIND_DROP, o, g, ee - 1, n, F, m)
            nm += 1
    return nm


@njit(cache=True)
def _fbits(F):
    """Bits for a frame aimed at + 1 (0: none) in a canonical sort key."""
    fb = 1
    while (1 << fb) <= F:
        fb += 1
    return fb


@njit(cache=True)
def _human_moves(x, n, m, F, pb, eb, gb, mv_after, obj_class, obj_pos, class_members, class_offsets,
                 place_rank, rank_place, dd, letters, atom_at, free_at, free_all):
    """The human's moves at packed state x (§5: one object not in the hand to a
    free location, not the one the gripper is aligned over, or to Else) into
    mv_after, canonical when x is (below), and the task's letter after each
    into letters; their count.

    The letter is the one of the move before canonicalizing: the other
    objects' atoms, OR-ed once per moved object, and the moved object's at
    its new place (2 table reads a move instead of n).  Canonicalizing
    permutes objects of one class, whose atoms are the same (the premise of
    the reduction), so it is the canonical state's letter too.

    x canonical: in each class the members' sort keys (place rank, frame
    aimed at) ascend in member order.  A move changes one member's key, so
    the canonical state is x with that key moved to its place in the order,
    the members in between shifting by one (what `_canon` would find, without
    sorting).  dd: scratch space for n integers."""
    pmask = (1 << pb) - 1
    eshift = n * pb
    emask = (1 << eb) - 1
    ee = (x >> eshift) & emask
    grip = (x >> (eshift + eb)) & ((1 << gb) - 1)
    fb = _fbits(F)
    fmask = (1 << fb) - 1
    holder = (ee - 1 - m) // F if ee > m else -1
    occupied = 0
    for j in range(n):
        p = (x >> (j * pb)) & pmask
        if p < m:
            occupied |= 1 << p
        dd[j] = place_rank[p] << fb
        if j == holder:
            dd[j] += 1 + (ee - 1 - m) % F
    aligned = ee - 1 if grip != 0 and 1 <= ee <= m else -1
    nm = 0
    for o in range(n):
        p = (x >> (o * pb)) & pmask
        if p == m + 1:
            continue
        aimed = o == holder
        c = obj_class[o]
        others = 0  # the atoms the other objects make true, and the free atoms they make false
        gone = 0
        for j in range(n):
            if j != o:
                pj = (x >> (j * pb)) & pmask
                others |= atom_at[j, pj]
                gone |= free_at[pj]
        for t in range(m + 1):
            if t < m and (occupied >> t & 1 or t == aligned):
                continue
            letters[nm] = others | atom_at[o, t] | (free_all & ~(gone | free_at[t]))
            y = (x & ~(pmask << (o * pb))) | (t << (o * pb))
            if aimed:
                y &= ~(emask << eshift)
            if c >= 0:
                first = class_offsets[c]
                last = class_offsets[c + 1] - 1
                r = first + obj_pos[o]
                d = place_rank[t] << fb
                if r > first and d < dd[class_members[r - 1]]:
                    while r > first and d < dd[class_members[r - 1]]:
                        y = _assign(y, class_members[r], dd[class_members[r - 1]], m, F, pb, eshift, emask,
                                    fb, fmask, rank_place)
                        r -= 1
                    y = _assign(y, class_members[r], d, m, F, pb, eshift, emask, fb, fmask, rank_place)
                elif r < last and d > dd[class_members[r + 1]]:
                    while r < last and d > dd[class_members[r + 1]]:
                        y = _assign(y, class_members[r], dd[class_members[r + 1]], m, F, pb, eshift, emask,
                                    fb, fmask, rank_place)
                        r += 1
                    y = _assign(y, class_members[r], d, m, F, pb, eshift, emask, fb, fmask, rank_place)
            mv_after[nm] = y
            nm += 1
    return nm


@njit(cache=True)
def _assign(y, i, d, m, F, pb, eshift, emask, fb, fmask, rank_place):
    """y with object i given sort key d: its place, and the end-effector's
    aim when d carries a frame."""
    pmask = (1 << pb) - 1
    y = (y & ~(pmask << (i * pb))) | (rank_place[d >> fb] << (i * pb))
    f = d & fmask
    if f > 0:
        y = (y & ~(emask << eshift)) | ((1 + m + i * F + (f - 1)) << eshift)
    return y


if sys.platform.startswith("linux"):
    _madvise = types.ExternalFunction("madvise", signature(types.int32, types.uintp, types.uintp, types.int32))
    MADV_HUGEPAGE = 14

    @njit(cache=True)
    def _huge(a):
        """Asks Linux to back array a (not yet touched) with 2 MB pages: its
        random reads then miss the TLB far less (a hash table probed at random:
        1.7x faster reads measured).  Advice only; its failure changes nothing."""
        start = (a.ctypes.data + 4095) & ~4095
        end = (a.ctypes.data + a.size * a.itemsize) & ~4095
        if end > start:
            _madvise(start, end - start, MADV_HUGEPAGE)  # type: ignore[call-overload]  # numba: callable in njit code only
else:
    @njit(cache=True)
    def _huge(a):
        """Huge pages are asked for on Linux only."""


@njit(cache=True)
def _table(bits):
    """An empty hash table of 2^bits slots (key, index); -1: empty."""
    table = np.empty((1 << bits, 2), np.int64)
    _huge(table)
    table[:] = -1
    return table


@njit(cache=True)
def _probe(table, bits, key, new):
    """The index stored with `key` in the hash table; when absent, `key` is
    stored with index `new` and `new` returned (one probe sequence)."""
    mask = (1 << bits) - 1
    a = _slot(key, bits)
    while True:
        k = table[a, 0]
        if k == key:
            return table[a, 1]
        if k < 0:
            table[a, 0] = key
            table[a, 1] = new
            return new
        a = (a + 1) & mask


@njit(cache=True)
def _rehash(keys, lo, count, bits):
    """A hash table of 2^bits slots holding keys[lo:count] with their indices."""
    table = _table(bits)
    for r in range(lo, count):
        _insert(table, bits, keys[r], r)
    return table


@njit(cache=True)
def _targets(mv_after, nm, canonical, q, n, m, F, pb, eb, qbits, class_members, class_offsets, place_rank,
             rank_place, desc, atom_at, free_at, free_all, trans, accepting, table, bits, letters):
    """The keys of the nodes the moves mv_after[:nm] lead to, in place (-1:
    the task is won; `canonical`: the states are canonical already, with
    their letters in `letters`).  Then each key's first slot in the hash table is read,
    all at once, so that the cache misses overlap; returns what was read, that
    the reads stay."""
    for e in range(nm):
        w = mv_after[e]
        if canonical:
            q2 = trans[q, letters[e]]
        else:
            w = _canon(w, n, m, F, pb, eb, class_members, class_offsets, place_rank, rank_place, desc)
            q2 = trans[q, _letter(w, n, pb, atom_at, free_at, free_all)]
        mv_after[e] = -1 if accepting[q2] else w << qbits | q2
    seen = 0
    for e in range(nm):
        if mv_after[e] >= 0:
            seen ^= table[_slot(mv_after[e], bits), 0]
    return seen


@njit(cache=True)
def _room_nodes(keys, hflag, r_off, h_off, count, room, store):
    """The per-node arrays, grown when `room` more nodes would not fit (h_off
    while the human moves are stored)."""
    if count + room > len(keys):
        size = 2 * (count + room)
        keys = _grow(keys, size)
        hflag = _grow(hflag, size)
        hflag[count:] = 0
        r_off = _grow(r_off, size + 1)
        if store:
            h_off = _grow(h_off, size + 1)
    return keys, hflag, r_off, h_off


@njit(cache=True)
def _known(moves, nm, table, bits):
    """Each target key among moves[:nm] found in the table (only read) as
    node j becomes -2 - j."""
    for e in range(nm):
        if moves[e] >= 0:
            j = _find(table, bits, moves[e])
            if j >= 0:
                moves[e] = -2 - j


@njit(cache=True, parallel=True)
def _robot_batch(b0, b1, keys, out, mvb, cnt, room, table, bits, n, m, F, pb, eb, gb, qbits, anchor_at,
                 anchor_count, home_starts, samples_mask, rule_start, rule_count, rule_free, rule_units,
                 slide_start, slide_count, is_grasp, grab_units, drop_units, atom_at, free_at, free_all, trans,
                 accepting, class_members, class_offsets, place_rank, rank_place, code_bits):
    """The robot's moves from nodes b0..b1, on numba's threads, as
    `_human_batch` leaves the human's: node i's targets in
    out[(i - b0) * room:] (-1 a win, -2 - j found as node j, else the key of
    a node not in the table when the batch began), each move's units <<
    code_bits | code at the same place in mvb, their count in cnt[i - b0]."""
    size = b1 - b0
    chunks = min(size, 64)
    for c in prange(chunks):
        at = np.empty(n, np.int64)
        free = np.empty(n, np.int64)
        desc = np.empty(n, np.int64)
        S = np.empty(len(home_starts) + anchor_at.shape[2], np.int64)
        T = np.empty(anchor_at.shape[2], np.int64)
        units = np.empty(room, np.int64)
        codes = np.empty(room, np.int64)
        for i in range(b0 + size * c // chunks, b0 + size * (c + 1) // chunks):
            key = keys[i]
            base = (i - b0) * room
            moves = out[base:base + room]
            nm = _robot_moves(key >> qbits, n, m, F, pb, eb, gb, anchor_at, anchor_count, home_starts,
                              samples_mask, rule_start, rule_count, rule_free, rule_units, slide_start,
                              slide_count, is_grasp, grab_units, drop_units, at, free, S, T, moves, units, codes)
            sink = _targets(moves, nm, False, key & ((1 << qbits) - 1), n, m, F, pb, eb, qbits, class_members,
                            class_offsets, place_rank, rank_place, desc, atom_at, free_at, free_all, trans,
                            accepting, table, bits, units)
            for e in range(nm):
                mvb[base + e] = (units[e] << code_bits) | codes[e]
            _known(moves, nm, table, bits)
            cnt[i - b0] = nm | ((sink & 1) << 40)  # (keeps the first reads)


@njit(cache=True)
def _robot_layer(st, lo, b0, b1, room, keys, hflag, r_off, r_tgt, r_move, table, bits, out, mvb, cnt):
    """Breadth-first through the robot moves of the layer whose nodes start at
    `lo`: the moves `_robot_batch` left in out and mvb for nodes st[0]..b1,
    their new targets added in order, while the arrays have room for one
    more node's moves; st (i, count, ne, ...) is updated.  (The arrays are
    never reassigned in here: numba then counts no references in the loop.)"""
    i, count, ne, sink = st[0], st[1], st[2], st[5]
    while i < b1:
        if count + room > len(keys) or ne + room > len(r_tgt) or 2 * (count + room - lo) > len(table):
            break
        base = (i - b0) * room
        nm = cnt[i - b0] & ((1 << 32) - 1)
        count, sink = _number(out, base, nm, table, bits, keys, count, sink, r_tgt, ne)
        for e in range(nm):
            j = r_tgt[ne + e]
            if j >= 0:
                hflag[j] = 1
            r_move[ne + e] = mvb[base + e]
        ne += nm
        r_off[i + 1] = ne
        i += 1
    st[0], st[1], st[2], st[5] = i, count, ne, sink


@njit(cache=True, parallel=True)
def _human_batch(b0, b1, keys, hflag, out, cnt, room, table, bits, n, m, F, pb, eb, gb, qbits, atom_at,
                 free_at, free_all, trans, accepting, obj_class, obj_pos, class_members, class_offsets,
                 place_rank, rank_place):
    """The human's moves from the human turns of nodes b0..b1, on numba's
    threads (chunks of nodes, each with its own scratch): node i's moves in
    out[(i - b0) * room:] and their count in cnt[i - b0] (low 32 bits), each
    as -1 (the task is won), -2 - j (found as node j in `table`, only read in
    here; a node's first slots are read at once, so that the misses
    overlap) or the key of its node, not in the table when the batch began
    (`_human_layer` probes those, in order, so the nodes are numbered as
    a serial search numbers them)."""
    size = b1 - b0
    chunks = min(size, 64)
    for c in prange(chunks):
        desc = np.empty(n, np.int64)
        letters = np.empty(room, np.int64)
        for i in range(b0 + size * c // chunks, b0 + size * (c + 1) // chunks):
            cnt[i - b0] = 0
            if not hflag[i]:
                continue
            key = keys[i]
            moves = out[(i - b0) * room:(i - b0 + 1) * room]
            nm = _human_moves(key >> qbits, n, m, F, pb, eb, gb, moves, obj_class, obj_pos, class_members,
                              class_offsets, place_rank, rank_place, desc, letters, atom_at, free_at, free_all)
            sink = _targets(moves, nm, True, key & ((1 << qbits) - 1), n, m, F, pb, eb, qbits, class_members,
                            class_offsets, place_rank, rank_place, desc, atom_at, free_at, free_all, trans,
                            accepting, table, bits, letters)
            _known(moves, nm, table, bits)
            cnt[i - b0] = nm | ((sink & 1) << 40)  # (keeps the first reads)


@njit(cache=True)
def _number(out, base, nm, table, bits, keys, count, sink, tgt, t0):
    """The node numbers of the nm targets a batch left in out[base:] (-1 a
    win, -2 - j found as node j, else a key: probed, and added as node
    `count` when new), into tgt[t0:t0 + nm]; (count, sink) after them.  The
    first slots are read at once, so that the cache misses overlap."""
    for e in range(nm):
        if out[base + e] >= 0:
            sink ^= table[_slot(out[base + e], bits), 0]
    for e in range(nm):
        w = out[base + e]
        j = -1
        if w >= 0:
            j = _probe(table, bits, w, count)
            if j == count:
                keys[count] = w
                count += 1
        elif w < -1:
            j = -2 - w
        tgt[t0 + e] = j
    return count, sink


@njit(cache=True)
def _human_layer(st, lo, b0, b1, room, keys, h_off, h_tgt, table, bits, out, cnt):
    """The moves `_human_batch` left in out for nodes st[0]..b1, into the
    layer whose nodes start at `lo` (added there when new, in the order of
    the nodes and their moves), while the arrays have room for one more
    node's moves; st (i, count, ..., nh, store) is updated.  The moves are
    counted, and stored (h_off, h_tgt: their target nodes, -1 for a win)
    while st[4] says so."""
    i, count, nh, store, sink = st[0], st[1], st[3], st[4], st[5]
    scratch = np.empty(room, np.int64)  # the targets' numbers while they are not stored
    while i < b1:
        if (count + room > len(keys) or 2 * (count + room - lo) > len(table)
                or (store and nh + room > len(h_tgt))):
            break
        base = (i - b0) * room
        nm = cnt[i - b0] & ((1 << 32) - 1)
        if store:
            count, sink = _number(out, base, nm, table, bits, keys, count, sink, h_tgt, nh)
        else:
            count, sink = _number(out, base, nm, table, bits, keys, count, sink, scratch, 0)
        nh += nm
        if store:
            h_off[i + 1] = nh
        i += 1
    st[0], st[1], st[3], st[5] = i, count, nh, sink


@njit(cache=True)
def _solve(keys, hflag, lo, hi, r_off, r_tgt, r_move, h_off, h_tgt, code_bits, n, m, F, pb, eb, gb, qbits,
           atom_at, free_at, free_all, trans, accepting, class_members, class_offsets, place_rank, rank_place):
    """The value of every node's robot turn (rval) and the robot's chosen move
    (choice, relative to r_off[i]; -1: none), layer by layer from h = 0 up;
    also the value of the start's human turn (node 0; INF: lost) and the
    number of human moves that found no node (0 unless there is a bug).

    The human's moves from layer h lead into layer h - 1, solved already, so
    each human turn's best move is a number K known before layer h is solved:
    from the stored moves (h_off, h_tgt) when exploring kept them, else the
    moves are generated again and looked up in a hash table of layer h - 1
    built from its keys with their values (one table alive at a time, freed
    before the layer is solved).  Then `_solve_layer`."""
    N = len(keys)
    rval = np.empty(N, np.int64)  # read at random by the human moves of the layer above
    _huge(rval)
    rval[:] = INF
    choice = np.full(N, -1, np.int16)
    C = np.int64(1)  # (numba literals are compiled for apart: np.int64 where a callee gets them)
    for e in range(len(r_move)):
        if (r_move[e] >> code_bits) + 1 > C:
            C = (r_move[e] >> code_bits) + 1
    top = INF
    missing = 0
    obj_class = np.full(n, -1, np.int64)  # each object's class and place in it
    obj_pos = np.zeros(n, np.int64)
    for c in range(len(class_offsets) - 1):
        for r in range(class_offsets[c], class_offsets[c + 1]):
            obj_class[class_members[r]] = c
            obj_pos[class_members[r]] = r - class_offsets[c]
    room = 4 * (n * (F + m + 2) + m + 2)  # the most moves a node can have
    for h in range(len(lo)):
        a, b = lo[h], hi[h]
        size = b - a
        K = np.empty(size, np.int64)  # the human's best move into layer h - 1 (-1: none)
        K[:] = -1
        if h > 0 and len(h_off) == N + 1:
            for i in range(a, b):
                best = -1
                for e in range(h_off[i], h_off[i + 1]):
                    t = h_tgt[e]
                    v = 0 if t < 0 else rval[t]
                    if v > best:
                        best = v
                K[i - a] = best
        elif h > 0:
            bits = np.int64(17)
            while (1 << bits) < 2 * (hi[h - 1] - lo[h - 1]):
                bits += 1
            table = _table(bits)  # layer h - 1's keys with their values
            for r in range(lo[h - 1], hi[h - 1]):
                _insert(table, bits, keys[r], rval[r])
            missing += _human_values_par(a, b, keys, hflag, K, table, bits, n, m, F, pb, eb, gb, qbits,
                                         atom_at, free_at, free_all, trans, accepting, obj_class, obj_pos,
                                         class_members, class_offsets, place_rank, rank_place, room)
            table = _table(np.int64(1))  # freed before the layer's scratch is taken
            missing &= (1 << 32) - 1
        moves = r_off[b] - r_off[a]
        hval = np.full(size, INF, np.int64)
        indeg = np.empty(size + 1, np.int32)  # fewer than 2^31 robot moves (solve_compiled)
        fill = np.empty(size, np.int32)
        waiting = np.empty(size, np.int32)
        pred = np.empty(moves, np.int32)
        psrc = np.empty(moves, np.int32)
        head = np.empty(C, np.int64)
        # ring entries: one per human turn at the start, then at most one per relaxation
        # (untouched pages of these cost no memory)
        entry_node = np.empty(size + moves, np.int32)
        entry_dist = np.empty(size + moves, np.int64)
        entry_next = np.empty(size + moves, np.int64)
        _solve_layer(a, b, C, code_bits, hflag, r_off, r_tgt, r_move, rval, hval, choice,
                     K, indeg, fill, waiting, pred, psrc, head, entry_node, entry_dist, entry_next)
        if a == 0:
            top = hval[0]
    return rval, choice, top, missing


@njit(cache=True, parallel=True)
def _human_values_par(a, b, keys, hflag, K, table, bits, n, m, F, pb, eb, gb, qbits, atom_at, free_at,
                      free_all, trans, accepting, obj_class, obj_pos, class_members, class_offsets,
                      place_rank, rank_place, room):
    """`_human_values` on the threads numba runs (`numba.set_num_threads`):
    the nodes a..b in chunks, each with its own scratch; the table and the
    layer below are only read, and each chunk writes its own part of K."""
    chunks = min(b - a, 256)  # (numba's thread count read in here would stop caching)
    missing = 0
    for c in prange(chunks):
        lo = a + (b - a) * c // chunks
        hi = a + (b - a) * (c + 1) // chunks
        desc = np.empty(n, np.int64)
        mv_after = np.empty(room, np.int64)
        mv_letter = np.empty(room, np.int64)
        missing += _human_values(lo, hi, a, keys, hflag, K, table, bits, n, m, F, pb, eb, gb, qbits, atom_at,
                                 free_at, free_all, trans, accepting, obj_class, obj_pos, class_members,
                                 class_offsets, place_rank, rank_place, desc, mv_after, mv_letter)
    return missing


@njit(cache=True)
def _human_values(a, b, base, keys, hflag, K, table, bits, n, m, F, pb, eb, gb, qbits, atom_at, free_at,
                  free_all, trans, accepting, obj_class, obj_pos, class_members, class_offsets, place_rank,
                  rank_place, desc, mv_after, mv_letter):
    """K[i - base] for the human turns i of nodes a..b: the largest value among
    the human's moves (0 for a move that wins, the value `table` holds with
    the key of its node in layer h - 1 otherwise: one random read per move),
    -1 with no move.  Returns how many moves found no node in the table (in
    the low 32 bits; the rest keeps the batched first reads alive)."""
    qmask = (1 << qbits) - 1
    missing = 0
    sink = 0
    for i in range(a, b):
        if not hflag[i]:
            continue
        key = keys[i]
        nm = _human_moves(key >> qbits, n, m, F, pb, eb, gb, mv_after, obj_class, obj_pos,
                          class_members, class_offsets, place_rank, rank_place, desc, mv_letter, atom_at,
                          free_at, free_all)
        sink ^= _targets(mv_after, nm, True, key & qmask, n, m, F, pb, eb, qbits, class_members,
                         class_offsets, place_rank, rank_place, desc, atom_at, free_at, free_all, trans,
                         accepting, table, bits, mv_letter)
        best = -1
        for e in range(nm):
            w = mv_after[e]
            v = 0
            if w >= 0:
                v = _find(table, bits, w)
                if v < 0:
                    missing += 1
                    continue
            if v > best:
                best = v
        K[i - base] = best
    return missing | ((sink & 1) << 40)


@njit(cache=True)
def _by_k(a, b, hflag, K, nodes, out):
    """The human turns i in a..b with 0 <= K[i - a] < INF into out, ordered by
    K then by i (a counting sort when K's range is small, a stable sort
    otherwise; `nodes` is scratch); their count."""
    nw = 0
    top = 0
    for i in range(a, b):
        if hflag[i] and 0 <= K[i - a] < INF:
            nodes[nw] = i
            nw += 1
            top = max(top, K[i - a])
    if top < 4 * nw + (1 << 16):
        start = np.zeros(top + 2, np.int64)
        for r in range(nw):
            start[K[nodes[r] - a] + 1] += 1
        for v in range(top + 1):
            start[v + 1] += start[v]
        for r in range(nw):
            v = K[nodes[r] - a]
            out[start[v]] = nodes[r]
            start[v] += 1
    else:
        order = np.argsort(K[nodes[:nw] - a], kind="mergesort")
        for r in range(nw):
            out[r] = nodes[order[r]]
    return nw


@njit(cache=True)
def _solve_layer(a, b, C, code_bits, hflag, r_off, r_tgt, r_move, rval, hval, choice,
                 K, indeg, fill, waiting, pred, psrc, head, entry_node, entry_dist, entry_next):
    """Layer a..b of `_solve`, the layers below it solved and K known: hval
    (relative to a) = max(K, rval), rval = min over robot moves of units +
    hval of the target.  Dijkstra's algorithm for min-cost reachability games
    (solvers/explicit.py) on the robot moves alone, with a bucket queue
    (Dial's: costs are small integers, so the human turns waiting to settle
    are kept in a ring of max-cost + 1 buckets) and the human turns whose K
    dominates released in order of K.  (The arrays are scratch, never
    reassigned in here: numba then counts no references.)"""
    size = b - a
    # the robot moves into each node of the layer, grouped by target
    ea, eb = r_off[a], r_off[b]
    indeg[:size + 1] = 0
    for e in range(ea, eb):
        t = r_tgt[e]
        if t >= 0:
            indeg[t - a + 1] += 1
    for j in range(size):
        indeg[j + 1] += indeg[j]
    fill[:size] = indeg[:size]
    for i in range(a, b):
        for e in range(r_off[i], r_off[i + 1]):
            t = r_tgt[e]
            if t >= 0:
                pred[fill[t - a]] = e - ea  # the move, relative to ea
                psrc[fill[t - a]] = i - a  # its source, relative to a
                fill[t - a] += 1
    # moves that win
    for i in range(a, b):
        for e in range(r_off[i], r_off[i + 1]):
            if r_tgt[e] < 0 and (r_move[e] >> code_bits) < rval[i]:
                rval[i] = r_move[e] >> code_bits
                choice[i] = e - r_off[i]
    head[:] = -1
    used = 0
    pending = 0
    # human turns whose K (finite) may come to dominate, in order of K (then of node)
    nw = _by_k(a, b, hflag, K, waiting, fill)
    released = fill
    for i in range(a, b):  # the rest start in the ring
        if hflag[i] and K[i - a] < INF and rval[i] < INF and rval[i] > K[i - a]:
            entry_node[used] = i - a
            entry_dist[used] = rval[i]
            entry_next[used] = head[rval[i] % C]
            head[rval[i] % C] = used
            used += 1
            pending += 1
    d = 0
    wp = 0
    while pending > 0 or wp < nw:
        if pending == 0 and K[released[wp] - a] > d:
            d = K[released[wp] - a]
        # settle the human turns released at d, then the ring's bucket d
        while True:
            if wp < nw and K[released[wp] - a] <= d:
                j = released[wp]
                wp += 1
                if hval[j - a] < INF or rval[j] > K[j - a]:
                    continue
            else:
                x = head[d % C]
                if x < 0:
                    break
                head[d % C] = entry_next[x]
                pending -= 1
                j = entry_node[x] + a
                if hval[j - a] < INF or entry_dist[x] != max(K[j - a], rval[j]):
                    continue  # settled already, or a stale entry
            hval[j - a] = d
            for p in range(indeg[j - a], indeg[j - a + 1]):
                e = pred[p] + ea
                i = psrc[p] + a
                cand = d + (r_move[e] >> code_bits)
                if cand < rval[i]:
                    rval[i] = cand
                    choice[i] = e - r_off[i]
                    if hflag[i] and hval[i - a] >= INF and K[i - a] < INF:
                        key = max(K[i - a], cand)
                        if key < d + C:
                            entry_node[used] = i - a
                            entry_dist[used] = key
                            entry_next[used] = head[key % C]
                            head[key % C] = used
                            used += 1
                            pending += 1
        d += 1


def dispatchers() -> list:
    """Every kernel of this module (numba dispatchers), for cache checks."""
    return [value for value in globals().values() if isinstance(value, numba.core.registry.CPUDispatcher)]
