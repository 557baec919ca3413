"""What every motion primitive plugin must do (`planning.primitive_protocol`),
as `testing.planner` is for planners.  `conformance("primitive", NAME, ...)`
(`symsynth.testing`) runs it on a registered primitive; `check_displacement`
and `check_prehensile` are its two halves, for one scene and planner.

A displacement primitive, on the scene file it is meant for (`scene=`),
with its contact (`contact=`), checked against values computed here, not
by the plugin:
- `name`, `kind = "displacement"`, a finite `fixed_cost >= 0`;
- `slides` returns `SlideRule`s of the contact asked for, between two
  different locations of interest, whose `free` names only places other
  than the two, whose cost is finite and at least the primitive's fixed
  cost (the scene's `costs: {NAME: c}` when given), whose path starts and
  ends at the two anchors' configurations, stays within the joint limits
  and has no static contact anywhere (re-checked here configuration by
  configuration); the same question gives the same answer;
- `execute`, in a simulated world with an object at the slide's start (the
  one standing there, or else the scene's first object: a slide rule serves
  any object, and may start where none stands) and the robot at its anchor,
  leaves the object on the goal's pose, the hand empty, and reports the
  path it followed.

In the physical world (`execution.physics`), unless the suite is given
`physical=False`: each of its slides, executed by the plugin in a world of
its own (`execution.trial.slide_trial`, the object alone) with seeded
randomization (`RANDOMIZE`, seeds 0..`TRIALS`-1), ends with the object
within the observation's tolerance of the goal in at least `PASSING` of
`TRIALS` trials, and never moves it while nothing of the robot touches it
(`rule_trials.UNTOUCHED`): a plugin that sets the object's pose (the
kinematic world's way) fails, however exactly it aims.

A prehensile primitive, on a block standing in the open (the planner
suite's `single` scene): `holds` and `reaches` answer a bool, the same one
twice; the primitive that carries out the game's `grab` closes the hand on
the block and returns to its anchor, the one for `drop` sets the held block
down on its place and empties the hand; in the physical world, the two
together (grab, then drop on the same place) hold and lift the block with
the fingers and set it down within the tolerance in at least `PASSING`
of `TRIALS` randomized trials.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np

from symsynth.execution.hand_motions import Approaches
from symsynth.execution.observe import POSITION
from symsynth.execution.physics import Randomization
from symsynth.execution.rule_trials import Rate, Subject, rates, slide_tried
from symsynth.execution.world import SimWorld
from symsynth.game.abstraction import Move, State
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.primitive_protocol import SlideRule
from symsynth.planning.protocol import Mode, Planner
from symsynth.planning.registry import planner_class
from symsynth.primitive_registry import primitive
from symsynth.scene import load_scene
from symsynth.scene.costmap import Rule
from symsynth.scene.model import HAND, Scene
from symsynth.testing import Conformance

#: How near a dropped object must stand to its place (metres, radians).
PLACED = (1e-6, 1e-6)
#: The physical test: randomized trials, and how many must succeed.
TRIALS, PASSING = 10, 9
RANDOMIZE = Randomization(friction=0.2, mass=0.2, pose=0.005)


class PrimitiveConformance(Conformance):
    """The primitive suite; options: `scene` (a scene file, for a
    displacement primitive: give an absolute path, e.g. next to the test
    file), `contact` (the contact of that scene that uses the primitive),
    `slides` (the (from, to) pairs of locations expected, optional) and
    `planners` (default: the scene's own), `physical` (default True: the
    physical test, module doc; False leaves it out, for a primitive meant
    for the kinematic world only)."""

    OPTIONS = ("scene", "contact", "slides", "planners", "physical")
    scene: str | Path | None = None
    contact: str | None = None
    slides: set[tuple[str, str]] | None = None
    planners: tuple[str, ...] | None = None
    physical: bool = True

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if not cls.physical:  # not collected: no test that passes by checking nothing
            cls.test_it_does_in_the_world_what_it_claims = None  # type: ignore[assignment,method-assign]

    def test_the_registry_loads_it_under_its_name(self):
        plugin = primitive(self.name)  # the registry checks the kind and the members
        assert plugin.name == self.name

    def test_it_conforms_to_its_kind(self):
        plugin = primitive(self.name)
        if plugin.kind == "prehensile":
            from symsynth.testing.planner import scene as suite_scene

            block = suite_scene("single")
            for name in self.planners or ("ompl-fcl",):
                check_prehensile(plugin, block, planner_class(name)(block))
            return
        assert self.scene is not None and self.contact is not None, \
            f"the displacement primitive {self.name!r} needs conformance(..., scene=FILE, contact=NAME)"
        scene = load_scene(self.scene)
        assert scene.geometry is not None, f"{self.scene}: a primitive acts in physical scenes only"
        for name in self.planners or (scene.geometry.planner.name,):
            found = check_displacement(plugin, scene, planner_class(name)(scene), self.contact)
            if self.slides is not None:
                assert {(r.start, r.goal) for r in found} == set(self.slides), name


    def test_it_does_in_the_world_what_it_claims(self):
        plugin = primitive(self.name)
        if plugin.kind == "prehensile":
            from symsynth.testing.planner import scene as suite_scene

            block = suite_scene("single")
            check_prehensile_physics(plugin, block, planner_class((self.planners or ("ompl-fcl",))[0])(block))
            return
        assert self.scene is not None and self.contact is not None, \
            f"the displacement primitive {self.name!r} needs conformance(..., scene=FILE, contact=NAME)"
        scene = load_scene(self.scene)
        assert scene.geometry is not None, f"{self.scene}: a primitive acts in physical scenes only"
        check_displacement_physics(plugin, scene, planner_class(scene.geometry.planner.name)(scene), self.contact)


def check_displacement_physics(plugin: Any, scene: Scene, planner: Planner, contact: str) -> list[Rate]:
    """The physical clause of the module doc for each of the plugin's slides
    of `contact`, the object the one `_check_slide` takes; the rates."""
    found = []
    for rule in plugin.slides(scene, planner, contact, anchor_configs(planner, scene)):
        obj = ([o for o in scene.objects if o.at == rule.start] or list(scene.objects[:1]))[0].name
        subject = Subject("slide", (contact, rule.start, rule.goal), 0, obj, contact, rule.start, rule.goal,
                          Rule(rule.free, rule.cost, rule.path))
        tried = tuple(slide_tried(scene, subject, randomization=RANDOMIZE, seed=seed, primitive=plugin)
                      for seed in range(TRIALS))
        moved = [t.reason for t in tried if "nothing touched" in t.reason]
        assert not moved, f"{plugin.name}: slide {rule.start} -> {rule.goal} {moved[0]} (a pose set, not a push)"
        rate = Rate(subject, tried)
        assert rate.successes >= PASSING, \
            (f"{plugin.name}: slide {rule.start} -> {rule.goal} ended within {POSITION} m of {rule.goal} in "
             f"{rate.successes} of {TRIALS} physical trials (at least {PASSING} needed; worst "
             f"{rate.worst_error:.3f} m off)")
        found.append(rate)
    return found


def check_prehensile_physics(plugin: Any, scene: Scene, planner: Planner) -> Rate | None:
    """The physical clause for the game's grab and drop: grab the block
    where it stands and drop it there again, `TRIALS` randomized times;
    None for a prehensile primitive the game does not carry out."""
    if plugin.name not in ("grab", "drop"):
        return None
    (obj,), (grasp,) = scene.objects, scene.grasps
    anchor = tuple(anchor_configs(planner, scene)[f"{obj.at}/{grasp}"])
    subject = Subject("transfer", (f"{obj.name}/{grasp}", f"{obj.at}/{grasp}", f"{obj.at}/{grasp}"), 0, obj.name,
                      grasp, obj.at, obj.at, Rule(frozenset(), 0.0, (anchor,)))
    (rate,) = rates(scene, planner, [subject], TRIALS, randomization=RANDOMIZE)
    assert rate.successes >= PASSING, (f"{plugin.name}: grab and drop of {obj.name} at {obj.at} succeeded in "
                                       f"{rate.successes} of {TRIALS} physical trials ({'; '.join(rate.reasons)})")
    return rate


def check_displacement(plugin: Any, scene: Scene, planner: Planner, contact: str) -> list[SlideRule]:
    """Every clause of the module doc for a displacement primitive; returns
    the slides (at least one: a conformance run that checks nothing proves
    nothing)."""
    assert isinstance(plugin.name, str) and plugin.kind == "displacement"
    assert math.isfinite(plugin.fixed_cost) and plugin.fixed_cost >= 0
    geometry = scene.geometry
    assert geometry is not None, f"{scene.name}: a primitive acts in physical scenes only"
    anchors = anchor_configs(planner, scene)
    slides = plugin.slides(scene, planner, contact, anchors)
    assert slides, f"{plugin.name}: no slide with {contact} in {scene.name}"
    assert plugin.slides(scene, planner, contact, anchors) == slides  # a function of its arguments
    places = set(geometry.places)
    fixed = geometry.primitive_costs.get(plugin.name, plugin.fixed_cost)
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
        _check_slide(plugin, scene, rule)
    return slides


def _check_slide(plugin: Any, scene: Scene, rule: SlideRule) -> None:
    """The slide carried out on the object at its start, alone in the world
    (the rule's `free` places are free then): the one standing there, or the
    scene's first object put there."""
    standing = [o for o in scene.objects if o.at == rule.start] or list(scene.objects[:1])
    assert standing, f"{scene.name}: a scene without objects cannot show a slide"
    obj = dataclasses.replace(standing[0], at=rule.start)
    world = SimWorld(dataclasses.replace(scene, objects=(obj,)))
    try:
        world.set_config(rule.path[0])
        move = Move("slide", f"slide({obj.name},{rule.contact},{rule.goal})", obj.name, 0, rule.contact,
                    rule.goal, after=State((rule.goal,), None, (obj.name, rule.contact)))
        done = plugin.execute(world, move, rule.path)
        _assert_placed(world, obj.name, scene, rule.goal)
        assert world.held is None
        assert tuple(done.path[0]) == rule.path[0] and tuple(done.path[-1]) == rule.path[-1]
        assert done.radians >= 0
    finally:
        world.close()


def check_prehensile(plugin: Any, scene: Scene, planner: Planner) -> None:
    """Every clause of the module doc for a prehensile primitive, on a
    scene of one object standing at a location, with one grasp."""
    assert isinstance(plugin.name, str) and plugin.kind == "prehensile"
    geometry = scene.geometry
    assert geometry is not None, f"{scene.name}: a primitive acts in physical scenes only"
    (obj,), (grasp,) = scene.objects, scene.grasps
    held = plugin.holds(geometry, obj.name, grasp)
    assert isinstance(held, bool) and plugin.holds(geometry, obj.name, grasp) == held
    anchors = anchor_configs(planner, scene)
    for place in scene.locations:
        config = anchors[f"{place}/{grasp}"]
        reached = plugin.reaches(scene, planner, place, grasp, config)
        assert isinstance(reached, bool) and plugin.reaches(scene, planner, place, grasp, config) == reached
    if plugin.name not in ("grab", "drop"):
        return  # the game carries out no other prehensile action (primitive_registry.PREHENSILE_ACTIONS)
    start = anchors[f"{obj.at}/{grasp}"]
    world = SimWorld(scene)
    try:
        world.set_config(start)
        if plugin.name == "drop":
            world.attach(obj.name, grasp)
        after = State((HAND,), grasp, obj.at) if plugin.name == "grab" else State((obj.at,), None, (obj.name, grasp))
        move = Move(plugin.name, f"{plugin.name}({obj.name})", obj.name, 0, grasp, obj.at, after=after)
        done = plugin.execute(world, Approaches(planner), move)
        assert np.allclose(world.config, start, atol=1e-6), "the hand is back at the anchor it started from"
        assert tuple(done.path[0]) == tuple(start) and done.radians >= 0
        if plugin.name == "grab":
            assert (world.held, world.grasp) == (obj.name, grasp)
        else:
            assert world.held is None
            _assert_placed(world, obj.name, scene, obj.at)
    finally:
        world.close()


def _assert_placed(world: SimWorld, obj: str, scene: Scene, place: str) -> None:
    assert scene.geometry is not None
    goal = scene.geometry.places[place]
    assert np.allclose(world.poses[obj].xyz, goal.xyz, atol=PLACED[0]), (world.poses[obj], goal)
    assert world.poses[obj].angle_to(goal) < PLACED[1]


def moved_scene(scene: Scene, obj: str, place: str) -> Scene:
    """`scene` with `obj` standing at `place` (to check slides from there)."""
    objects = tuple(dataclasses.replace(o, at=place) if o.name == obj else o for o in scene.objects)
    return dataclasses.replace(scene, objects=objects)
