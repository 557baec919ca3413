"""The AND-OR search's last question asked again after σ's and the hybrid's
(`andor._resumed`): from an anytime answer whose lower end is E_p it proves
E_p with the search's strategy (followed through every human behaviour); from
one whose lower end is below E_p it raises the lower end to what the "no"
proved, and the answer is exact when that meets the upper end."""

from __future__ import annotations

import dataclasses

from symsynth.game.abstraction import initial_state
from symsynth.game.solution import task_formula
from symsynth.logic import parse_ltlf
from symsynth.solvers import andor
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables
from symsynth.testing.gamegen import random_scene
from support.games import worst_case_of


def _searched(scene, k):
    """(memo, start) of a fresh search of the game, no question asked yet."""
    andor.prepare()
    formula = task_formula(scene, None)
    tables = Tables(scene, formula, 1.0, None, k)
    memo = andor.Memo(tables, BoundTables(tables, formula), k)
    x = tables.pack(initial_state(scene))
    return memo, memo.node(memo.key2(x, tables.step(tables.dfa_index[tables.dfa.initial], x), k))


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


def test_asked_again_below_the_value_it_raises_the_lower_end():
    far = 1e18
    for scene, k, value in _games():
        memo, start = _searched(scene, k)
        anytime = andor._answer(memo, start, value - 1, None, None, {}, {})
        found = andor._resumed(anytime, memo, start, far)
        assert not found.exact and found.lower_units == value, (scene.name, k)
        memo, start = _searched(scene, k)
        anytime = dataclasses.replace(andor._answer(memo, start, value - 1, None, None, {}, {}), units=value)
        assert andor._resumed(anytime, memo, start, far).exact
