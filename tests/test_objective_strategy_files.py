"""Strategy files of semantics §9 (`symsynth.objective-strategy/1`): written
from the explicit solver's graph, read back and certified against the game
(every play within B; the class kept by every robot move); a file that
lies fails certification."""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import pytest

from symsynth.errors import InputError
from symsynth.game.human_model import RandomModel, parse_model
from symsynth.game.objective_strategy import (certify_objective, read_objective_strategy,
                                              write_objective_strategy)
from symsynth.logic import parse_ltlf
from symsynth.scene import load_scene
from symsynth.solvers.objectives import solve_objective
from symsynth.solvers.objectives.files import objective_table
from symsynth.testing.gamegen import random_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def _write(tmp_path, scene, objective, model=None, **options):
    got = solve_objective(scene, objective=objective, model=model, solver="explicit", **options)
    table = objective_table(scene, scene.task, parse_ltlf(scene.task), got)
    path = tmp_path / f"{scene.name}-{objective}.json"
    write_objective_strategy(path, table)
    return got, path


def test_random_scenes_round_trip_and_certify(tmp_path):
    kinds = set()
    for seed in range(60):
        scene = random_scene(seed, contacts=seed % 3 == 0, zeros=0.3 if seed % 2 else 0.0)
        if len(scene.objects) > 2 or len(scene.locations) > 3:
            continue
        for objective in ("expected", "best-effort"):
            got, path = _write(tmp_path, scene, objective, RandomModel(Fraction(1, 2)))
            certify_objective(scene, read_objective_strategy(path))
            kinds.add((objective, got.position_class or ("waits" if got.attained is False else "attained")))
    assert {("best-effort", "cooperative"), ("best-effort", "winning"), ("expected", "waits")} <= kinds


def test_the_wait_file_carries_the_counter_and_the_waiting_bound(tmp_path):
    scene = load_scene(SCENES / "wait.yaml")
    got, path = _write(tmp_path, scene, "expected", parse_model("random(0.3)"))
    data = json.loads(path.read_text())
    assert data["waiting"] == got.waiting == 42 and data["epsilon"] == 1e-6 and data["budget_units"] == 21
    assert {e["left"] for e in data["positions"]} >= {21, 17}  # memory: the budget left
    assert data["worst"]  # after n turns: the worst-case strategy
    certify_objective(scene, read_objective_strategy(path))
    data["waiting"] = None  # waiting forever is not B-safe
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match="circles"):
        certify_objective(scene, read_objective_strategy(path))


def test_a_file_over_budget_fails(tmp_path):
    scene = load_scene(SCENES / "wait.yaml")
    _, path = _write(tmp_path, scene, "expected", parse_model("random(0.3)"))
    data = json.loads(path.read_text())
    data["budget_units"] = 20
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match="left of the budget|more than the budget|no action"):
        certify_objective(scene, read_objective_strategy(path))


def test_a_best_effort_file_that_drops_the_class_fails(tmp_path):
    """reach.yaml: after the transit, grab keeps the start's cooperative
    class; a transit elsewhere with a claim it cannot keep is refused."""
    scene = load_scene(SCENES / "reach.yaml")
    got, path = _write(tmp_path, scene, "best-effort")
    data = json.loads(path.read_text())
    assert data["class"] == "cooperative" and data["cooperative_cost"] == 9
    certify_objective(scene, read_objective_strategy(path))
    for entry in data["positions"]:
        if entry["action"] == "grab(b)":
            entry["action"] = "transit(b,top)" if entry["ee"] != ["b", "top"] else "transit(b,top)"
            entry["cooperative"] = 0  # claims a win it cannot have
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match="cooperative play|can only|not available"):
        certify_objective(scene, read_objective_strategy(path))


def test_the_table_and_the_adversary_read_one_walk(monkeypatch):
    """`simulate --in-world --human adversarial` needs the strategy table and
    what the strategy may still pay at each turn: the same turns, walked once
    (twice before, 1 s each on the line at k = 5), and both agree on them."""
    from symsynth.solvers.objectives import play
    from symsynth.solvers.objectives.files import to_pay_by_position

    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(3, 10)), solver="explicit")
    walks = []
    walk = play.expected_turns
    monkeypatch.setattr(play, "expected_turns", lambda *a: walks.append(a) or walk(*a))
    table = objective_table(scene, scene.task, parse_ltlf(scene.task), got)
    to_pay = to_pay_by_position(got)
    assert len(walks) == 1
    assert {(position, b) for position, b, w in to_pay if got.attained or w < got.waiting} == set(table.positions)


def test_a_replaced_solution_walks_its_own_strategy():
    """The walk is kept on the solution, not carried into a copy whose
    strategy differs (the waiting bound off: its plays circle)."""
    import dataclasses

    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(3, 10)), solver="explicit")
    assert got.attained is False and len(got.reached().node) > 0
    with pytest.raises(RuntimeError, match="circles"):
        dataclasses.replace(got, waiting=None, attained=True).reached()
