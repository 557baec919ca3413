"""Grab and drop, the two primitives of the abstraction (semantics §4), as motions
in the world.

Both are a Cartesian approach along the grasp's approach direction, from
the anchor (the grasp's pre-image) to the grasp pose, by inverse kinematics
at `APPROACH_STEPS` evenly spaced poses, each solution seeding the next; the
gripper closes (the object is attached to the hand: `SimWorld.attach`) or
opens (the object is set down exactly on the location's pose); then the
same path back, so the robot ends on the anchor it started from.  Their
cost is the scene's fixed `grab` / `drop` cost, as in the paper; the
radians they travel are reported, not charged.

Each configuration of the approach is checked in the world: the fingers
may meet the object they close around, nothing else.

The approach paths themselves are kept (`Approaches`, one per simulation):
inverse kinematics is a function of the pose and its seed configuration,
so an approach from the same configuration to the same poses -- an anchor
the runs come back to -- is the same path, and is computed once.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from symsynth.errors import SymsynthError
from symsynth.execution.motion import steps
from symsynth.execution.observe import close, place_at
from symsynth.execution.physics import SLIDE_SPEED, PhysicsWorld
from symsynth.execution.reach import reach
from symsynth.execution.world import SimWorld
from symsynth.planning.protocol import Config, Planner
from symsynth.planning.verify import path_length
from symsynth.scene.geometry import Grasp, Pose, point_text, vec3

APPROACH_STEPS = 6
SAME_HAND = (1e-4, 1e-3)  # metres, radians: a grasp pose this close to the planned one is that one
# (a tenth of inverse kinematics' tolerance: at 1 mm, 0.01 rad, two of 20 randomized arch runs
# ended 8.3 mm off instead of 0.3)
WALK = 0.01  # radians between the configurations checked along the approach


class PrimitiveFailed(SymsynthError):
    """A grab or drop that cannot be carried out in the world."""


@dataclass(frozen=True)
class Primitive:
    path: tuple[Config, ...]  # down and back up
    touched: frozenset[str]  # what the approach penetrated (should be nothing)

    @property
    def radians(self) -> float:
        return path_length(self.path)


class Approaches:
    """Approach paths by start configuration and poses, each solved once."""

    def __init__(self, planner: Planner) -> None:
        self.planner = planner
        self._paths: dict[tuple[Config, Pose, Pose], tuple[Config, ...]] = {}

    def path(self, config: Config, start: Pose, end: Pose, what: str) -> tuple[Config, ...]:
        """From `config` (at `start`) down to `end`, `APPROACH_STEPS` poses."""
        key = (tuple(config), start, end)
        if key not in self._paths:
            self._paths[key] = _approach(self.planner, key[0], start, end, what)
        return self._paths[key]


    def near(self, config: Config, place: Pose, actual: Pose, grasp: Grasp, what: str,
             solve: Callable[[Pose, Config], Config | None] | None = None) -> tuple[Config, ...]:
        """The approach of `grasp` to an object at `actual`, close to
        `place` (within the observation's tolerance): the approach to
        `place` (`path`, solved once) bent toward the one solution at the
        grasp pose on `actual`, its configurations shifted by that end's
        difference in proportion to their way down.  One inverse kinematics
        solution for an object a physical world moved a few millimetres,
        where `path` would solve `APPROACH_STEPS` of them; the hand's poses
        on the way lie within a fraction of a millimetre of the straight
        approach (the shift's square times the arm's curvature).  Where the
        hand's grasp pose on `actual` is within `SAME_HAND` of the one on
        `place` (metres, radians: an object that has not moved from where
        it was put), `path` as it is, with no solution solved.  `solve(pose,
        seed)` finds that one solution (default: the planner's inverse
        kinematics; the physical world's grab: `reach`, Newton steps from the
        approach's end); where it finds none, `path` solves the approach to
        `actual` whole."""
        nominal = self.path(config, place @ grasp.pre_image(), place @ grasp.pose, what)
        hand, planned = actual @ grasp.pose, place @ grasp.pose
        if math.dist(hand.xyz, planned.xyz) <= SAME_HAND[0] and hand.angle_to(planned) <= SAME_HAND[1]:
            return nominal
        end = (solve or self.planner.inverse_kinematics)(hand, nominal[-1])
        if end is None:
            return self.path(config, actual @ grasp.pre_image(), actual @ grasp.pose, what)
        shift = np.subtract(end, nominal[-1])
        last = len(nominal) - 1
        return (nominal[0], *(tuple(float(v) for v in np.add(q, shift * (i / last)))
                              for i, q in enumerate(nominal[1:-1], 1)), tuple(end))


def grab(world: SimWorld, approaches: Approaches, name: str, grasp: str) -> Primitive:
    """Close the hand on object `name` with `grasp`, from its pre-image.
    In the physical world an object within the observation's tolerance of
    a place is approached by `Approaches.near` (the place's approach, bent)."""
    g = world.geometry.grasps[grasp]
    target = world.poses[name]
    if isinstance(world, PhysicsWorld):
        place = place_at(world.scene, target)
        if place is not None and close(world.geometry.places[place], target):
            down = approaches.near(world.config, world.geometry.places[place], target, g, f"grab({name})",
                                   solve=lambda pose, seed: reach(world, seed, pose))
        else:
            down = approaches.path(world.config, target @ g.pre_image(), target @ g.pose, f"grab({name})")
        return _physical(world, down, lambda: world.close_hand(name, grasp), {name})
    down = approaches.path(world.config, target @ g.pre_image(), target @ g.pose, f"grab({name})")
    hits = _walk(world, down, ignore={name})
    world.attach(name, grasp)
    up = down[::-1]
    hits |= _walk(world, up, ignore={name})
    return Primitive(down + up[1:], frozenset(hits))


def drop(world: SimWorld, approaches: Approaches, location: str) -> Primitive:
    """Open the hand over `location` and leave the held object on its pose."""
    name, grasp = world.held, world.grasp
    if name is None or grasp is None:  # held and grasp are set together
        raise PrimitiveFailed(f"drop at {location}: the hand is empty")
    g = world.geometry.grasps[grasp]
    place = world.geometry.places[location]
    down = approaches.path(world.config, place @ g.pre_image(), place @ g.pose, f"drop({name},{location})")
    if isinstance(world, PhysicsWorld):
        return _physical(world, down, world.open_hand, {name})
    hits = _walk(world, down)
    world.detach()
    world.place(name, place)
    up = down[::-1]
    hits |= _walk(world, up, ignore={name})
    return Primitive(down + up[1:], frozenset(hits))


CONTACT_TOLERANCE = 0.002  # metres: the hand is at a contact pose
CAREFUL = 0.03  # metres: a physical slide's hand slows this close to its way


def slide(world: SimWorld, move: Any, path: Sequence[Config]) -> Primitive:
    """Slide `move.obj` with its contact `move.grasp` to `move.location`
    along `path` (a slide rule's evidence, `planning.slides`): the object
    is taken along, kinematically, from where the hand reaches the contact
    pose at the object's pose to where it reaches the contact pose at the
    target, and is then set down exactly on the target's pose."""
    name, contact, goal = move.obj, move.grasp, move.location
    if isinstance(world, PhysicsWorld):
        return physical_slide(world, name, contact, goal, path)
    frame = world.geometry.hand_frame(contact)
    at_contact = world.poses[name] @ frame.pose
    at_goal = world.geometry.places[goal] @ frame.pose
    hits: set[str] = set()
    stage = "before"
    for config in steps(path, WALK):
        world.set_config(config)
        ee = world.ee_pose()
        if stage == "before" and _near(ee, at_contact):
            world.attach(name, contact)
            stage = "sliding"
        elif stage == "sliding" and _near(ee, at_goal):
            world.detach()
            world.place(name, world.geometry.places[goal])
            stage = "after"
        hits |= world.touching(ignore={name})
    if stage != "after":
        if stage == "sliding":
            world.detach()
        raise PrimitiveFailed(f"{move.action}: the path never brings the hand to the contact "
                              + ("pose at the target" if stage == "sliding" else f"pose at {name}"))
    return Primitive(tuple(path), frozenset(hits))


def physical_slide(world: PhysicsWorld, name: str, contact: str, goal: str, path: Sequence[Config]) -> Primitive:
    """The slide in the physical world: the fingers closed (the hand a
    paddle), the joints driven along `path`, the hand at most
    `physics.SLIDE_SPEED` on legs within `CAREFUL` of the straight way of
    the contact pose from the object to `goal` (elsewhere as fast as any
    motion); the object moves only as the hand pushes it and friction holds
    it back, and settles before it is observed.  Nothing is set, nothing
    constrained.  A leg that goes back against the slide's way (the
    retreat, the hand leaving the object behind) is not slowed, and one
    clear of every object goes as fast as a transit's (`follow`'s `clear`)."""
    frame = world.geometry.hand_frame(contact).pose
    a = np.asarray((world.poses[name] @ frame).xyz)
    b = np.asarray((world.geometry.places[goal] @ frame).xyz)

    def near(point: np.ndarray) -> bool:  # near the segment a-b
        t = float(np.clip(np.dot(point - a, b - a) / max(float(np.dot(b - a, b - a)), 1e-12), 0.0, 1.0))
        return float(np.linalg.norm(point - (a + t * (b - a)))) <= CAREFUL

    def careful(start: np.ndarray, end: np.ndarray) -> bool:  # a leg near the way, going the slide's way
        return (near(start) or near(end)) and float(np.dot(end - start, b - a)) > 0.0

    world.close_hand()
    with world.watched() as touched:
        world.follow(path, hand_speed=SLIDE_SPEED, careful=careful, clear=True)
    world.open_hand()
    return Primitive(tuple(path), frozenset(touched - {name}))


def _physical(world: PhysicsWorld, down: tuple[Config, ...], act, allowed: set[str]) -> Primitive:
    """Down the approach, `act` (close or open the hand), back up; what the
    robot touched on the way besides `allowed` (PyBullet's contact points)."""
    with world.watched() as touched:
        world.follow(down)
        act()
        up = down[::-1]
        world.follow(up, settle=True, passing=True)  # the objects' rest watched while the robot arrives
    return Primitive(down + up[1:], frozenset(touched - allowed))


def _near(a: Pose, b: Pose) -> bool:
    return float(np.linalg.norm(np.subtract(a.xyz, b.xyz))) <= CONTACT_TOLERANCE and a.angle_to(b) <= 0.02


def _approach(planner: Planner, at: Config, start: Pose, end: Pose, what: str) -> tuple[Config, ...]:
    path = [at]
    for i in range(1, APPROACH_STEPS + 1):
        t = i / APPROACH_STEPS
        xyz = vec3(a + (b - a) * t for a, b in zip(start.xyz, end.xyz))
        config = planner.inverse_kinematics(Pose(xyz, end.quat), path[-1])
        if config is None:
            raise PrimitiveFailed(f"{what}: no inverse kinematics solution {t:.0%} of the way "
                                  f"down the approach (end-effector at {point_text(xyz)})")
        path.append(tuple(config))
    return tuple(path)


def _walk(world: SimWorld, path: Sequence[Config], ignore: Collection[str] = frozenset()) -> set[str]:
    hits: set[str] = set()
    for config in steps(path, WALK):
        world.set_config(config)
        hits |= world.touching(ignore)
    return hits

