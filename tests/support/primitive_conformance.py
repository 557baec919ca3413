"""What every displacement primitive plugin must do (`planning.primitive_protocol`),
as `planner_conformance.py` is for planners.  `check_displacement` runs the
whole contract on one scene, planner and contact; it is used for the
built-ins (tests/test_primitive_conformance.py) and for a third-party
plugin installed from the test tree (tests/test_primitive_plugin.py).

The contract, each clause checked against values computed here, not by
the plugin:
- `name`, `kind = "displacement"`, a finite `fixed_cost >= 0`;
- `slides` returns `SlideRule`s of the contact asked for, between two
  different locations of interest, whose `free` names only places other
  than the two, whose cost is finite and at least the primitive's fixed
  cost (the scene's `costs: {NAME: c}` when given), whose path starts and
  ends at the two anchors' configurations, stays within the joint limits
  and has no static contact anywhere (re-checked here configuration by
  configuration); the same question gives the same answer;
- `execute`, in a simulated world with the object at the slide's start
  and the robot at its anchor, leaves the object on the goal's pose, the
  hand empty, and reports the path it followed.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from symsynth.execution.world import SimWorld
from symsynth.game.abstraction import Move
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.primitive_protocol import SlideRule
from symsynth.planning.protocol import Mode


def check_displacement(primitive, scene, planner, contact: str) -> list[SlideRule]:
    """Every clause of the module doc; returns the slides (at least one:
    a conformance run that checks nothing proves nothing)."""
    assert isinstance(primitive.name, str) and primitive.kind == "displacement"
    assert math.isfinite(primitive.fixed_cost) and primitive.fixed_cost >= 0
    anchors = anchor_configs(planner, scene)
    slides = primitive.slides(scene, planner, contact, anchors)
    assert slides, f"{primitive.name}: no slide with {contact} in {scene.name}"
    assert primitive.slides(scene, planner, contact, anchors) == slides  # a function of its arguments
    places = set(scene.geometry.places)
    fixed = scene.geometry.primitive_costs.get(primitive.name, primitive.fixed_cost)
    limits = np.asarray(planner.limits)
    for rule in slides:
        assert isinstance(rule, SlideRule) and rule.contact == contact
        assert rule.start in scene.locations and rule.goal in scene.locations and rule.start != rule.goal
        assert rule.free <= places - {rule.start, rule.goal}
        assert math.isfinite(rule.cost) and rule.cost >= fixed
        assert rule.path[0] == tuple(anchors[f"{rule.start}/{contact}"])
        assert rule.path[-1] == tuple(anchors[f"{rule.goal}/{contact}"])
        path = np.asarray(rule.path)
        assert ((path >= limits[:, 0] - 1e-9) & (path <= limits[:, 1] + 1e-9)).all()
        assert not any(planner.contacts(Mode(), q).static for q in rule.path)
        _check_execute(primitive, scene, rule)
    return slides


def _check_execute(primitive, scene, rule: SlideRule) -> None:
    obj = next(o.name for o in scene.objects if o.at == rule.start)
    world = SimWorld(scene)
    try:
        world.set_config(rule.path[0])
        i = scene.object_names.index(obj)
        move = Move("slide", f"slide({obj},{rule.contact},{rule.goal})", obj, i, rule.contact, rule.goal,
                    after=None)
        done = primitive.execute(world, move, rule.path)
        goal = scene.geometry.places[rule.goal]
        assert world.held is None
        assert np.allclose(world.poses[obj].xyz, goal.xyz, atol=1e-6) and world.poses[obj].angle_to(goal) < 1e-6
        assert tuple(done.path[0]) == rule.path[0] and tuple(done.path[-1]) == rule.path[-1]
        assert done.radians >= 0
    finally:
        world.close()


def moved_scene(scene, obj: str, place: str):
    """`scene` with `obj` standing at `place` (to check slides from there)."""
    objects = tuple(dataclasses.replace(o, at=place) if o.name == obj else o for o in scene.objects)
    return dataclasses.replace(scene, objects=objects)
