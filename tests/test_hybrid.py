"""The hybrid strategy τ_j (symsynth/solvers/hybrid.py): optimal while the
human has more than j moves left, the replanning strategy σ after.  On
generated scenes, W_j (what τ_j pays at most, found by bisection over the
question) is E_p at j = 0 (the explicit solver's), never decreases with j,
is at most σ's bound B_k, and is what the strategy pays when followed
through every human behaviour."""

from __future__ import annotations

import dataclasses
import math

import pytest

from symsynth.game.abstraction import initial_state
from symsynth.game.solution import OutOfReach
from symsynth.logic import parse_ltlf
from symsynth.solvers import andor, replan_budget
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.hybrid import Hybrid
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables
from symsynth.solvers.replan_budget import BudgetedBound
from support.games import planning_scene, worst_case_of

CEILING = 5000


def _hybrid(scene, formula, k, j):
    """τ_j's question on a fresh memo of the game (no rounds before it)."""
    tables = Tables(scene, formula, 1.0, None, k)
    memo = andor.Memo(tables, BoundTables(tables, formula), k)
    x = tables.pack(initial_state(scene))
    start = memo.node(memo.key2(x, tables.step(tables.dfa_index[tables.dfa.initial], x), k))
    return Hybrid(memo, BudgetedBound(scene, formula, k), j, start)


def _games(seeds):
    """(seed, scene, k, formula, E_p, σ's bound) of generated games σ wins at a cost."""
    for seed in seeds:
        scene = planning_scene(seed, 9100)
        k = 1 + seed % 3
        formula = parse_ltlf(scene.task)
        try:
            sigma = BudgetedBound(scene, formula, k).least(0, CEILING)
        except OutOfReach:  # a zero-cost move: the searches refuse the game
            continue
        if 0 < sigma < math.inf:
            yield seed, scene, k, formula, solve_explicit(scene, k=k), sigma


def test_what_the_hybrid_pays_lies_between_the_value_and_what_sigma_pays():
    """W_0 = E_p, E_p <= W_j <= W_{j+1} <= B_k, and the strategy kept pays W_j
    against every human behaviour (so the question is exact for τ_j)."""
    checked = 0
    for seed, scene, k, formula, exact, sigma in _games(range(1, 60)):
        values = []
        for j in range(k):
            hybrid = _hybrid(scene, formula, k, j)
            assert not hybrid.within(exact.units - 1), (seed, j)
            w = hybrid.least(exact.units, int(sigma))
            values.append(w)
            followed = dataclasses.replace(exact, strategy=hybrid.strategy)
            assert worst_case_of(scene, followed, formula) == w, (seed, j)
            assert sum(step.cost for step in hybrid.play()) <= w, (seed, j)
        checked += 1
        assert values[0] == exact.units, seed
        assert values == sorted(values) and values[-1] <= sigma, (seed, values, sigma)
    assert checked >= 8, checked


@pytest.mark.parametrize("drop", [0, 3])
def test_an_anytime_answer_tightened_by_the_hybrid_holds_the_value(monkeypatch, drop):
    """The search's proof from above withheld (it returns its value less `drop`
    as a lower end only), and with `drop` = 0 σ's bound too: every answer
    holds the explicit solver's value, the ones the hybrid made exact are it,
    and the hybrid's strategy pays at most its upper end against every human.
    The search's last question is not asked again after the hybrid's (that
    is `test_andor_resumed`'s)."""
    andor.prepare()  # (its warm-up game is solved by the search as it is)
    search = andor._search
    monkeypatch.setattr(andor, "_resumed", lambda solution, *args: solution)

    def from_below(memo, start, deadline, rounds_until=None):
        lower, upper, rounds = search(memo, start, None)
        if deadline is None or lower is not None or upper is None:  # (σ's no-human searches take no deadline)
            return lower, upper, rounds
        return max(0, upper - drop), None, rounds

    monkeypatch.setattr(andor, "_search", from_below)
    if drop == 0:
        monkeypatch.setattr(replan_budget, "certified_upper", lambda *args, **kwargs: None)
    tightened = 0
    for seed, scene, k, formula, exact, _ in _games(range(1, 120)):
        if k == 1:
            continue
        found = andor.solve_andor(scene, k=k, time_limit=3600)
        assert found.lower_units is None or found.lower_units <= exact.units, seed
        assert found.units is None or exact.units <= found.units, seed
        assert found.exact == (drop == 0 and found.units is not None), seed
        if not found.stats.get("upper_by", "").startswith("hybrid"):
            continue
        tightened += 1
        assert found.units == exact.units or found.units < found.stats.get("replanning_bound", math.inf), seed
        assert worst_case_of(scene, found, formula) <= found.units, seed
        assert sum(step.cost for step in found.principal_play) <= found.cost_bound, seed
    assert tightened >= 3, tightened


def test_a_play_deeper_than_the_recursion_limit_leaves_the_answer_as_it_was():
    """`within` recurses once per turn of a play, so a budget of many thousand
    units can pass Python's recursion limit: the tightening then gives up, as
    at its deadline, rather than ending the command with a traceback."""
    from symsynth.solvers import hybrid

    class TooDeep:
        def within(self, b, deadline):
            raise RecursionError

    assert hybrid._tightened(TooDeep(), 700, 722, None) == (None, 699)


def test_a_question_reading_what_earlier_ones_kept_answers_as_a_fresh_one():
    """One hybrid asked at budgets around W_j from above, then from below (the
    kept hi, refutations, refuters and σ's leaf answers with their tightened
    budgets all read back) answers every budget as a fresh hybrid does, and
    both say yes exactly from W_j (found by `least` on its own fresh hybrid)."""
    checked = 0
    for seed, scene, k, formula, exact, sigma in _games(range(1, 60, 2)):
        j = k - 1
        w = _hybrid(scene, formula, k, j).least(exact.units, int(sigma))
        budgets = list(range(w + 3, exact.units - 3, -1))
        reused = _hybrid(scene, formula, k, j)
        answers = [reused.within(b) for b in budgets + budgets[::-1]]
        fresh = [b >= w for b in budgets]
        assert answers == fresh + fresh[::-1], (seed, j, w)
        assert [_hybrid(scene, formula, k, j).within(b) for b in budgets[::3]] == fresh[::3], (seed, j)
        checked += 1
    assert checked >= 5, checked
