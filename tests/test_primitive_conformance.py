"""The built-in primitives pass the conformance suite
(`symsynth.testing.primitive`), by the line a plugin's own repository uses:
push on the push-small geometry (the box from behind, away from the robot:
l1 -> l2), pull on pull-small (a block drawn toward the robot by a contact
on its far side: l2 -> l1), grab and drop on a block in the open; each with
both built-in planners (the physical test with the scene's own).  And the
suite itself on a slide from a location where no object stands, and its
physical test on a primitive that teleports the object (it must fail;
push passes it in TestPush)."""

from __future__ import annotations

from pathlib import Path

import pytest

from symsynth.execution import hand_motions
from symsynth.planning.registry import planner_class
from symsynth.primitive_registry import displacement
from symsynth.scene import load_scene
from symsynth.testing import conformance
from symsynth.testing.primitive import check_displacement, check_displacement_physics, moved_scene

DATA = Path(__file__).parent / "data"
PLANNERS = ("ompl-fcl", "pybullet")

TestPush = conformance("primitive", "push", scene=DATA / "push-small.yaml", contact="behind",
                       slides={("l1", "l2")}, planners=PLANNERS)
TestPull = conformance("primitive", "pull", scene=DATA / "pull-small.yaml", contact="far",
                       slides={("l2", "l1")}, planners=PLANNERS)
TestGrabAndDrop = conformance("primitive", "grab", "drop", planners=PLANNERS)


def test_a_slide_may_start_where_no_object_stands():
    """The protocol's slides are for some object of the scene, not for
    where the objects stand: with the box moved to l2, push's slide still
    starts at l1, now empty, and the suite carries it out with the box put
    there (it took the object standing at the start, and had none)."""
    scene = moved_scene(load_scene(DATA / "push-small.yaml"), "box", "l2")
    assert [o.at for o in scene.objects] == ["l2"]
    slides = check_displacement(displacement("push"), scene, planner_class("ompl-fcl")(scene), "behind")
    assert {(r.start, r.goal) for r in slides} == {("l1", "l2")}


class Teleport:
    """push's slides, carried out the kinematic world's way even in the
    physical one: the box is set on its target, untouched."""

    name, kind, fixed_cost = "teleport", "displacement", 2.0

    def slides(self, scene, planner, contact, anchors):
        return displacement("push").slides(scene, planner, contact, anchors)

    def execute(self, world, move, path):
        world.set_config(path[-1])
        world.place(move.obj, world.geometry.places[move.location])
        return hand_motions.Primitive(tuple(path), frozenset())


def test_the_physical_test_fails_a_primitive_that_teleports_the_object():
    """It ends exactly on l2 (so aiming alone would pass), but moved 18 cm
    while nothing touched it: the suite names that."""
    scene = load_scene(DATA / "push-small.yaml")
    planner = planner_class("ompl-fcl")(scene)
    check_displacement(Teleport(), scene, planner, "behind")  # the kinematic clauses cannot tell
    with pytest.raises(AssertionError, match="while nothing touched it"):
        check_displacement_physics(Teleport(), scene, planner, "behind")


def test_physical_false_leaves_the_physical_test_out():
    kinematic = conformance("primitive", "push", scene=DATA / "push-small.yaml", contact="behind", physical=False)
    assert kinematic.test_it_does_in_the_world_what_it_claims is None
    assert callable(TestPush.test_it_does_in_the_world_what_it_claims)
