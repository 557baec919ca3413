"""Named tests for what the fuzz suite (test_fuzz.py) found, one per finding."""

from __future__ import annotations

import pytest

from support.paper import SCENES
from symsynth.cli import main
from symsynth.solvers import SOLVERS
from symsynth.scene import load_scene


@pytest.mark.parametrize("solver", sorted(SOLVERS))
def test_the_task_false_has_no_winning_strategy(solver, capsys):
    """No trace satisfies `false`: E_p is infinite.  The symbolic solver's
    attractor ran no round when nothing accepts and crashed (IndexError)."""
    assert SOLVERS[solver](load_scene(SCENES / "toy.yaml"), "false").cost_bound is None
    assert main(["solve", str(SCENES / "toy.yaml"), "--task", "false", "--solver", solver]) == 0
    assert "E_p        infinite" in capsys.readouterr().out


@pytest.mark.parametrize("solver", sorted(SOLVERS))
def test_the_task_true_costs_nothing(solver):
    """`true` holds on the first letter: E_p = 0 (the other end of the same case)."""
    assert SOLVERS[solver](load_scene(SCENES / "toy.yaml"), "true").cost_bound == 0
