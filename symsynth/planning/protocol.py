"""The small interface every planner plugin implements.

A planner is built for one physical scene (`Planner(scene)`) and answers
geometric questions in one *mode*: the hand empty, or holding object `o` with
grasp `g`.  Static obstacles are the table and the scene's `obstacles`.  A
*location obstacle* at `x` (a location of interest or an Else sample) stands
for "some object other than the served one stands at `x`"; its geometry is
every object's shape but the held one's, placed at `x`'s pose (a sound
over-approximation when objects differ).

Everything the costmap algorithms need reduces to four calls; the
conformance suite (`symsynth.testing.planner`) pins their meaning.
Conventions both built-in planners follow (and the suite checks):

* touching (zero distance) is not a collision; penetration is;
* the robot's root link is never checked against static obstacles or
  places (a base standing on the table touches it);
* the held object is not checked against the end-effector link and the
  links below it (the fingers hold it), but against the rest of the robot;
* when `Contacts.static` is true, `locations` may be incomplete (the check
  stops early; for `motion_contacts`, exactly where is fixed below);
* "at most `step` radians" is the euclidean norm in joint space, and
  the roadmap's edges are checked at `geometry.planner.check_step`;
* an unknown object or grasp in a mode raises `PlannerError`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

from symsynth.errors import SymsynthError
from symsynth.scene.geometry import Pose
from symsynth.scene.model import EMPTY, Scene

Config = tuple[float, ...]  # one value per controlled joint, radians


@dataclass(frozen=True)
class Mode:
    """`Mode()` is the empty hand; `Mode("w1", "top")` holds w1 by its top grasp."""

    object: str | None = None
    grasp: str | None = None

    def __str__(self) -> str:
        return EMPTY if self.object is None else f"{self.object}/{self.grasp}"

    @staticmethod
    def parse(text: str) -> Mode:
        if text == EMPTY:
            return Mode()
        obj, _, grasp = text.partition("/")
        return Mode(obj, grasp)


@dataclass(frozen=True)
class Contacts:
    """What a configuration or a motion touches: `static` is a collision with
    the robot itself or a static obstacle (the motion is impossible whatever
    the objects do); `locations` are the location obstacles it touches."""

    static: bool = False
    locations: frozenset[str] = frozenset()

    def __or__(self, other: Contacts) -> Contacts:
        return Contacts(self.static or other.static, self.locations | other.locations)


@dataclass(frozen=True)
class Roadmap:
    """A graph in configuration space, collision-free against static
    obstacles; `anchors` names the vertices that are anchors."""

    configs: np.ndarray  # (n, d)
    edges: np.ndarray  # (m, 2) vertex indices, each undirected edge once
    lengths: np.ndarray  # (m,) joint-space euclidean length, radians
    anchors: Mapping[str, int] = field(default_factory=dict)


class PlannerError(SymsynthError):
    """A planner could not do what was asked (unreachable anchor, plugin that
    does not load, ...); the message names what and why."""


@runtime_checkable
class Planner(Protocol):
    name: ClassVar[str]

    def __init__(self, scene: Scene) -> None: ...

    @property
    def limits(self) -> np.ndarray:
        """(d, 2) lower and upper bound of each controlled joint."""

    def inverse_kinematics(self, pose: Pose, seed: Config) -> Config | None:
        """A configuration placing the end-effector link at `pose` (world),
        verified by forward kinematics (position within 1 mm, orientation
        within 0.01 rad), inside the joint limits; None if none was found.
        A function of (pose, seed): the same arguments give the same answer,
        whatever was asked before (the simulator reuses approach paths, and
        runs with one seed must repeat)."""

    def contacts(self, mode: Mode, config: Config) -> Contacts:
        """Collisions of the robot (and, in a holding mode, the held object)
        at one configuration: self-collision (adjacent links excluded,
        `planning.adjacent`), static obstacles, and location obstacles."""

    def motion_contacts(self, mode: Mode, start: Config, goal: Config, step: float) -> Contacts:
        """`contacts` along the straight joint-space segment, checked at steps
        of at most `step` radians, both ends included (`planning.segment`).

        The check stops at the first configuration with a static contact (the
        whole motion is unusable): the answer is then `static=True` with the
        locations touched by the configurations before that one, not by it
        or any after it (from a start in static collision: none)."""

    def roadmap(self, mode: Mode, anchors: Mapping[str, Config], size: int, seed: int,
                seconds: float | None = None) -> Roadmap:
        """A roadmap of about `size` vertices plus the anchors, whose edges are
        free of static collisions (location obstacles ignored).  With
        `seconds`, the vertices it can add in that time instead of `size`
        (the scene's `planner: {seconds: S}`).  A planner that honours
        `seconds` says so with a class attribute `time_limited = True`; one
        without it may leave the parameter out, and such scenes are refused
        with one message before any work."""
