"""Semantics §9: EX_μ(B), the class and C against the independent reference
(tests/support/objectives.py) and against values solved by hand
(scenes/wait.yaml, scenes/reach.yaml); every solver that computes an
objective gives the same value."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest

from symsynth.errors import InputError
from symsynth.game.human_model import RandomModel, parse_model
from symsynth.logic import parse_ltlf
from symsynth.scene import load_scene
from symsynth.solvers.objectives import solve_objective
from symsynth.testing.gamegen import random_scene
from tests.support.objectives import reference

SCENES = Path(__file__).resolve().parents[1] / "scenes"
SOLVERS = ("explicit", "compiled")
#: seeds whose game the plain-Python reference solves in a moment
SEEDS = range(100)


def _small(scene):
    return len(scene.objects) <= 2 and len(scene.locations) <= 3


@pytest.mark.parametrize("contacts", [False, True])
def test_class_and_cooperative_cost_match_the_reference(contacts):
    kinds = set()
    for seed in SEEDS:
        scene = random_scene(seed, contacts=contacts)
        if not _small(scene):
            continue
        formula = parse_ltlf(scene.task)
        ref = reference(scene, formula, scene.k)
        kinds.add(ref["class"])
        for solver in SOLVERS:
            got = solve_objective(scene, objective="best-effort", solver=solver)
            assert got.position_class == ref["class"], (seed, solver)
            assert got.cooperative_cost == ref["C"], (seed, solver)
            assert got.cost_bound == ref["E_p"], (seed, solver)
    assert kinds == {"winning", "cooperative", "losing"}  # the seeds cover every class


@pytest.mark.parametrize("contacts", [False, True])
def test_expected_cost_matches_the_reference(contacts):
    """With a third of the motions at cost 0, waiting pays in some games."""
    checked = waited = 0
    for seed in SEEDS:
        scene = random_scene(seed, contacts=contacts, zeros=0.3 if seed % 2 else 0.0)
        if not _small(scene):
            continue
        formula = parse_ltlf(scene.task)
        P = Fraction(1, 2) if seed % 2 else Fraction(3, 10)
        extra = seed % 3  # B = E_p, E_p + 1, E_p + 2
        ref = reference(scene, formula, scene.k, P)
        if ref["E_p"] is None:
            for solver in SOLVERS:
                got = solve_objective(scene, objective="expected", model=RandomModel(P), solver=solver)
                assert got.expected_cost is None
            continue
        budget = ref["E_p"] + extra
        ref = reference(scene, formula, scene.k, P, budget)
        for solver in SOLVERS:
            got = solve_objective(scene, objective="expected", model=RandomModel(P), solver=solver,
                                  budget=float(budget))
            assert got.expected_cost == pytest.approx(ref["EX"], abs=1e-9), (seed, solver)
            assert got.expected_cost <= budget + 1e-9
            waited += not got.attained
        checked += 1
    assert checked >= 10 and waited >= 1, (checked, waited)  # some infimum reached only by waiting


def test_budget_below_E_p_leaves_it_undefined():
    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=parse_model("random(0.3)"), budget=20.9)
    assert got.cost_bound == 21 and got.expected_cost is None and got.realizable is False


def test_expected_never_increases_with_the_budget():
    for seed in range(12):
        scene = random_scene(seed)
        if not _small(scene):
            continue
        base = solve_objective(scene, objective="expected", model=RandomModel(Fraction(2, 5)), solver="explicit")
        if base.cost_bound is None:
            continue
        values = [solve_objective(scene, objective="expected", model=RandomModel(Fraction(2, 5)),
                                  solver="explicit", budget=base.cost_bound + d).expected_cost for d in range(5)]
        assert all(a >= b - 1e-12 for a, b in zip(values, values[1:])), (seed, values)


@pytest.mark.parametrize("P", ["0.1", "0.3", "0.5", "1"])
@pytest.mark.parametrize("solver", SOLVERS)
def test_wait_scene_as_solved_by_hand(P, solver):
    """scenes/wait.yaml's comments: E_p = 21 and EX = 12.5 - 4 P, an
    infimum reached only by waiting on the zero-cost wrist turn."""
    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=parse_model(f"random:{P}"), solver=solver)
    assert got.cost_bound == 21 and got.budget == 21
    assert got.expected_cost == pytest.approx(12.5 - 4 * float(P), abs=1e-9)
    assert got.attained is False  # the value is an infimum: the strategy waits
    assert got.waiting is not None and got.waiting_bound <= got.expected_cost + got.epsilon


def test_wait_scene_without_a_move_left_is_attained():
    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=parse_model("random(0.3)"), k=0)
    assert got.cost_bound == 17 and got.expected_cost == 17 and got.attained  # 4 + 5 + 3 + 5


@pytest.mark.parametrize("solver", SOLVERS)
def test_reach_scene_as_solved_by_hand(solver):
    """scenes/reach.yaml's comments: E_p infinite, the start cooperative with C = 9."""
    scene = load_scene(SCENES / "reach.yaml")
    got = solve_objective(scene, objective="best-effort", solver=solver)
    assert got.cost_bound is None and got.position_class == "cooperative" and got.cooperative_cost == 9
    undefined = solve_objective(scene, objective="expected", model=parse_model("random(0.3)"), solver=solver)
    assert undefined.expected_cost is None and undefined.budget is None


def test_expected_needs_a_model():
    scene = load_scene(SCENES / "toy.yaml")
    with pytest.raises(InputError, match="--human-model random:P.*human: {k: K, model: random"):
        solve_objective(scene, objective="expected")


def test_objectives_name_their_solvers():
    scene = load_scene(SCENES / "toy.yaml")
    with pytest.raises(InputError, match="auto, compiled, explicit"):
        solve_objective(scene, objective="best-effort", solver="symbolic")


def test_sorting_symmetry_keeps_the_value():
    """The compiled solver explores canonical positions when objects are
    interchangeable (the sorting family); random(P) counts every move, so
    the value is the explicit solver's on all positions."""
    from bench.gamefamily import pattern_scene

    scene = pattern_scene(3, 4, k=1, colours=1)
    values = {s: solve_objective(scene, objective="expected", model=RandomModel(Fraction(1, 3)), solver=s)
              for s in SOLVERS}
    assert values["explicit"].cost_bound == values["compiled"].cost_bound is not None
    assert values["explicit"].states > values["compiled"].states  # the compiled one reduced by symmetry
    assert values["explicit"].expected_cost == pytest.approx(values["compiled"].expected_cost, abs=1e-9)


@pytest.mark.parametrize("solver", ["symbolic", "explicit", "compiled", "forward"])
def test_every_worst_case_solver_agrees_on_the_teaching_scenes(solver):
    """E_p as the scenes' comments compute it: 21 on wait.yaml, infinite on reach.yaml."""
    from symsynth.solvers import SOLVERS as WORST

    assert WORST[solver](load_scene(SCENES / "wait.yaml")).cost_bound == 21
    assert WORST[solver](load_scene(SCENES / "reach.yaml")).cost_bound is None
