"""Slides along the table, the geometry every displacement primitive shares.

A slide of object `o` by contact `a` from location `l` to `l2` is three
straight Cartesian segments of the end-effector, followed by inverse
kinematics in small steps (each seeded with the last configuration, a step halved where the
solution jumps: `_reach`):

1. *approach*: from the anchor `l/a` (the contact's pre-image) in to the
   contact pose, the object standing at `l`;
2. *slide*: the contact pose carried from `l` to `l2`, the object moving
   with it rigidly;
3. *retreat*: back out to the pre-image at `l2`, then, if inverse
   kinematics ended elsewhere than the anchor `l2/a`'s configuration, a
   joint-space segment to it (the game's hand ends at that anchor).

Only slides between locations whose poses share their orientation and
height are possible (the object stays on the table as it was).  A step of
inverse kinematics that fails, or that jumps more than `MAX_JUMP` radians
(another branch of the arm's solutions), or any static collision along the
path makes the slide impossible.  The places the hand touches along the
path and those the object's footprint sweeps on the table (bounding
circles: `swept_places`), other than `l` and `l2`, are the rule's `free`
set (the object itself is not checked by the planner in the contact's frame: it
slides touching the table, and inverse kinematics' tolerance of 0.01 rad
would tilt it into the table); its cost is the path's length in radians x `per_radian`, plus
the primitive's fixed cost.  One path, so one rule per slide, and the
start-goal and recursive costmap methods give the same slide rules.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from symsynth.planning.primitive_protocol import SlideRule
from symsynth.planning.protocol import Config, Contacts, Mode, Planner
from symsynth.scene.geometry import Pose, vec3
from symsynth.scene.model import Scene, geometry_of

STEP = 0.01  # metres between inverse kinematics steps along a segment
MAX_JUMP = 0.3  # radians (joint-space norm) between two steps
SPLITS = 5  # halvings of a step whose inverse kinematics jumps
SAME_HEIGHT = 1e-3  # metres
SAME_ORIENTATION = 1e-3  # radians


def slide_path(scene: Scene, planner: Planner, obj: str, contact: str, start: str, goal: str,
               anchors: Mapping[str, Config]) -> tuple[tuple[Config, ...], frozenset[str]] | None:
    """The configurations of the slide (module doc) and the places it
    touches, or None when it is not possible."""
    geometry = geometry_of(scene)
    frame = geometry.hand_frame(contact)
    here, there = geometry.places[start], geometry.places[goal]
    if abs(here.xyz[2] - there.xyz[2]) > SAME_HEIGHT or here.angle_to(there) > SAME_ORIENTATION:
        return None
    first, last = anchors.get(f"{start}/{contact}"), anchors.get(f"{goal}/{contact}")
    if first is None or last is None:
        return None
    path = [tuple(first)]
    swept = swept_places(scene, obj, start, goal)
    if swept is None:
        return None
    touched: set[str] = set(swept)
    segments = [(here @ frame.pre_image(), here @ frame.pose), (here @ frame.pose, there @ frame.pose),
                (there @ frame.pose, there @ frame.pre_image())]
    for a, b in segments:
        found = straight(planner, path[-1], a, b, geometry.planner.check_step)
        if found is None:
            return None
        path += found[0][1:]
        touched |= found[1]
    if path[-1] != tuple(last):
        ending: Contacts = planner.motion_contacts(Mode(), path[-1], tuple(last), geometry.planner.check_step)
        if ending.static:
            return None
        touched |= ending.locations
        path.append(tuple(last))
    return tuple(path), frozenset(touched - {start, goal})


def straight(planner: Planner, q: Config, a: Pose, b: Pose, step: float
             ) -> tuple[list[Config], frozenset[str]] | None:
    """The end-effector along the straight line from pose `a` (where the
    robot stands at `q`) to pose `b`, the hand empty, by inverse kinematics
    in `STEP`s: the configurations (`q` first) and the places the motion
    through them touches (each joint-space segment checked at `step`
    radians, as `costmap verify` checks it again); None when a step fails
    or the hand meets a static obstacle.  Shared by the slides and by the
    grab's approach (`symsynth_primitives`)."""
    path: list[Config] = [tuple(q)]
    touched: set[str] = set()
    previous = a
    for pose in _between(a, b):
        reached = _reach(planner, path[-1], previous, pose, 0)
        if reached is None:
            return None
        for config in reached:
            found = planner.motion_contacts(Mode(), path[-1], config, step)
            if found.static:
                return None
            touched |= found.locations
            path.append(config)
        previous = pose
    return path, frozenset(touched)


def slide_rule(scene: Scene, planner: Planner, obj: str, contact: str, start: str, goal: str,
               anchors: Mapping[str, Config], fixed_cost: float) -> SlideRule | None:
    """The slide rule of one slide (module doc), None when it is impossible."""
    found = slide_path(scene, planner, obj, contact, start, goal, anchors)
    if found is None:
        return None
    path, touched = found
    length = float(np.linalg.norm(np.diff(np.asarray(path), axis=0), axis=1).sum())
    cost = length * geometry_of(scene).per_radian + fixed_cost
    return SlideRule(contact, start, goal, touched, cost, path)


def swept_places(scene: Scene, obj: str, start: str, goal: str) -> frozenset[str] | None:
    """The places other than `start` and `goal` whose objects the slid
    object's footprint may meet on its way: those within the sum of the two
    footprints' radii of the straight segment from `start` to `goal`
    (bounding circles on the table: more places than exactly touched,
    never fewer, so the rule's condition stays sound).  None for an object
    of a shape without a known footprint (a mesh)."""
    geometry = geometry_of(scene)
    shapes = geometry.shapes
    radius = _footprint(shapes[obj])
    others = [_footprint(shape) for name, shape in shapes.items() if name != obj]
    known = [r for r in others if r is not None]
    if radius is None or len(known) < len(others):
        return None
    reach = radius + max(known, default=0.0)
    places = geometry.places
    a, b = np.asarray(places[start].xyz[:2]), np.asarray(places[goal].xyz[:2])
    found = set()
    for name, pose in places.items():
        if name in (start, goal):
            continue
        p = np.asarray(pose.xyz[:2])
        t = float(np.clip(np.dot(p - a, b - a) / max(float(np.dot(b - a, b - a)), 1e-12), 0.0, 1.0))
        if np.linalg.norm(p - (a + t * (b - a))) < reach:
            found.add(name)
    return frozenset(found)


def _footprint(shape) -> float | None:
    """The radius of a shape's footprint on the table (box, cylinder)."""
    if shape.kind == "box":
        return math.hypot(shape.size[0], shape.size[1]) / 2
    if shape.kind == "cylinder":
        return shape.radius
    return None


def direction(scene: Scene, contact: str, start: str, goal: str) -> float:
    """The angle (radians) between the slide's direction on the table and
    the direction the contact's hand faces (its z axis, along which it
    approaches), both projected on the table; pi when the hand faces
    straight down."""
    geometry = geometry_of(scene)
    here, there = geometry.places[start], geometry.places[goal]
    facing = (here @ geometry.hand_frame(contact).pose).matrix()[:3, 2]
    move = np.subtract(there.xyz, here.xyz)
    facing, move = facing[:2], move[:2]
    if np.linalg.norm(facing) < 1e-6 or np.linalg.norm(move) < 1e-9:
        return math.pi
    cos = float(np.dot(facing, move) / (np.linalg.norm(facing) * np.linalg.norm(move)))
    return math.acos(max(-1.0, min(1.0, cos)))


def _reach(planner: Planner, q: Config, a: Pose, b: Pose, depth: int) -> list[Config] | None:
    """Configurations from `q` (at pose `a`) to pose `b`: one inverse
    kinematics step, or, when it fails or jumps to another branch of the
    arm's solutions, two half steps (at most `SPLITS` times over: an
    inverse kinematics that is not local at 1 cm often is at 5 mm)."""
    found = planner.inverse_kinematics(b, q)
    if found is not None and np.linalg.norm(np.subtract(found, q)) <= MAX_JUMP:
        return [tuple(found)]
    if depth == SPLITS:
        return None
    middle = Pose(vec3(np.add(a.xyz, b.xyz) / 2), b.quat)
    first = _reach(planner, q, a, middle, depth + 1)
    if first is None:
        return None
    second = _reach(planner, first[-1], middle, b, depth + 1)
    return None if second is None else first + second


def _between(a: Pose, b: Pose) -> list[Pose]:
    """Poses from a (excluded) to b (included) along the straight line, at
    most STEP apart, the orientation of `a` (the segments keep it)."""
    gap = np.subtract(b.xyz, a.xyz)
    steps = max(1, math.ceil(np.linalg.norm(gap) / STEP))
    return [Pose(vec3(np.add(a.xyz, gap * i / steps)), a.quat) for i in range(1, steps + 1)]
