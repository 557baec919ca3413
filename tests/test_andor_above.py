"""The AND-OR search's proof from above (issue 32).

- The hint (`packed.search._hint_first`): at a robot turn with h >= 1 human
  moves left, the action proven at h = 0 from the same (state, DFA state) is
  tried first.  The order changes which proof is found, never the value: the
  same E_p with it on and off, and fewer robot turns expanded at h >= 1 with
  it on.
- The rounds from below resumed after σ's and the hybrid's questions
  (`andor._resumed`): from an anytime answer whose lower end is below E_p they
  go on to E_p, with the search's strategy (followed through every human
  behaviour), and stop at the end; a lower end raised to meet the upper end is
  exact."""

from __future__ import annotations

import dataclasses

import numpy as np

from bench.gamefamily import pattern_scene
from symsynth.game.abstraction import initial_state
from symsynth.game.solution import task_formula
from symsynth.logic import parse_ltlf
from symsynth.solvers import andor
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.packed import search as sk
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables
from symsynth.solvers.replan import NoHumanValue
from symsynth.solvers.replan_budget import BudgetedBound
from symsynth.testing.gamegen import random_scene
from support.games import worst_case_of


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


def _searched(scene, k):
    """(memo, start node) of a fresh search of the game, no question asked yet."""
    memo, x, q = _memo(scene, k)
    return memo, memo.node(memo.key2(x, q, k))


def _games():
    found = 0
    for seed in range(40):
        scene = random_scene(9100 + seed, positive=True)
        k = 1 + seed % 3
        value = solve_explicit(scene, k=k).units
        if value is not None and value > 0:
            found += 1
            yield scene, k, value
    assert found >= 10


def test_asked_again_at_the_value_it_proves_it_with_its_own_strategy():
    far = 1e18
    for scene, k, value in _games():
        memo, start = _searched(scene, k)
        anytime = andor._answer(memo, start, value, None, None, {}, {})
        assert not anytime.exact
        found = andor._resumed(anytime, memo, start, far)
        assert found.exact and found.units == value, (scene.name, k)
        assert found.stats["upper_by"] == "search"
        assert worst_case_of(scene, found, parse_ltlf(scene.task)) == value


def test_from_below_the_rounds_go_on_to_the_value_and_stop_at_the_end():
    for scene, k, value in _games():
        memo, start = _searched(scene, k)
        anytime = andor._answer(memo, start, value - 1, None, None, {}, {})
        found = andor._resumed(anytime, memo, start, 1e18)
        assert found.exact and found.units == value, (scene.name, k)
        assert worst_case_of(scene, found, parse_ltlf(scene.task)) == value
        memo, start = _searched(scene, k)
        anytime = andor._answer(memo, start, value - 1, None, None, {}, {})
        assert andor._resumed(anytime, memo, start, 0.0).lower_units == value - 1  # (the end has passed)


def test_resumed_on_the_memo_that_sigmas_questions_filled():
    """The solve's own order: σ's question over the search's memo first (its
    no-human searches prove h = 0 nodes and choose their actions there), then
    the rounds from below on that memo: E_p, with a strategy that pays it."""
    grew = 0
    for scene, k, value in _games():
        memo, start = _searched(scene, k)
        before = memo.count
        formula = task_formula(scene, None)
        bound = BudgetedBound(scene, formula, k, 1.0, NoHumanValue(scene, formula, 1.0, memo))
        assert bound.within(bound.least(value, 4 * value + 100))
        grew += memo.count > before
        anytime = andor._answer(memo, start, value - 1, None, None, {}, {})
        found = andor._resumed(anytime, memo, start, 1e18)
        assert found.exact and found.units == value, (scene.name, k)
        assert worst_case_of(scene, found, parse_ltlf(scene.task)) == value
    assert grew >= 5


def test_a_raised_lower_end_meeting_the_upper_end_is_exact(monkeypatch):
    scene, k, value = next(_games())
    memo, start = _searched(scene, k)
    monkeypatch.setattr(andor, "_search", lambda *args: (value, None, 1))  # rounds raised lo to value, no proof
    anytime = andor._answer(memo, start, value - 2, None, None, {}, {})
    found = andor._resumed(anytime, memo, start, 1e18)
    assert not found.exact and found.lower_units == value and found.stats["lower_units"] == value
    found = andor._resumed(dataclasses.replace(anytime, units=value), memo, start, 1e18)
    assert found.exact and found.units == value and "lower_units" not in found.stats


def test_a_raised_lower_end_above_the_budget_keeps_the_play_as_counter_play(monkeypatch):
    """Exact and lost within the budget: the play that makes the robot pay
    E_p is the counter play, as every other exact answer says it."""
    scene, k, value = next(_games())
    memo, start = _searched(scene, k)
    monkeypatch.setattr(andor, "_search", lambda *args: (value, None, 1))
    anytime = andor._answer(memo, start, value - 2, None, None, {}, {})
    resolution = anytime.resolution
    play = ("a play that pays the upper end",)
    budget = (value - 1) * resolution  # in costmap units: below E_p
    given = dataclasses.replace(anytime, units=value, principal_play=play, budget=budget)
    found = andor._resumed(given, memo, start, 1e18)
    assert found.exact and found.realizable is False and found.counter_play == play
    fits = andor._resumed(dataclasses.replace(given, budget=value * resolution), memo, start, 1e18)
    assert fits.exact and fits.realizable is True and fits.counter_play is None


def test_a_resumed_round_that_cannot_go_on_keeps_the_answer_in_hand(monkeypatch):
    """A 0-unit robot move met, or memory run out, in the resumed rounds: the
    certified interval σ or τ_1 gave is the answer, not an error."""
    scene, k, value = next(_games())
    memo, start = _searched(scene, k)
    anytime = dataclasses.replace(andor._answer(memo, start, value - 2, None, None, {}, {}), units=value + 3)
    for error in (andor.ZeroCost, MemoryError):
        def stopped(*args, error=error):
            raise error()
        monkeypatch.setattr(andor, "_search", stopped)
        found = andor._resumed(anytime, memo, start, 1e18)
        assert (found.lower_units, found.units) == (value - 2, value + 3) and found.stats["resumed"].startswith("stopped")
