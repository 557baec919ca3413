"""The replanning bound's kernels (`solvers.replan_budget` drives them and
proves what they compute): the human's replies on a plan of the replanning
strategy, checked in bulk against budgets on the no-human game's memo
(`solvers.andor.Memo` with k = 0).

- `_replies`: every human move at a list of turns (packed state, DFA state),
  as the memo's keys at h = 0 (-1: the move wins), with the turn it is at;
- `_plan`: σ's plan read back from the memo's chosen actions;
- `_repair`: the cost of a sequence of robot actions that undoes a human
  move (puts the moved object back, and the hand where it was), each action
  generated at the state it is played in, so a plan whose cost bounds V_0
  from above whatever the game (-1 when the sequence is not legal there or
  does not come back); `_repair_path` the same plan action by action, for
  the strategy that repairs (`solvers.replan_repair`);
- `_follow`: σ's own next actions played after a human move, until the play
  meets σ's plan again (or wins), the moved object parked out of σ's way
  once if it blocks an action: again a plan, so again a bound on V_0;
- `_act`: one robot action played where the certificates need it, only
  that action generated (`_robot_move`: the branch of
  `kernels._robot_moves` that makes it, checked against it at every state
  of small scenes), not every move there;
- `_settle`: each reply's key against its budget b, "V_0 <= b?": answered
  from the node's proven bounds when they decide it, else by the repair
  (V_0(after) <= repair + V_0(turn)), else by σ's plan followed, else by the search
  (`packed.search._ask`), until the first "no" or the end; stops with a
  reason in st[ST_ABORT] as `_ask` does, to be called again from where it
  stopped.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from symsynth.solvers.packed.kernels import (INF, KIND_DROP, KIND_GRAB, KIND_SLIDE, KIND_TRANSFER, KIND_TRANSIT,
                                             _code, _find, _human_moves, _letter, _motion, _rule_min)
from symsynth.solvers.packed.search import HI_R, KEY, R_OFF, ST_BITS, _ask, _lo_h, _node, _room, _small

# numba's disk cache checks only this file's source (tests/test_numba_cache.py)
COMPILED_WITH = {"kernels.py": "e4a5b3789bf06122", "search.py": "8826aee9e9f8d25b"}


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
def _settle(keys, budgets, turn, xs, qs, bases, codes, first, P, G, B, M, S, room, counts, upper):
    """Whether V_0 <= budgets[r] for every r >= first with keys[r] >= 0 (a
    node key at h = 0, a human move at the turn (xs[j], qs[j]) of σ's plan
    whose V_0 is bases[j] and whose next action is codes[j], j = turn[r]):
    the index of the first reply answered "no",
    len(keys) when all are "yes", or the index to go on from when
    st[ST_ABORT] is set (the arrays full, the questions used up, the stack
    too shallow, a move of 0 units; what was proven is kept).  counts: the
    replies answered by the memo, by a repair, by the plan followed, by the
    search.  upper[r]: the bound on V_0 that answered reply r "yes" (the
    node's hi, the repair's or the followed plan's cost plus V_0 where it
    ends; 0 for a move that wins), at most budgets[r]."""
    table, rec = M[0], M[1]
    st = S[0]
    hb, qbits = P[7], P[6]
    for r in range(first, len(keys)):
        key, b = keys[r], budgets[r]
        upper[r] = 0
        if key < 0:
            continue
        i = _find(table, st[ST_BITS], key)
        if i >= 0:
            upper[r] = rec[i, HI_R]
            if upper[r] <= b:
                counts[0] += 1
                continue
            if _lo_h(rec, i) > b:
                return r
        j = turn[r]
        fix = _repair(xs[j], qs[j], (key >> hb) >> qbits, (key >> hb) & ((1 << qbits) - 1), P, G, S)
        if 0 <= fix <= b - bases[j]:
            upper[r] = fix + bases[j]
            counts[1] += 1
            continue
        upper[r] = _follow(j, (key >> hb) >> qbits, (key >> hb) & ((1 << qbits) - 1), xs, qs, bases, codes, b, P, G, S)
        if 0 <= upper[r]:
            counts[2] += 1
            continue
        counts[3] += 1
        if i < 0:
            if not _room(M, S, room):
                return r
            i = _node(key, P, B, M, S)
        if not _ask(i, b, True, P, G, B, M, S):
            return r
        upper[r] = rec[i, HI_R]
    return len(keys)


@njit(cache=True)
def _follow(j, w, q2, xs, qs, bases, codes, b, P, G, S):
    """An upper bound <= b on V_0(w, q2), w a human move at turn j of σ's plan:
    σ's next actions (codes[j], codes[j + 1], ...) played from w, each
    generated where it is played, until the state meets the plan's (then its
    cost + V_0 there), the task holds (its cost), or, once the hand is free,
    a repair (`_repair`) brings it back to the plan's state.  The moved
    object is parked out of σ's way (`_park`) when it stands where σ will
    carry something, or blocks an action (`_swap` when the hand is full).
    -1 when an action is still not
    available, the cost passes b, or the plan ends first."""
    gb, eb, n, pb = P[5], P[4], P[0], P[3]
    accepting = G[13]
    out = np.empty(3, np.int64)
    y, qq, total = w, q2, 0
    parked = _park(y, qq, xs[j], codes, j, True, P, G, S, out)
    if parked:
        y, qq, total = out[0], out[1], out[2]
    repaired = False
    step = j
    while step < len(codes):
        _act(y, qq, codes[step], P, G, S, out)
        if out[2] < 0:
            x = xs[step] if step < len(xs) else -1
            if parked or not (_park(y, qq, x, codes, step, False, P, G, S, out)
                              or _swap(y, qq, x, codes, step, P, G, S, out)):
                return -1
            parked = True
        else:
            step += 1
        y, qq, total = out[0], out[1], total + out[2]
        if total > b:
            return -1
        if accepting[qq]:
            return total
        if step < len(xs) and y == xs[step] and qq == qs[step]:
            return total + bases[step] if total + bases[step] <= b else -1
        if step < len(xs) and not repaired and (y >> (n * pb + eb)) & ((1 << gb) - 1) == 0:
            repaired = True
            fix = _repair(xs[step], qs[step], y, qq, P, G, S)
            if 0 <= fix and total + fix + bases[step] <= b:
                return total + fix + bases[step]
    return -1


@njit(cache=True)
def _ahead(codes, step, n, m, F):
    """The locations σ's actions codes[step:] carry something to, as a bit mask."""
    mask = 0
    for e in range(step, len(codes)):
        if codes[e] // ((m + 2) * (F + 1) * (n + 1)) == KIND_TRANSFER:
            mask |= 1 << (codes[e] % (m + 2))
    return mask


@njit(cache=True)
def _first_grasp(is_grasp):
    """The first preimage that is a grasp, -1 when none is."""
    for f in range(len(is_grasp)):
        if is_grasp[f]:
            return f
    return -1


@njit(cache=True)
def _park(y, q, x, codes, step, only_in_the_way, P, G, S, out):
    """The object the human moved (where y and σ's plan state x differ) carried
    to a free location that σ's actions codes[step:] never carry anything to,
    the cheapest, and the hand aimed again as at y: out = (state, DFA state,
    units) after it; whether there is such a plan (not: the hand full or
    aimed at Else, the object not on a location, no such place; and with
    `only_in_the_way`, when the object does not stand where σ carries
    something)."""
    n, m, F, pb, eb, gb = P[:6]
    is_grasp = G[9]
    pmask = (1 << pb) - 1
    eshift = n * pb
    emask = (1 << eb) - 1
    out[2] = -1
    ee = (y >> eshift) & emask
    if (y >> (eshift + eb)) & ((1 << gb) - 1) != 0 or ee == 0 or x < 0:
        return False
    moved = -1
    for i in range(n):
        if (x >> (i * pb)) & pmask != (y >> (i * pb)) & pmask:
            moved = i
    if moved < 0:
        return False
    t = (y >> (moved * pb)) & pmask
    if t >= m:
        return False
    ahead = _ahead(codes, step, n, m, F)
    g = _first_grasp(is_grasp)
    if only_in_the_way and not ahead >> t & 1 or g < 0:
        return False
    blocked = ahead | 1 << t
    for i in range(n):
        if (y >> (i * pb)) & pmask < m:
            blocked |= 1 << ((y >> (i * pb)) & pmask)
    codes_ = np.empty(5, np.int64)
    trial = np.empty(3, np.int64)
    for f in range(m):
        if blocked >> f & 1:
            continue
        codes_[0] = _code(KIND_TRANSIT, moved, g, 0, n, F, m)
        codes_[1] = _code(KIND_GRAB, moved, g, 0, n, F, m)
        codes_[2] = _code(KIND_TRANSFER, moved, g, f, n, F, m)
        codes_[3] = _code(KIND_DROP, moved, g, f, n, F, m)
        c = 4
        if ee != 1 + m + moved * F + g:
            codes_[4] = _code(KIND_TRANSIT, (ee - 1 - m) // F, (ee - 1 - m) % F, 0, n, F, m)
            c = 5
        _play(y, q, codes_, c, P, G, S, trial)
        if trial[2] >= 0 and (out[2] < 0 or trial[2] < out[2]):
            out[:] = trial
    return out[2] >= 0


@njit(cache=True)
def _swap(y, q, x, codes, step, P, G, S, out):
    """With the hand full and the object the human moved (where y and σ's plan
    state x differ) in the way: what the hand holds put on a free location
    f, the moved object carried back where x has it (or, when x has it at
    Else, to another free location), the held object taken up again from f:
    out = (state, DFA state, units) after it, the cheapest over f; whether
    there is such a plan.  Locations σ's actions codes[step:] carry things
    to are not used."""
    n, m, F, pb, eb, gb = P[:6]
    is_grasp = G[9]
    pmask = (1 << pb) - 1
    eshift = n * pb
    out[2] = -1
    grip = (y >> (eshift + eb)) & ((1 << gb) - 1)
    if grip == 0 or x < 0:
        return False
    held = moved = -1
    occupied = 0
    for i in range(n):
        p = (y >> (i * pb)) & pmask
        if p == m + 1:
            held = i
        elif p < m:
            occupied |= 1 << p
        if (x >> (i * pb)) & pmask != p:
            moved = i
    if moved < 0 or held < 0 or (y >> (moved * pb)) & pmask >= m:
        return False
    ahead = _ahead(codes, step, n, m, F)
    back = (x >> (moved * pb)) & pmask
    g = _first_grasp(is_grasp)
    if g < 0:
        return False
    plan = np.empty(8, np.int64)
    trial = np.empty(3, np.int64)
    for f in range(m):
        if (occupied | ahead) >> f & 1 or f == back:
            continue
        for to in range(m):
            if back < m and to != back or back >= m and ((occupied | ahead) >> to & 1 or to == f):
                continue
            plan[0] = _code(KIND_TRANSFER, held, grip - 1, f, n, F, m)
            plan[1] = _code(KIND_DROP, held, grip - 1, f, n, F, m)
            plan[2] = _code(KIND_TRANSIT, moved, g, 0, n, F, m)
            plan[3] = _code(KIND_GRAB, moved, g, 0, n, F, m)
            plan[4] = _code(KIND_TRANSFER, moved, g, to, n, F, m)
            plan[5] = _code(KIND_DROP, moved, g, to, n, F, m)
            plan[6] = _code(KIND_TRANSIT, held, grip - 1, 0, n, F, m)
            plan[7] = _code(KIND_GRAB, held, grip - 1, 0, n, F, m)
            _play(y, q, plan, 8, P, G, S, trial)
            if trial[2] >= 0 and (out[2] < 0 or trial[2] < out[2]):
                out[:] = trial
    return out[2] >= 0


@njit(cache=True)
def _play(y, q, plan, count, P, G, S, out):
    """The robot's actions plan[:count] played from (y, q), up to a win: out =
    (state, DFA state, units) after them; units -1 when one is not available."""
    accepting = G[13]
    step = np.empty(3, np.int64)
    out[0], out[1], out[2] = y, q, 0
    for e in range(count):
        _act(out[0], out[1], plan[e], P, G, S, step)
        if step[2] < 0:
            out[2] = -1
            return
        out[0], out[1], out[2] = step[0], step[1], out[2] + step[2]
        if accepting[out[1]]:
            return


@njit(cache=True)
def _act(y, q, code, P, G, S, out):
    """The robot's action `code` at (y, q): out = (state after, DFA state
    after, units); units -1 when it is not available there.  Only that
    action is generated (`_robot_move`), not every move at y: what
    `kernels._robot_moves` gives for it (tests/test_replies_act.py)."""
    n, pb, free_all = P[0], P[3], P[12]
    atom_at, free_at, trans = G[10], G[11], G[12]
    out[2] = -1
    after, units = _robot_move(y, code, P, G, S[1], S[3], S[4])
    if units >= 0:
        out[0] = after
        out[1] = trans[q, _letter(after, n, pb, atom_at, free_at, free_all)]
        out[2] = units


@njit(cache=True, inline="always")
def _robot_move(x, code, P, G, at, Sx, Tx):
    """(state after, units) of the robot's move `code` at packed state x, as
    `kernels._robot_moves` makes it (the same branch of §4, its cost found
    the same way, for the one object and frame the code names); units -1
    when the move is not among the robot's moves there (at, Sx, Tx: scratch)."""
    n, m, F, pb, eb, gb = P[:6]
    samples_mask = P[11]
    anchor_at, anchor_count, home_starts = G[0], G[1], G[2]
    loc = code % (m + 2)
    rest = code // (m + 2)
    f = rest % (F + 1)
    o = (rest // (F + 1)) % (n + 1)
    kind = rest // ((F + 1) * (n + 1))
    pmask = (1 << pb) - 1
    eshift = n * pb
    ee = (x >> eshift) & ((1 << eb) - 1)
    grip = (x >> (eshift + eb)) & ((1 << gb) - 1)
    occupied = 0
    held = -1
    for j in range(n):
        at[j] = (x >> (j * pb)) & pmask
        if at[j] < m:
            occupied |= 1 << at[j]
        elif at[j] == m + 1:
            held = j
    if o >= n or f >= F or (held >= 0) != (kind == KIND_TRANSFER or kind == KIND_DROP) or held >= 0 and (
            o != held or f != grip - 1):
        return x, -1
    free = ((1 << m) - 1)  # kernels._free_masks for object o alone
    else_other = False
    for j in range(n):
        if j != o:
            if at[j] < m:
                free &= ~(1 << at[j])
            elif at[j] == m:
                else_other = True
    if not else_other:
        free |= samples_mask
    if grip != 0 or ee > m:  # the anchors the state may stand for
        place, g = (m if ee == 0 else ee - 1, grip - 1) if grip != 0 else (at[(ee - 1 - m) // F], (ee - 1 - m) % F)
        slen = anchor_count[place, g]
        for a in range(slen):
            Sx[a] = anchor_at[place, g, a]
    else:
        slen = len(home_starts)
        for a in range(slen):
            Sx[a] = home_starts[a]
    if held >= 0:
        return _held_move(x, kind, o, f, loc, ee, occupied, free, slen, P, G, Sx, Tx)
    return _free_hand_move(x, kind, o, f, loc, ee, occupied, free, slen, P, G, Sx, Tx)


@njit(cache=True, inline="always")
def _free_hand_move(x, kind, o, f, loc, ee, occupied, free, slen, P, G, Sx, Tx):
    """`_robot_move` with the hand empty: a transit to (o, f), a grab, a slide to loc."""
    n, m, F, pb, eb, gb = P[:6]
    grab_units = P[9]
    anchor_at, anchor_count, rule_start, rule_count, rule_free, rule_units = G[0], G[1], G[3], G[4], G[5], G[6]
    slide_start, slide_count, is_grasp = G[7], G[8], G[9]
    pmask, eshift, emask = (1 << pb) - 1, n * pb, (1 << eb) - 1
    p = (x >> (o * pb)) & pmask
    aimed = ee > m and (ee - 1 - m) // F == o and (ee - 1 - m) % F == f
    if kind == KIND_TRANSIT and loc == 0 and not aimed:
        tlen = anchor_count[p, f]
        for a in range(tlen):
            Tx[a] = anchor_at[p, f, a]
        c = _motion(0, Sx, slen, Tx, tlen, free, rule_start, rule_count, rule_free, rule_units)
        if c < INF:
            return (x & ~(emask << eshift)) | ((1 + m + o * F + f) << eshift), c
    elif kind == KIND_GRAB and loc == 0 and aimed and is_grasp[f] and grab_units < INF:
        y = (x & ~(pmask << (o * pb))) | ((m + 1) << (o * pb))
        y = (y & ~(emask << eshift)) | ((1 + p if p < m else 0) << eshift)
        return y | ((1 + f) << (eshift + eb)), grab_units
    elif kind == KIND_SLIDE and aimed and not is_grasp[f] and p < m and loc < m and not occupied >> loc & 1:
        c = _rule_min(slide_start[f, p, loc], slide_count[f, p, loc], free, rule_free, rule_units)
        if c < INF:
            return (x & ~(pmask << (o * pb))) | (loc << (o * pb)), c
    return x, -1


@njit(cache=True, inline="always")
def _held_move(x, kind, o, g, loc, ee, occupied, free, slen, P, G, Sx, Tx):
    """`_robot_move` with object o held in frame g: a transfer to loc, a drop there."""
    n, m, F, pb, eb, gb = P[:6]
    drop_units = P[10]
    anchor_at, rule_start, rule_count, rule_free, rule_units = G[0], G[3], G[4], G[5], G[6]
    pmask, eshift, emask = (1 << pb) - 1, n * pb, (1 << eb) - 1
    if kind == KIND_TRANSFER and loc < m and not occupied >> loc & 1 and ee != 1 + loc:
        Tx[0] = anchor_at[loc, g, 0]
        c = _motion(1 + o * F + g, Sx, slen, Tx, 1, free, rule_start, rule_count, rule_free, rule_units)
        if c < INF:
            return (x & ~(emask << eshift)) | ((1 + loc) << eshift), c
    elif kind == KIND_DROP and 1 <= ee <= m and loc == ee - 1 and not occupied >> loc & 1 and drop_units < INF:
        y = (x & ~(pmask << (o * pb))) | (loc << (o * pb))
        y &= ~(((1 << gb) - 1) << (eshift + eb))
        return (y & ~(emask << eshift)) | ((1 + m + o * F + g) << eshift), drop_units
    return x, -1


@njit(cache=True)
def _repair(x, q, w, q2, P, G, S):
    """The units of a robot plan from (w, q2), x after one human move, back
    to (x, q) or to a win: drop what x holds at its location, carry the
    moved object back from where the human put it, aim (or grab) again as
    in x (`_repair_codes`); -1 when there is none of this form (x holding
    over Else, the object taken from Else, an action not available, or
    another end)."""
    path = np.empty((8, 4), np.int64)
    c = _repair_path(x, q, w, q2, P, G, S, path)
    return -1 if c < 0 else path[:c, 2].sum()


@njit(cache=True)
def _repair_path(x, q, w, q2, P, G, S, out):
    """`_repair`'s plan played from (w, q2) action by action: out[e] = (state,
    DFA state, units, code) after action e; their count (the last is (x, q)
    or a win), -1 when there is no repair."""
    accepting = G[13]
    codes = np.empty(8, np.int64)
    c = _repair_codes(x, w, P, G, codes)
    if c < 0:
        return -1
    step = np.empty(3, np.int64)
    y, qq = w, q2
    for e in range(c):
        _act(y, qq, codes[e], P, G, S, step)
        if step[2] < 0:
            return -1
        y, qq = step[0], step[1]
        out[e, 0], out[e, 1], out[e, 2], out[e, 3] = y, qq, step[2], codes[e]
        if accepting[qq]:
            return e + 1
    return c if y == x and qq == q else -1


@njit(cache=True)
def _repair_codes(x, w, P, G, codes):
    """The actions of `_repair` from w back to x into codes; their count, -1
    when there is no plan of that form."""
    n, m, F, pb, eb, gb = P[:6]
    is_grasp = G[9]
    pmask = (1 << pb) - 1
    eshift = n * pb
    emask = (1 << eb) - 1
    ee = (x >> eshift) & emask
    grip = (x >> (eshift + eb)) & ((1 << gb) - 1)
    c = 0
    held = -1
    if grip != 0:
        if ee == 0 or ee > m:
            return -1
        for i in range(n):
            if (x >> (i * pb)) & pmask == m + 1:
                held = i
        codes[c] = _code(KIND_DROP, held, grip - 1, ee - 1, n, F, m)
        c += 1
    moved = -1
    for i in range(n):
        if (x >> (i * pb)) & pmask != (w >> (i * pb)) & pmask:
            moved = i
    if moved >= 0:
        a = (x >> (moved * pb)) & pmask
        if a >= m:
            return -1
        g = _first_grasp(is_grasp)
        if grip == 0 and ee > m and (ee - 1 - m) // F == moved and is_grasp[(ee - 1 - m) % F]:
            g = (ee - 1 - m) % F
        if g < 0:
            return -1
        codes[c] = _code(KIND_TRANSIT, moved, g, 0, n, F, m)
        codes[c + 1] = _code(KIND_GRAB, moved, g, 0, n, F, m)
        codes[c + 2] = _code(KIND_TRANSFER, moved, g, a, n, F, m)
        codes[c + 3] = _code(KIND_DROP, moved, g, a, n, F, m)
        c += 4
        aim = 1 + m + moved * F + g
    else:
        aim = (w >> eshift) & emask
    if held >= 0:
        codes[c] = _code(KIND_TRANSIT, held, grip - 1, 0, n, F, m)
        codes[c + 1] = _code(KIND_GRAB, held, grip - 1, 0, n, F, m)
        c += 2
    elif aim != ee:
        if ee == 0:
            return -1
        codes[c] = _code(KIND_TRANSIT, (ee - 1 - m) // F, (ee - 1 - m) % F, 0, n, F, m)
        c += 1
    return c


@njit(cache=True)
def _plan(i, rec, rm_tgt, rm_move, hb, out_key, out_move):
    """The chosen actions from node i to the win: their moves (units <<
    code_bits | code) into out_move and the key (>> hb: packed state << qbits
    | DFA state) of the node after each but the last (which wins) into
    out_key; their count, -1 when the arrays are too short."""
    count = 0
    while count < len(out_move):
        e = rec[i, R_OFF] + _small(rec, i, 32) - 1
        out_move[count] = rm_move[e]
        i = rm_tgt[e]
        count += 1
        if i < 0:
            return count
        out_key[count - 1] = rec[i, KEY] >> hb
    return -1
