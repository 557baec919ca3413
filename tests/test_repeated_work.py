"""Work done once that was done again (issue 33, "repeated work found by
walking the data through"): each test counts the calls of the expensive
step over one command or one solve."""

from __future__ import annotations

import pytest

import symsynth.automata.compile as compile
import symsynth.automata.shared as shared
from support.paper import SCENES
from symsynth.cli import main
from symsynth.problem import load_problem, solve


@pytest.fixture
def compiles(monkeypatch) -> list:
    """Every DFA construction of a task (`compile_ltlf`'s work, wherever it is called from)."""
    made: list = []
    construct = compile._compile

    def counted(formula, *options):
        made.append(formula)
        return construct(formula, *options)
    monkeypatch.setattr(compile, "_compile", counted)
    shared._kept.clear()
    getattr(shared, "_ordered", {}).clear()
    return made


def test_solve_with_a_strategy_file_compiles_the_task_once(tmp_path, compiles):
    """`solve -o` parsed the task again for the strategy file and built its
    DFA a second time."""
    assert main(["solve", str(SCENES / "toy.yaml"), "--solver", "explicit", "-o", str(tmp_path / "s.json")]) == 0
    assert len(compiles) == 1


def test_the_symbolic_solver_compiles_the_task_once_over_the_horizons_it_tries(compiles):
    """k = 20 is solved by trying k = 8 and 16 first (`game.horizon`); each
    try built the DFA again in its own BDD manager."""
    problem = load_problem(SCENES / "toy.yaml")
    solution = solve(problem, "symbolic", k=20)
    assert len(compiles) == 1
    assert solution.units == solve(problem, "explicit", k=20).units
