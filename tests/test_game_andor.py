"""The compiled AND-OR search (symsynth/solvers/andor.py) against the explicit
solver written in Python: the same value on generated scenes, a strategy
that wins within it against every human behaviour, and anytime intervals
[lower, upper] that hold the exact value, with a strategy for upper."""

from __future__ import annotations

import itertools

import pytest

from symsynth.logic import parse_ltlf
from symsynth.solvers.andor import solve_andor
from symsynth.solvers.explicit import solve_explicit
from symsynth.testing.gamegen import alike_scene, random_scene
from support.games import cut_answer, worst_case_of


def _scene(seed):
    if seed % 4 == 0:
        return alike_scene(seed, contacts=seed % 8 == 0)
    return random_scene(5000 + seed, positive=True, contacts=seed % 3 == 0)


@pytest.mark.parametrize("chunk", range(2))
def test_same_value_as_the_explicit_solver(chunk):
    kinds = {"finite": 0, "infinite": 0}
    for seed in range(40 * chunk, 40 * (chunk + 1)):
        scene = _scene(seed)
        k = seed % 4
        found = solve_andor(scene, k=k)
        explicit = solve_explicit(scene, k=k)
        assert found.units == explicit.units, (seed, k)
        assert found.exact
        kinds["infinite" if found.units is None else "finite"] += 1
        if found.units is not None and seed % 3 == 0:
            assert worst_case_of(scene, found, parse_ltlf(scene.task)) == found.units, seed
            assert sum(s.cost for s in found.principal_play) <= found.cost_bound + 1e-9
    assert kinds["finite"] >= 15 and kinds["infinite"] >= 3, kinds


def test_zero_cost_moves_go_to_the_layered_solver():
    """Scenes whose robot moves may cost 0 units (a question could wait on
    itself): answered all the same, by the layered solver."""
    for seed in range(12):
        scene = random_scene(7000 + seed, positive=False)
        assert solve_andor(scene, k=seed % 3).units == solve_explicit(scene, k=seed % 3).units, seed


def test_zero_cost_moves_under_a_time_limit_are_out_of_reach():
    """The layered solver, which answers zero-cost games, has no anytime
    answer of its own: under a limit, such a game is out of the search's
    reach (auto then goes on), every other game is answered within its
    interval."""
    from symsynth.game.solution import OutOfReach

    refused = 0
    for seed in range(12):
        scene = random_scene(7000 + seed, positive=False)
        exact = solve_explicit(scene, k=seed % 3).units
        try:
            found = solve_andor(scene, k=seed % 3, time_limit=30)
        except OutOfReach as error:
            assert "0 units" in str(error)
            refused += 1
            continue
        assert found.units == exact, seed
    assert refused >= 1


def test_time_limit_interval_holds_the_exact_value(monkeypatch):
    """Questions cut off every `chunk` steps and the clock read there: the
    answer is exact, or an interval lower <= E_p <= upper whose strategy
    spends at most upper against every human."""
    cut = upper = 0
    for (chunk, limit), seed in itertools.product([(10, 3), (20, 5), (40, 9), (80, 13)],
                                                  itertools.islice((s for s in range(60) if s % 4), 12)):
        scene = _scene(seed)
        k = 1 + seed % 3
        exact = solve_explicit(scene, k=k).units
        found = cut_answer(monkeypatch, scene, k, chunk, limit)
        if found.exact:
            assert found.units == exact, seed
            continue
        cut += 1
        assert exact is None or found.lower_units <= exact, seed
        if found.units is not None:
            upper += 1
            assert exact is not None and exact <= found.units, seed
            assert worst_case_of(scene, found, parse_ltlf(scene.task)) <= found.units, seed
    assert cut >= 3 and upper >= 1, (cut, upper)


def test_a_lost_game_under_a_time_limit_is_not_handed_to_the_unlimited_layered_solve(monkeypatch):
    """Without a limit, a game the search proves lost gets the layered
    solver's counter play; with one, that solve (which takes no limit) is
    not started: the search's own answer, E_p infinite, says why it has no
    counter play."""
    from symsynth.game.solution import OutOfReach
    from symsynth.solvers import andor, compiled

    andor.prepare()  # (its warm-up runs the layered solver)
    lost = []
    for seed in range(40):
        scene = random_scene(7000 + seed, positive=False)
        if solve_explicit(scene, k=1).units is None:
            lost.append(scene)
    assert len(lost) >= 3, len(lost)

    def refused(*args, **kwargs):
        raise AssertionError("the layered solver was started under a time limit")

    monkeypatch.setattr(compiled, "solve_compiled", refused)
    checked = 0
    for scene in lost:
        try:
            got = solve_andor(scene, k=1, time_limit=3600)
        except OutOfReach:  # a zero-cost move: out of the search's reach under a limit
            continue
        checked += 1
        assert got.exact and got.units is None
        assert got.stats["counter_play"].startswith("not built"), got.stats
    assert checked >= 3, checked
