"""Collision-only pybullet bodies made from symsynth shapes, and the
collision groups that decide which bodies are ever compared.

A `Shape`'s frame is the centre of its bottom face (boxes, cylinders) while
pybullet builds primitives around their centre, so a body's base sits at
`pose @ shape.centre_offset()`.  Meshes are used as authored: convex hulls
for objects (they move), exact triangle meshes for static obstacles (a
shelf or a bin is concave, and a static body may be).

Groups (one bit each) and the pairs that are checked, symmetric so that
pybullet's group/mask test gives the same answer in either filter mode:

    robot links <-> robot links, base, held, static, place
    held object <-> robot links, base, static, place
    base link   <-> robot links, held
    static, place bodies <-> robot links, held

The robot's base link never moves, so its contacts with static obstacles
and places (the table it stands on) are a property of the scene, not of a
configuration: they are never checked.  Static and place bodies are never
compared with each other (objects stand on the table).
"""

from __future__ import annotations

from symsynth.bullet import collision_shape

from symsynth.scene.geometry import Pose, Shape

ROBOT, BASE, HELD, STATIC, PLACE = 1, 2, 4, 8, 16
MASK = {
    ROBOT: ROBOT | BASE | HELD | STATIC | PLACE,
    BASE: ROBOT | HELD,
    HELD: ROBOT | BASE | STATIC | PLACE,
    STATIC: ROBOT | HELD,
    PLACE: ROBOT | HELD,
}
OFF = 0  # group and mask of a body that takes part in nothing
PARKED = ((0.0, 0.0, -1000.0), (0.0, 0.0, 0.0, 1.0))  # where unused bodies wait


def make_body(client, shape: Shape, pose: Pose | None, group: int, *, concave: bool = False) -> int:
    """A massless body of `shape` with its shape frame at `pose` (parked
    out of the way when `pose` is None), in collision group `group`."""
    shape_id = collision_shape(client, shape, concave=concave)
    position, orientation = PARKED if pose is None else base_pose(pose, shape)
    body = client.createMultiBody(baseMass=0, baseCollisionShapeIndex=shape_id,
                                  basePosition=position, baseOrientation=orientation)
    set_group(client, body, -1, group)
    return body


def base_pose(pose: Pose, shape: Shape) -> tuple[tuple, tuple]:
    """Position and quaternion of the pybullet base for a shape frame at `pose`."""
    centre = pose @ shape.centre_offset()
    return centre.xyz, centre.quat


def set_group(client, body: int, link: int, group: int) -> None:
    client.setCollisionFilterGroupMask(body, link, group, MASK.get(group, OFF))
