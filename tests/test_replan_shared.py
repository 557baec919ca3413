"""The replanning question over the AND-OR search's own memo (issue 32:
`solve_andor` under a time limit hands its memo to `certified_upper`): V_0
read at the h = 0 nodes of a memo built for k human moves, whose bounds the
search proved, gives σ's plans, and the bound found is what σ pays."""

from __future__ import annotations

import pytest

from symsynth.game.abstraction import initial_state
from symsynth.game.solution import OutOfReach
from symsynth.game.symmetry import Symmetry
from symsynth.logic import parse_ltlf
from symsynth.solvers import andor
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables
from symsynth.solvers.replan import NoHumanValue
from support.games import asked_least, explicit_and_paid, planning_scene


def _searched(scene, formula, k, symmetry=None):
    """The memo of the AND-OR search for k human moves, run to the end (the
    game's E_p proven); None when the search hands the game on."""
    tables = Tables(scene, formula, 1.0, symmetry, k)
    memo = andor.Memo(tables, BoundTables(tables, formula), k)
    v = initial_state(scene)
    q = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v))
    if tables.accepting[q]:
        return None
    try:
        andor._search(memo, memo.node(memo.key2(tables.canon(tables.pack(v)), q, k)), None)
    except (andor.ZeroCost, andor._TooManyRounds):
        return None
    return memo


def test_the_question_over_the_searchs_memo_finds_what_its_strategy_pays():
    andor.prepare()
    checked = 0
    for seed in (s for s in range(1, 80) if s % 4):
        scene = planning_scene(seed, 9100)
        k = 1 + seed % 3
        formula = parse_ltlf(scene.task)
        memo = _searched(scene, formula, k)
        if memo is None:
            continue
        found = asked_least(scene, formula, k, NoHumanValue(scene, formula, memo=memo))
        if found is None:
            continue
        asked, upper = found
        checked += 1
        assert asked.memo is memo, seed
        e_p, paid = explicit_and_paid(scene, formula, k, asked.strategy)
        assert e_p <= upper and paid == upper, seed
    assert checked >= 8, checked


def test_a_memo_over_canonical_positions_is_refused():
    from symsynth.testing.gamegen import alike_scene

    scene = alike_scene(8)
    formula = parse_ltlf(scene.task)
    symmetry = Symmetry.of(scene, formula)
    assert symmetry is not None
    tables = Tables(scene, formula, 1.0, symmetry, 1)
    with pytest.raises(ValueError, match="canonical"):
        NoHumanValue(scene, formula, memo=andor.Memo(tables, BoundTables(tables, formula), 1))


def test_the_principal_play_follows_the_searchs_strategy_after_the_question(monkeypatch):
    """σ's searches on the shared memo may lower bounds at h = 0 and so move
    the search's chosen actions there: when the search's strategy stays the
    answer's, its principal play is the one that strategy plays, step by step,
    against the worst replies (the search's proof is left as an interval, so
    the question runs after it)."""
    andor.prepare()
    search = andor._search

    def not_exact(memo, start, deadline, rounds_until=None):
        lower, upper, rounds = search(memo, start, None)
        if deadline is None or lower is not None or upper is None:
            return lower, upper, rounds
        return max(0, upper - 5), upper, rounds

    monkeypatch.setattr(andor, "_search", not_exact)
    checked = 0
    for seed in range(1, 40):  # (9500 + 23: a game whose principal play the question moves)
        scene = planning_scene(seed, 9500)
        k = 1 + seed % 3
        formula = parse_ltlf(scene.task)
        try:
            found = andor.solve_andor(scene, k=k, time_limit=3600)
        except OutOfReach:  # a zero-cost move: the searches refuse the game
            continue
        if not isinstance(found.strategy, andor.ProvenStrategy) or not found.principal_play:
            continue
        checked += 1
        tables = Tables(scene, formula, 1.0, None, k)
        v, h = initial_state(scene), k
        q = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v))
        for step in found.principal_play:
            if step.who == "robot":
                assert found.strategy[(v, tables.dfa_states[q], h)] == step.action, seed
            else:
                h -= 1
            v = step.state
            q = tables.step(q, tables.pack(v))
        assert tables.accepting[q], seed
    assert checked >= 8, checked
