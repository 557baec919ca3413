"""γ: the abstract state a vision system would read from the world (paper
Sec. V-B), and the places objects physically stand on.

- An object in the hand is at `Hand`.  Otherwise it is at location `l` when
  its frame is within `POSITION` metres of `l`'s pose, else at `Else`
  (orientation is not looked at: a block turned on its spot still stands
  there).
- The end-effector, hand empty, is at `(o, g)` when its link frame is
  within `POSITION` metres and `ANGLE` radians of the pre-image of grasp
  `g` on `o` where `o` really stands; holding with grasp `g`, it is at `l`
  when it is that close to `l`'s pre-image (`l ∈ L`); otherwise at `Else`.

The tolerances are far below the distance between two places (a scene
whose places are closer than 2 x `POSITION` would make γ ambiguous; the
first match in scene order wins) and far above the error of inverse
kinematics (1 mm, 0.01 rad).
"""

from __future__ import annotations

import math

from symsynth.execution.world import SimWorld
from symsynth.game.abstraction import State
from symsynth.scene.geometry import Pose
from symsynth.scene.model import ELSE, HAND, Scene, geometry_of

POSITION = 0.01  # metres
ANGLE = 0.05  # radians


def observe(scene: Scene, world: SimWorld) -> State:
    """γ(world)."""
    at = tuple(HAND if name == world.held else location_at(scene, world.poses[name])
               for name in scene.object_names)
    ee_pose = world.ee_pose()
    grasps = world.geometry.hand_frames  # grasps and contacts
    if world.held is not None and world.grasp is not None:
        pre_image = grasps[world.grasp].pre_image()
        ee = next((l for l in scene.locations if close(ee_pose, world.geometry.places[l] @ pre_image)), ELSE)
        return State(at, world.grasp, ee)
    for name in scene.object_names:
        for g in scene.preimages:
            if close(ee_pose, world.poses[name] @ grasps[g].pre_image()):
                return State(at, None, (name, g))
    return State(at, None, ELSE)


def location_at(scene: Scene, pose: Pose) -> str:
    """The location of interest an object at `pose` stands on, or `Else`."""
    place = place_at(scene, pose)
    return place if place in scene.locations else ELSE


def place_at(scene: Scene, pose: Pose) -> str | None:
    """The place (location of interest or Else sample) at `pose`, if any:
    the anchors, and the costmap's motions, exist only for places."""
    places = geometry_of(scene).places
    return next((x for x in scene.locations + scene.else_samples if distance(pose, places[x]) <= POSITION),
                None)


def distance(a: Pose, b: Pose) -> float:
    return math.dist(a.xyz, b.xyz)


def close(a: Pose, b: Pose) -> bool:
    return distance(a, b) <= POSITION and a.angle_to(b) <= ANGLE
