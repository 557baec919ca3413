"""Triangle meshes read from files, once per version of a file.

The scene loader reads every mesh a scene names (so that a file nobody can
use is reported with the scene's other problems) and the ompl-fcl planner
reads them again, with the robot's collision meshes, for its solids: both
go through `load_mesh`, which parses a file once for as long as its
modification time and size stay the same.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from symsynth.errors import InputError
from symsynth.files import check_regular

if TYPE_CHECKING:
    import trimesh


#: The largest mesh file read (the bundled ones are a few kilobytes).
MAX_BYTES = 256 << 20


class MeshError(InputError):
    """A mesh file that cannot be read, or holds no triangles."""


def load_mesh(path: Path, scale=1.0) -> trimesh.Trimesh:
    """The triangles of the file `path` (a multi-part file concatenated),
    scaled by `scale` (a number, or one per axis): a copy of its own."""
    try:
        stat = Path(path).stat()
    except OSError as error:
        raise MeshError(f"mesh file {str(path)!r} cannot be read: {error.strerror}") from None
    check_regular(path, "mesh file", MeshError, MAX_BYTES)
    mesh = _read(str(Path(path).resolve()), stat.st_mtime_ns, stat.st_size)
    factors = np.broadcast_to(np.asarray(scale, dtype=float), (3,))
    return mesh.copy().apply_transform(np.diag([*factors, 1.0]))


@functools.lru_cache(maxsize=64)
def _read(path: str, mtime_ns: int, size: int) -> trimesh.Trimesh:
    """The file's mesh, as read; keyed by the version of the file (never
    handed out: `load_mesh` copies it)."""
    import trimesh  # only scenes with meshes, and the ompl-fcl planner, need it

    try:
        mesh = trimesh.load(path, force="mesh")
    except Exception as error:  # noqa: BLE001 - trimesh's readers raise whatever their parser hits
        raise MeshError(f"mesh file {path!r} cannot be read by trimesh: {type(error).__name__}: {error}") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise MeshError(f"mesh file {path!r} has no triangles")
    return mesh
