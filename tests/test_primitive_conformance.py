"""The built-in displacement primitives pass the conformance suite
(`primitive_conformance.py`): push on the push-small geometry (the box
from behind, away from the robot: l1 -> l2), pull on pull-small (a block
drawn toward the robot by a contact on its far side: l2 -> l1)."""

from __future__ import annotations

from pathlib import Path

import pytest

from support.primitive_conformance import check_displacement
from symsynth.planning.registry import planner_class
from symsynth.primitive_registry import displacement
from symsynth.scene import load_scene

DATA = Path(__file__).parent / "data"


@pytest.mark.parametrize("name, file, contact, expected", [
    ("push", "push-small.yaml", "behind", {("l1", "l2")}),
    ("pull", "pull-small.yaml", "far", {("l2", "l1")}),
])
@pytest.mark.parametrize("planner", ["ompl-fcl", "pybullet"])
def test_builtin_displacement_primitives_conform(name, file, contact, expected, planner):
    scene = load_scene(DATA / file)
    slides = check_displacement(displacement(name), scene, planner_class(planner)(scene), contact)
    assert {(r.start, r.goal) for r in slides} == expected
