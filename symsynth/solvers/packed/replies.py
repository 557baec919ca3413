"""The replanning bound's kernels (`solvers.replan_budget` drives them and
proves what they compute): the human's replies on a plan of the replanning
strategy, checked in bulk against budgets on the no-human game's memo
(`solvers.andor.Memo` with k = 0).

- `_replies`: every human move at a list of turns (packed state, DFA state),
  as the memo's keys at h = 0 (-1: the move wins), with the turn it is at;
- `_plan`: σ's plan read back from the memo's chosen actions;
- `_settle`: each reply's key against its budget b, "V_0 <= b?": answered
  from the node's proven bounds when they decide it, else by the search
  (`packed.search._ask`), until the first "no" or the end; stops with a
  reason in st[ST_ABORT] as `_ask` does, to be called again from where it
  stopped.
"""

from __future__ import annotations

from numba import njit

from symsynth.solvers.packed.kernels import _find, _human_moves
from symsynth.solvers.packed.search import HI_R, KEY, R_OFF, ST_BITS, _ask, _lo_h, _node, _room, _small

# numba's disk cache checks only this file's source (tests/test_numba_cache.py)
COMPILED_WITH = {"kernels.py": "e4a5b3789bf06122", "search.py": "cfbdf5f663f7b748"}


@njit(cache=True)
def _replies(xs, qs, P, G, S, out_key, out_turn):
    """The human's moves at turns (xs[j], qs[j]) into out_key (the node key at
    h = 0 of the state after, -1 when the move makes the task hold) and
    out_turn (j); their count."""
    n, m, F, pb, eb, gb, qbits, hb = P[:8]
    free_all = P[12]
    atom_at, free_at, trans, accepting = G[10], G[11], G[12], G[13]
    class_members, class_offsets, place_rank, rank_place, obj_class, obj_pos = G[14:]
    desc, mv_after, letters = S[5], S[6], S[9]
    count = 0
    for j in range(len(xs)):
        nm = _human_moves(xs[j], n, m, F, pb, eb, gb, mv_after, obj_class, obj_pos, class_members, class_offsets,
                          place_rank, rank_place, desc, letters, atom_at, free_at, free_all)
        for e in range(nm):
            q2 = trans[qs[j], letters[e]]
            out_key[count] = -1 if accepting[q2] else ((mv_after[e] << qbits) | q2) << hb
            out_turn[count] = j
            count += 1
    return count


@njit(cache=True)
def _settle(keys, budgets, first, P, G, B, M, S, room):
    """Whether V_0 <= budgets[r] for every r >= first with keys[r] >= 0 (a
    node key at h = 0): the index of the first reply answered "no", len(keys)
    when all are "yes", or the index to go on from when st[ST_ABORT] is set
    (the arrays full, the questions used up, the stack too shallow, a move of
    0 units; what was proven is kept)."""
    table, rec = M[0], M[1]
    st = S[0]
    for r in range(first, len(keys)):
        key, b = keys[r], budgets[r]
        if key < 0:
            continue
        i = _find(table, st[ST_BITS], key)
        if i >= 0:
            if rec[i, HI_R] <= b:
                continue
            if _lo_h(rec, i) > b:
                return r
        elif not _room(M, S, room):
            return r
        else:
            i = _node(key, P, B, M, S)
        if not _ask(i, b, True, P, G, B, M, S):
            return r
    return len(keys)


@njit(cache=True)
def _plan(i, rec, rm_tgt, rm_move, code_bits, hb, out_key, out_units):
    """The chosen actions from node i to the win: their units into out_units
    and the key (>> hb: packed state << qbits | DFA state) of the node after
    each but the last (which wins) into out_key; their count, -1 when the
    arrays are too short."""
    count = 0
    while count < len(out_units):
        e = rec[i, R_OFF] + _small(rec, i, 32) - 1
        out_units[count] = rm_move[e] >> code_bits
        i = rm_tgt[e]
        count += 1
        if i < 0:
            return count
        out_key[count - 1] = rec[i, KEY] >> hb
    return -1
