"""The AND-OR search's hint (`packed.search._hint_first`): at a robot turn with
h >= 1 human moves left, the action proven at h = 0 from the same (state, DFA
state) is tried first.  The order changes which proof is found, never the
value: the same E_p with it on and off, and fewer robot turns expanded at
h >= 1 with it on (issue 32: it is what let 7 x 10 x k = 3's proof from above
finish)."""

from __future__ import annotations

import numpy as np

from bench.gamefamily import pattern_scene
from symsynth.game.abstraction import initial_state
from symsynth.game.solution import task_formula
from symsynth.solvers import andor
from symsynth.solvers.packed import search as sk
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables


def _memo(scene, k):
    andor.prepare()
    formula = task_formula(scene, None)
    tables = Tables(scene, formula, 1.0, None, k)
    memo = andor.Memo(tables, BoundTables(tables, formula), k)
    x = tables.pack(initial_state(scene))
    return memo, x, tables.step(tables.dfa_index[tables.dfa.initial], x)


def _hinted(memo, i, count):
    order = np.empty((1, count + 1), np.int64)
    order[0, :count] = [((10 + e) << 16) | e for e in range(count)]
    sk._hint_first(order, np.int64(0), np.int64(count), np.int64(i), memo.table, np.int64(memo.bits), memo.rec,
                   np.int64(memo.hb))
    return [int(v) & 0xFFFF for v in order[0, :count]]


def test_the_action_proven_at_h0_goes_first_and_the_rest_keep_their_order():
    memo, x, q = _memo(pattern_scene(3, 4, 1), 1)
    i = memo.node(memo.key2(x, q, 1))
    j = memo.node(memo.key2(x, q, 0))
    _, count = memo.expand(j, True)
    assert count >= 3
    assert _hinted(memo, i, count) == list(range(count))  # the node at h = 0 proves nothing yet
    memo.rec[j, sk.HI_R] = 50
    sk._set_small(memo.rec, np.int64(j), np.int64(32), np.int64(count - 1))  # move count - 2 chosen
    assert _hinted(memo, i, count) == [count - 2, *range(count - 2), count - 1]


def test_the_hint_keeps_the_value_and_shrinks_the_search_above_h0():
    expanded, values = [], []
    for hint in (1, 0):
        memo, x, q = _memo(pattern_scene(4, 5, 2), 2)
        memo.st[sk.ST_HINT] = hint
        start = memo.node(memo.key2(x, q, 2))
        lower, upper, _ = andor._search(memo, start, None)
        assert lower is None and upper is not None
        values.append(upper)
        rec = memo.rec[:memo.count]
        expanded.append(int(((rec[:, sk.R_OFF] >= 0) & (rec[:, sk.KEY] & ((1 << memo.hb) - 1) > 0)).sum()))
    assert values[0] == values[1]
    assert expanded[0] < expanded[1], expanded
