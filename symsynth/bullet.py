"""PyBullet, without its chatter on standard output.

PyBullet's C code prints "pybullet build time: ..." when imported and
"argv[0]=" when a client connects, straight to file descriptors 2 and 1
(where `--json` output goes).  `client()` opens a private DIRECT-mode client with
that descriptor pointed at /dev/null for the moment it takes.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections.abc import Iterator

from symsynth.errors import SymsynthError
from symsynth.scene.geometry import Shape


_libc = ctypes.CDLL(None)


@contextlib.contextmanager
def _silenced_stdout() -> Iterator[None]:
    """File descriptors 1 and 2 to /dev/null for a moment."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    try:
        with open(os.devnull, "wb") as devnull:
            os.dup2(devnull.fileno(), 1)
            os.dup2(devnull.fileno(), 2)
        yield
    finally:
        _libc.fflush(None)  # C stdio buffers what it printed: drop it while 1 and 2 are /dev/null
        for fd, copy in zip((1, 2), saved):
            os.dup2(copy, fd)
            os.close(copy)


with _silenced_stdout():
    import pybullet  # noqa: E402  (the import prints its build time)
    from pybullet_utils import bullet_client  # noqa: E402


def client(gui: bool = False) -> bullet_client.BulletClient:
    """A new PyBullet client of its own: headless, or with a window
    (`gui=True`, which needs a display)."""
    if gui:
        if not os.environ.get("DISPLAY") and sys.platform.startswith("linux"):
            raise SymsynthError("a window needs a display, and DISPLAY is not set; "
                                "leave --gui out (the simulation runs headless)")
        return bullet_client.BulletClient(connection_mode=pybullet.GUI)
    with _silenced_stdout():
        return bullet_client.BulletClient(connection_mode=pybullet.DIRECT)


# -- symsynth shapes as PyBullet shapes (frames as pybullet wants: centred) -------------

def collision_shape(client, shape: Shape, *, concave: bool = False) -> int:
    """A pybullet collision shape id for `shape`, centred as pybullet wants."""
    if shape.kind == "box":
        return client.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[s / 2 for s in shape.size])
    if shape.kind == "cylinder":
        return client.createCollisionShape(pybullet.GEOM_CYLINDER, radius=shape.radius, height=shape.height)
    if shape.kind == "mesh" and shape.mesh is not None:
        flags = pybullet.GEOM_FORCE_CONCAVE_TRIMESH if concave else 0
        shape_id = client.createCollisionShape(pybullet.GEOM_MESH, fileName=str(shape.mesh),
                                               meshScale=[shape.scale] * 3, flags=flags)
        if shape_id < 0:
            raise SymsynthError(f"pybullet could not load the mesh {shape.mesh}")
        return shape_id
    raise SymsynthError(f"unknown shape kind {shape.kind!r} (expected box, cylinder or mesh)")


def visual_shape(client, shape: Shape, colour: tuple[float, float, float, float]) -> int:
    """A pybullet visual shape id for `shape` in `colour` (RGBA), centred."""
    if shape.kind == "box":
        return client.createVisualShape(pybullet.GEOM_BOX, halfExtents=[s / 2 for s in shape.size],
                                        rgbaColor=colour)
    if shape.kind == "cylinder":
        return client.createVisualShape(pybullet.GEOM_CYLINDER, radius=shape.radius, length=shape.height,
                                        rgbaColor=colour)
    return client.createVisualShape(pybullet.GEOM_MESH, fileName=str(shape.mesh),
                                    meshScale=[shape.scale] * 3, rgbaColor=colour)
