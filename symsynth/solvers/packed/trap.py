"""The trap the human can close within the AND-OR search's nodes (`_trap`,
called by `andor.Memo.trap`), over the records of `packed.search`."""

from __future__ import annotations

from numba import njit

from symsynth.solvers.packed.search import H_OFF, INF, KEY, LO_H, LO_R, R_OFF, _lo_h, _small

# numba's disk cache checks only this file's source: search.py's SHA-256 (first 16 hex
# digits) stands here so that a change there recompiles `_trap` (tests/test_numba_cache.py).
COMPILED_WITH = {"search.py": "8826aee9e9f8d25b"}


@njit(cache=True)
def _trap(count, M, hb, won):
    """The positions the human can keep from ever being won, within the
    nodes generated so far: lo := INF there (`solvers.forward._qualitative`
    on the compiled memo).  A node not expanded counts as won (it may be),
    so what is left unwon is a trap the human closes whatever lies outside
    it.  won: scratch, 2 * count bytes (bit 0 robot turn, bit 1 human turn).
    Passes over the nodes, newest first, until nothing changes; the number
    of robot turns found lost."""
    table, rec, rm_tgt, rm_move, hm_tgt = M
    won[:count] = 0
    changed = True
    while changed:
        changed = False
        for i in range(count - 1, -1, -1):
            w = won[i]
            if not w & 1 and rec[i, LO_R] < INF:
                ok = rec[i, R_OFF] < 0
                for e in range(_small(rec, i, 0) if not ok else 0):
                    t = rm_tgt[rec[i, R_OFF] + e]
                    if t < 0 or won[t] & 2:
                        ok = True
                        break
                if ok:
                    w |= 1
            if not w & 2 and _lo_h(rec, i) < INF:
                if rec[i, KEY] & ((1 << hb) - 1) == 0:
                    ok = (w & 1) != 0
                elif rec[i, H_OFF] < 0:
                    ok = True
                else:
                    ok = (w & 1) != 0
                    for e in range(_small(rec, i, 16)):
                        t = hm_tgt[rec[i, H_OFF] + e]
                        if ok and t >= 0 and not won[t] & 1:
                            ok = False
                if ok:
                    w |= 2
            if w != won[i]:
                won[i] = w
                changed = True
    lost = 0
    for i in range(count):
        if not won[i] & 1:
            rec[i, LO_R] = INF
            lost += 1
        if not won[i] & 2:
            rec[i, LO_H] = INF
    return lost
