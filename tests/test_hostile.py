"""Named tests for what the fuzz suite (test_fuzz.py) found, one per finding."""

from __future__ import annotations

import dataclasses

import pytest

from support.paper import SCENES
from symsynth.cli import main
from symsynth.solvers import SOLVERS
from symsynth.game.solution import OutOfReach
from symsynth.solvers.compiled import TooLarge
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


def test_a_cost_beyond_64_bits_is_solved_exactly_or_refused():
    """A costmap cost of 1e30 is finite and valid.  Quantized it is a Python
    int beyond int64: the compiled solver's tables overflowed (OverflowError
    traceback), and the forward search, which recurses once per move of a
    play within the budget, ran out of stack (RecursionError); both found
    by the fuzz suite.  Now each refuses the game with the reason, auto
    hands it on, and the answer is the explicit solver's exact integers."""
    scene = load_scene(SCENES / "toy.yaml")
    big = dataclasses.replace(scene, costmap=dataclasses.replace(scene.costmap, motions={
        key: [dataclasses.replace(rule, cost=rule.cost + 1e30) for rule in rules] if key[1] == "home" else rules
        for key, rules in scene.costmap.motions.items()}))
    with pytest.raises(TooLarge, match="2\\^40 units a move"):
        SOLVERS["compiled"](big)
    with pytest.raises(OutOfReach, match="deeper than its"):
        SOLVERS["forward"](big)
    exact = SOLVERS["explicit"](big)
    assert exact.units > 10 ** 30  # a transit from home is in every plan
    fallback = SOLVERS["auto"](big)
    assert (fallback.units, fallback.stats["auto"]) == (exact.units, "symbolic")
    assert "compiled refused it" in fallback.stats["auto_reason"]
    assert "forward refused it" in fallback.stats["auto_reason"]
