"""The application layer (`symsynth.problem`): a problem composed once and
solved by name, as the command line and comparison runs use it."""

from __future__ import annotations

import pytest

from support.paper import SCENES
from symsynth.errors import InputError
from symsynth.problem import load_problem, solve


def test_the_toy_problem_has_its_hand_solved_values():
    """scenes/toy.yaml's comments: E_p = 50 with its k = 1, 17 with k = 0."""
    problem = load_problem(SCENES / "toy.yaml")
    assert problem.task == problem.scene.task and problem.obtained is None
    assert {name: solve(problem, name).cost_bound for name in ("symbolic", "explicit", "forward")} == {
        "symbolic": 50, "explicit": 50, "forward": 50}
    assert solve(problem, k=0).cost_bound == solve(load_problem(SCENES / "toy.yaml", k=0)).cost_bound == 17


def test_a_task_is_checked_against_the_scene_with_its_source():
    with pytest.raises(InputError, match="--task: .*unknown"):
        load_problem(SCENES / "toy.yaml", task="F(at(purple, l1))")
    problem = load_problem(SCENES / "toy.yaml", task="F(at(black, l2))")
    assert solve(problem, k=0).cost_bound is not None


def test_an_unknown_solver_names_the_installed_ones():
    with pytest.raises(InputError, match="unknown solver 'simplex'; installed solvers: auto, compiled, explicit, forward, symbolic"):
        solve(load_problem(SCENES / "toy.yaml"), "simplex")
