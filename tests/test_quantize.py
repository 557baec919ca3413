"""Rounding costs to units never lowers them (semantics §6: "rounding each action
cost up, so the bound stays sound").

The reference value here is exact: the game's min-max equations iterated
down from infinity (as `support.games.horizon_value`) over the costs as
rationals, with no resolution at all.  Every solver's `units * resolution`
must be at least that value at every resolution, and equal to it when the
resolution divides every cost.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
from fractions import Fraction

import pytest

from symsynth.testing.gamegen import random_scene
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.game.abstraction import quantize
from symsynth.solvers import SOLVERS
from symsynth.logic import parse_ltlf
from symsynth.scene.costmap import Costmap
from support.games import horizon_value

TOY = "scenes/toy.yaml"


@pytest.mark.parametrize("cost, resolution, units", [
    (4, 1e10, 1),  # far below one unit: still one (it was 0: E_p 0 on the toy)
    (1e-12, 1.0, 1),
    (3.0000000001, 1.0, 4),  # just above 3: never rounded down to 3
    (0.3, 0.1, 3), (1.1, 0.1, 11), (0.7, 0.1, 7),  # decimals, no float noise
    (0, 5.0, 0), (10, 2.5, 4), (10.000001, 2.5, 5),
])
def test_quantize_rounds_up_exactly(cost, resolution, units):
    assert quantize(cost, resolution) == units


def exact_value(scene, formula, k):
    """E_p with the costs as the rationals they are written as: the min-max
    equations iterated down from infinity on the game graph (whose own
    rounding, at resolution 1, is replaced by the exact costs)."""
    value = horizon_value(scene, formula, k, units=lambda c: Fraction(repr(float(c))))
    return Fraction(0) if value == 0 else value


def fractional(scene, factor: str, nudge: float = 0.0):
    """`scene` with every cost multiplied by the decimal `factor`, written
    back as the float of its two-decimal rounding (so e.g. 2.59, 0.37), plus
    `nudge` on each positive cost (2.590000000001: just above a multiple of 0.01)."""
    scale = Fraction(factor)

    def cost(c):
        scaled = float(round(Fraction(repr(float(c))) * scale, 2))
        return scaled + nudge if scaled > 0 else scaled
    motions = {key: tuple(dataclasses.replace(r, cost=cost(r.cost)) for r in rules)
               for key, rules in scene.costmap.motions.items()}
    return dataclasses.replace(scene, costmap=Costmap(motions), grab_cost=cost(scene.grab_cost),
                               drop_cost=cost(scene.drop_cost))


@functools.cache
def fractional_case(seed: int, nudge: float):
    """(scene, formula, exact value) of one case, worked out once for all
    the solvers (the exact value takes most of a second of Fractions)."""
    scene = fractional(random_scene(seed), "0.37", nudge)
    formula = parse_ltlf(scene.task)
    return scene, formula, exact_value(scene, formula, scene.k)


@pytest.mark.parametrize("nudge", [0.0, 1e-12])
@pytest.mark.parametrize("solver", sorted(SOLVERS))
@pytest.mark.parametrize("seed", range(100, 112))
def test_units_never_undercut_the_exact_value(solver, seed, nudge):
    scene, formula, exact = fractional_case(seed, nudge)
    largest = max([scene.grab_cost, scene.drop_cost]
                  + [r.cost for rules in scene.costmap.motions.values() for r in rules])
    for resolution in (0.01, 0.1, 0.25, 1.0, 3.0, largest):
        got = SOLVERS[solver](scene, formula, resolution=resolution)
        if exact == math.inf:
            assert got.units is None
            continue
        assert got.units is not None
        assert got.units * Fraction(repr(resolution)) >= exact
        if resolution == 0.01 and not nudge:  # divides every cost: the value is exact
            assert got.units * Fraction(1, 100) == exact


def test_fractional_scenes_are_varied():
    """The property above is not vacuous: finite, non-zero exact values occur."""
    values = [exact_value(s, parse_ltlf(s.task), s.k)
              for s in (fractional(random_scene(seed), "0.37") for seed in range(100, 112))]
    assert sum(0 < v < math.inf for v in values) >= 5


def test_toy_at_a_huge_resolution_is_refused(capsys):
    """The toy's E_p is 50 (worked out in scenes/toy.yaml); at resolution 1e10
    every cost used to round to 0 units and the toy was 'realizable within
    budget 0'.  A resolution above every cost is refused, with the reason."""
    assert main(["solve", TOY, "--resolution", "1e10", "--budget", "0"]) == 2
    err = capsys.readouterr().err
    assert "coarser than every action cost (the largest is 9)" in err and "Traceback" not in err
    with pytest.raises(InputError, match="coarser than every action cost"):
        SOLVERS["explicit"](random_scene(100), resolution=1e12)


def test_toy_at_its_largest_cost_is_sound(capsys):
    """At resolution 9 (the toy's largest cost) every action costs one unit of
    9 or more, so E_p is a multiple of 9 that is at least 50, and a budget
    below 50 is never met."""
    assert main(["solve", TOY, "--resolution", "9", "--budget", "49", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["realizable"] is False
    assert data["cost_bound"] >= 50 and data["cost_bound"] == 9 * data["units"]
