"""fcl collision geometry for scene shapes and URDF collision elements.

Every solid is a `Solid`: an fcl geometry, the pose of that geometry in its
owner's frame (fcl builds boxes and cylinders centred on their origin), and
an oriented bounding box in the geometry's frame (pose, half extents) for
culling (`bounds`).

* Robot links use the **convex hull** of each collision mesh: a solid, so a
  small object fully inside a link still collides.  The Panda's collision
  meshes are near-convex already (hulls 10-30 % larger), and with culling
  by bounding boxes first, hulls and triangle meshes check equally fast.
* Scene meshes (obstacles, objects) are kept as authored, as fcl triangle
  meshes (BVH): a hull would fill a shelf's openings.  A triangle mesh is a
  surface: something entirely inside it without touching it is not a contact.
* Boxes and cylinders are fcl primitives, lifted by `Shape.centre_offset()`
  (their frame is the centre of the bottom face).
* Mesh files are read by `symsynth.scene.mesh.load_mesh`, once per file
  version (the scene loader has read the scene's already).
* URDF mesh references: `package://a/b.obj` and `a/b.obj` resolve against
  the URDF's directory, as `a/b.obj` or, failing that, `b.obj` (a ROS
  package name as first component).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import fcl
import numpy as np
import trimesh
import yourdfpy

from symsynth.planning.protocol import PlannerError
from symsynth.scene.geometry import Shape
from symsynth.scene.mesh import load_mesh


@dataclass(frozen=True)
class Solid:
    geometry: fcl.CollisionGeometry
    offset: np.ndarray  # 4x4, the geometry's pose in its owner's frame
    box: np.ndarray  # 4x4, the bounding box's pose in the geometry's frame
    half: np.ndarray  # (3,), the bounding box's half extents


def box(size) -> Solid:
    size = np.asarray(size, dtype=float)
    return Solid(fcl.Box(*size), np.eye(4), np.eye(4), size / 2)


def cylinder(radius: float, height: float) -> Solid:
    return Solid(fcl.Cylinder(radius, height), np.eye(4), np.eye(4), np.array([radius, radius, height / 2]))


def sphere(radius: float) -> Solid:
    return Solid(fcl.Sphere(radius), np.eye(4), np.eye(4), np.full(3, float(radius)))


def hull(mesh: trimesh.Trimesh) -> Solid:
    """The convex hull of a mesh, as an fcl `Convex`."""
    convex = mesh.convex_hull
    faces = np.hstack([np.full((len(convex.faces), 1), 3), convex.faces]).ravel()
    geometry = fcl.Convex(np.asarray(convex.vertices, dtype=float), len(convex.faces), faces)
    return _bounded(geometry, convex)


def triangles(mesh: trimesh.Trimesh) -> Solid:
    """A mesh as authored, as an fcl triangle mesh (BVH)."""
    model = fcl.BVHModel()
    model.beginModel(len(mesh.vertices), len(mesh.faces))
    model.addSubModel(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64))
    model.endModel()
    return _bounded(model, mesh)


def _bounded(geometry: fcl.CollisionGeometry, mesh: trimesh.Trimesh) -> Solid:
    """With the mesh's minimum-volume oriented bounding box (trimesh)."""
    bounds = mesh.bounding_box_oriented.primitive
    return Solid(geometry, np.eye(4), np.asarray(bounds.transform, dtype=float),
                 np.asarray(bounds.extents, dtype=float) / 2)


def scene_solid(shape: Shape) -> Solid:
    """A scene shape (obstacle or object) in its own frame."""
    if shape.kind == "box":
        solid = box(shape.size)
    elif shape.kind == "cylinder":
        solid = cylinder(shape.radius, shape.height)
    elif shape.kind == "mesh" and shape.mesh is not None:
        solid = triangles(load_mesh(shape.mesh, shape.scale))
    else:
        raise PlannerError(f"unknown shape kind {shape.kind!r} (box, cylinder or mesh with a file)")
    return with_offset(solid, shape.centre_offset().matrix())


def with_offset(solid: Solid, offset: np.ndarray) -> Solid:
    return Solid(solid.geometry, offset @ solid.offset, solid.box, solid.half)


def link_solids(model: yourdfpy.URDF, urdf: Path, link: str) -> list[Solid]:
    """A URDF link's collision elements, in the link frame (meshes as
    convex hulls)."""
    solids = []
    for element in model.link_map[link].collisions:
        shape = element.geometry
        if shape.box is not None:
            solid = box(shape.box.size)
        elif shape.cylinder is not None:
            solid = cylinder(shape.cylinder.radius, shape.cylinder.length)
        elif shape.sphere is not None:
            solid = sphere(shape.sphere.radius)
        elif shape.mesh is not None:
            path = resolve_mesh(urdf, shape.mesh.filename)
            solid = hull(load_mesh(path, 1.0 if shape.mesh.scale is None else shape.mesh.scale))
        else:
            raise PlannerError(f"link {link} has a collision element without geometry")
        origin = np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=float)
        solids.append(with_offset(solid, origin))
    return solids


def resolve_mesh(urdf: Path, filename: str) -> Path:
    """A URDF mesh reference as a file: `package://a/b.obj` and `a/b.obj` are
    tried as `<urdf dir>/a/b.obj`, then without the first component."""
    relative = filename.removeprefix("package://").removeprefix("file://")
    if Path(relative).is_absolute():
        return Path(relative)
    first = urdf.parent / relative
    parts = Path(relative).parts
    second = urdf.parent.joinpath(*parts[1:]) if len(parts) > 1 else first
    return first if first.exists() or not second.exists() else second
