"""Grab and drop: the hand closes on a grasp, or opens over a location.

The game charges the scene's fixed costs (`costs: {grab, drop}`); the
simulator carries them out with `execution.hand_motions` (approach along the
grasp's axis, close or open, retreat).

`holds` says which objects a grasp can close on: those no wider,
across the fingers (the hand's y axis), than the robot's `opening`.  The
costmap has no motion holding an object the hand cannot close on, so such
an object is never carried (a box wider than the gripper opens can still
be pushed).  `reaches` says where a grasp can close at all: where the
hand's straight approach from the anchor down to the grasp pose meets no
static obstacle (under a low shelf it does not); the costmap has no motion
holding anything at a place it cannot reach.  Drop answers both as grab
does: it comes down the same approach and opens the hand that closed."""

from __future__ import annotations

from typing import Any, ClassVar

from symsynth.execution import hand_motions
from symsynth.planning.slides import straight
from symsynth.scene.geometry import Geometry


class _Hand:
    """What grab and drop share: the hand comes straight down from the anchor
    to the grasp pose and back, closing on the object or opening around it,
    so they act on the same objects (`holds`) at the same places (`reaches`)."""

    kind: ClassVar[str] = "prehensile"

    def reaches(self, scene: Any, planner: Any, place: str, grasp: str, anchor: Any) -> bool:
        """Whether the hand, empty, goes straight from the anchor `place/grasp`
        (configuration `anchor`) to the grasp pose at `place` by inverse
        kinematics without meeting a static obstacle."""
        pose, frame = scene.geometry.places[place], scene.geometry.grasps[grasp]
        return straight(planner, anchor, pose @ frame.pre_image(), pose @ frame.pose,
                        scene.geometry.planner.check_step) is not None

    def holds(self, geometry: Geometry, obj: str, grasp: str) -> bool:
        """Whether the hand closes on `obj` with `grasp`: its width across
        the fingers at most the robot's opening (always, when the robot has
        none, or for a mesh)."""
        opening = geometry.robot.opening
        width = geometry.across_fingers(obj, grasp)
        return opening is None or width is None or width <= opening + 1e-9


class Grab(_Hand):
    name: ClassVar[str] = "grab"

    def execute(self, world: Any, approaches: Any, move: Any) -> Any:
        return hand_motions.grab(world, approaches, move.obj, move.grasp)


class Drop(_Hand):
    name: ClassVar[str] = "drop"

    def execute(self, world: Any, approaches: Any, move: Any) -> Any:
        return hand_motions.drop(world, approaches, move.location)
