"""Exploring the compiled solver's game layer by layer (`explore`): a Python
loop over batches of nodes, each batch's moves generated and added by the
kernels (`packed.kernels`), so that the loop can report progress.

A node is a key (packed state << qbits | DFA state) in a layer h: the
robot's turn there, and (hflag) the human's turn, whose pass leads to it.
Layer h is closed under robot moves (breadth-first from the nodes the layer
above reached by human moves, and the start); then the human turns of layer
h reach, by their moves, the seeds of layer h - 1.  The moves of `batch`
nodes at a time are generated on numba's threads and their targets looked
up in the layer's table (`_robot_batch`, `_human_batch`), then the new
targets added in order (`_robot_layer`, `_human_layer`): the nodes are
numbered as one thread numbers them.  The arrays grow between those calls,
never inside them (numba then counts no references in the hot loops).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from symsynth.solvers.packed.kernels import (_grow, _human_batch, _human_layer, _insert, _rehash, _robot_batch,
                                             _robot_layer, _room_nodes, _table)

#: progress(h, nodes, lo, done): called after each batch with the layer, the nodes found so far,
#: the layers' first nodes and the end of the batch whose moves were generated (`packed.deadline`
#: reads them); it may raise to stop exploring, and the arrays go with explore's frame
Progress = Callable[[int, int, np.ndarray, int], None]


def explore(start, n, m, F, pb, eb, gb, qbits, k, anchor_at, anchor_count, home_starts, samples_mask,
            rule_start, rule_count, rule_free, rule_units, slide_start, slide_count, is_grasp,
            grab_units, drop_units, atom_at, free_at, free_all, trans, accepting,
            class_members, class_offsets, place_rank, rank_place, code_bits, human_cap, batch, *,
            progress: Progress | None = None) -> tuple:
    """Every node the start (the human's turn at key `start`, h = k) reaches,
    layer by layer from h = k down to 0 (module doc).  Returns the keys,
    hflag, the layers' index ranges lo[h]..hi[h], the robot moves in CSR form
    (r_off; r_tgt: target node, -1 for a win; r_move: units << code_bits |
    action code), the number of human moves and, when there are at most
    `human_cap` of them (about 80% of all moves), the human moves in CSR
    form (h_off; h_tgt: target node in layer h - 1, -1 for a win); else
    h_off and h_tgt are empty and `_solve` generates the moves again."""
    np64 = np.int64
    n, m, F, pb, eb, gb, qbits, code_bits = (np64(x) for x in (n, m, F, pb, eb, gb, qbits, code_bits))
    keys = np.empty(1 << 16, np.int64)
    hflag = np.zeros(1 << 16, np.uint8)
    r_off = np.zeros((1 << 16) + 1, np.int64)
    h_off = np.zeros((1 << 16) + 1, np.int64)
    h_tgt = np.empty(min(1 << 18, human_cap), np.int32)
    r_tgt = np.empty(1 << 18, np.int32)
    r_move = np.empty(1 << 18, np.int32)
    lo = np.zeros(k + 1, np.int64)
    hi = np.zeros(k + 1, np.int64)
    bits = np64(17)
    table = _table(bits)  # open addressing: (key, index), -1 empty
    keys[0] = start
    hflag[0] = 1
    _insert(table, bits, np64(start), np64(0))
    obj_class = np.full(n, -1, np.int64)  # each object's class and place in it
    obj_pos = np.zeros(n, np.int64)
    for c in range(len(class_offsets) - 1):
        for r in range(class_offsets[c], class_offsets[c + 1]):
            obj_class[class_members[r]] = c
            obj_pos[class_members[r]] = r - class_offsets[c]
    room = np64(4 * (n * (F + m + 2) + m + 2))  # the most moves a node can have
    out = np.empty(batch * room, np.int64)  # a batch's moves (_robot_batch, _human_batch)
    mvb = np.empty(batch * room, np.int64)
    cnt = np.empty(batch, np.int64)
    b0 = np64(0)
    st = np.zeros(6, np.int64)  # i, count, ne, nh, store, sink: the kernels' loop state
    st[1] = 1
    st[4] = 1
    for h in range(k, -1, -1):
        # layer h: closed under robot moves from its seeds
        st[0] = lo[h]
        b1 = lo[h]
        while True:
            if st[0] == b1:  # the next batch of the layer's nodes, their moves generated on numba's threads
                if b1 == st[1]:
                    break
                b0, b1 = b1, min(st[1], b1 + batch)
                _robot_batch(b0, b1, keys, out, mvb, cnt, room, table, bits, n, m, F, pb, eb, gb, qbits,
                             anchor_at, anchor_count, home_starts, samples_mask, rule_start, rule_count,
                             rule_free, rule_units, slide_start, slide_count, is_grasp, grab_units, drop_units,
                             atom_at, free_at, free_all, trans, accepting, class_members, class_offsets,
                             place_rank, rank_place, code_bits)
                if progress is not None:
                    progress(h, int(st[1]), lo, int(b1))
            _robot_layer(st, lo[h], b0, b1, room, keys, hflag, r_off, r_tgt, r_move, table, bits, out, mvb, cnt)
            if st[0] == b1:
                continue
            keys, hflag, r_off, h_off = _room_nodes(keys, hflag, r_off, h_off, st[1], room, st[4])
            if st[2] + room > len(r_tgt):  # 1.5x: the move arrays are most of the memory
                size = st[2] + st[2] // 2 + room
                r_tgt = _grow(r_tgt, size)
                r_move = _grow(r_move, size)
            if 2 * (st[1] + room - lo[h]) > len(table):
                bits += 1
                table = _rehash(keys, lo[h], st[1], bits)
        hi[h] = st[1]
        if h == 0:
            if st[4]:
                h_off[lo[h] + 1:hi[h] + 1] = st[3]
            break
        # the human's moves from layer h: the seeds of layer h - 1
        lo[h - 1] = st[1]
        bits = np64(17)
        table = _table(bits)
        st[0] = lo[h]
        b1 = lo[h]
        while True:
            if st[0] == b1:  # the next batch of nodes, their moves generated on numba's threads
                if b1 == hi[h]:
                    break
                b0, b1 = b1, min(hi[h], b1 + batch)
                _human_batch(b0, b1, keys, hflag, out, cnt, room, table, bits, n, m, F, pb, eb, gb, qbits,
                             atom_at, free_at, free_all, trans, accepting, obj_class, obj_pos, class_members,
                             class_offsets, place_rank, rank_place)
                if progress is not None:
                    progress(h, int(st[1]), lo, int(b1))
            _human_layer(st, lo[h - 1], b0, b1, room, keys, h_off, h_tgt, table, bits, out, cnt)
            if st[0] == b1:
                continue
            keys, hflag, r_off, h_off = _room_nodes(keys, hflag, r_off, h_off, st[1], room, st[4])
            if st[4] and st[3] + room > len(h_tgt):
                if st[3] + room > human_cap:  # too many to keep: generated again when solving
                    st[4] = 0
                    h_off = np.zeros(1, np.int64)
                    h_tgt = np.empty(0, np.int32)
                else:
                    h_tgt = _grow(h_tgt, min(human_cap, st[3] + st[3] // 2 + room))
            if 2 * (st[1] + room - lo[h - 1]) > len(table):
                bits += 1
                table = _rehash(keys, lo[h - 1], st[1], bits)
    N, ne, nh = int(st[1]), int(st[2]), int(st[3])
    # views, not copies: a copy of the move arrays would hold them twice at the peak
    if st[4]:
        h_off, h_tgt = h_off[:N + 1], h_tgt[:nh]
    return keys[:N], hflag[:N], lo, hi, r_off[:N + 1], r_tgt[:ne], r_move[:ne], nh, h_off, h_tgt


def compile_growth() -> None:
    """Compile the kernels only a large game calls from here (the layer's
    table rebuilt larger, the arrays grown), with the types `explore` calls
    them with, so that `compiled.compile_kernels` leaves nothing to compile."""
    i64 = np.int64
    keys = np.zeros(4, np.int64)
    _rehash(keys, i64(0), i64(1), i64(2))
    _grow(np.zeros(2, np.int32), i64(4))
    _room_nodes(keys, np.zeros(4, np.uint8), np.zeros(5, np.int64), np.zeros(5, np.int64), i64(2), i64(4), i64(1))

