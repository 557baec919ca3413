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

from symsynth.bullet import pybullet as p

from symsynth.planning.protocol import PlannerError
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


def collision_shape(client, shape: Shape, *, concave: bool = False) -> int:
    """A pybullet collision shape id for `shape`, centred as pybullet wants."""
    if shape.kind == "box":
        return client.createCollisionShape(p.GEOM_BOX, halfExtents=[s / 2 for s in shape.size])
    if shape.kind == "cylinder":
        return client.createCollisionShape(p.GEOM_CYLINDER, radius=shape.radius, height=shape.height)
    if shape.kind == "mesh" and shape.mesh is not None:
        flags = p.GEOM_FORCE_CONCAVE_TRIMESH if concave else 0
        shape_id = client.createCollisionShape(p.GEOM_MESH, fileName=str(shape.mesh),
                                               meshScale=[shape.scale] * 3, flags=flags)
        if shape_id < 0:
            raise PlannerError(f"pybullet could not load the mesh {shape.mesh}")
        return shape_id
    raise PlannerError(f"unknown shape kind {shape.kind!r} (expected box, cylinder or mesh)")


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
