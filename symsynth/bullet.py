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
from collections.abc import Callable, Iterator
from pathlib import Path
from dataclasses import dataclass

from symsynth.errors import SymsynthError
from symsynth.scene.geometry import Robot, Shape


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


def check_display(gui: bool) -> None:
    """Fail if a window is asked for and there is no display to show it on
    (callers check before long work, not only when the window opens)."""
    if gui and not os.environ.get("DISPLAY") and sys.platform.startswith("linux"):
        raise SymsynthError("a window needs a display, and DISPLAY is not set; "
                            "leave --gui out (the simulation runs headless)")


def client(gui: bool = False) -> bullet_client.BulletClient:
    """A new PyBullet client of its own: headless, or with a window
    (`gui=True`, which needs a display)."""
    if gui:
        check_display(gui)
        return bullet_client.BulletClient(connection_mode=pybullet.GUI)
    with _silenced_stdout():
        return bullet_client.BulletClient(connection_mode=pybullet.DIRECT)


# -- symsynth shapes as PyBullet shapes (frames as pybullet wants: centred) -------------

#: The mesh files pybullet's shapes read, by extension (trimesh reads more, .ply
#: and .glb among them: pybullet refuses those collision shapes, and makes an
#: empty visual shape of them without a word).
MESH_SUFFIXES = (".obj", ".stl")


def collision_shape(client, shape: Shape, *, concave: bool = False) -> int:
    """A pybullet collision shape id for `shape`, centred as pybullet wants."""
    if shape.kind == "box":
        return client.createCollisionShape(pybullet.GEOM_BOX, halfExtents=[s / 2 for s in shape.size])
    if shape.kind == "cylinder":
        return client.createCollisionShape(pybullet.GEOM_CYLINDER, radius=shape.radius, height=shape.height)
    if shape.kind == "mesh" and shape.mesh is not None:
        flags = pybullet.GEOM_FORCE_CONCAVE_TRIMESH if concave else 0
        path = shape.mesh
        return _mesh(path, lambda: client.createCollisionShape(pybullet.GEOM_MESH, fileName=str(path),
                                                               meshScale=[shape.scale] * 3, flags=flags))
    raise SymsynthError(f"unknown shape kind {shape.kind!r} (expected box, cylinder or mesh)")


def visual_shape(client, shape: Shape, colour: tuple[float, float, float, float]) -> int:
    """A pybullet visual shape id for `shape` in `colour` (RGBA), centred."""
    if shape.kind == "box":
        return client.createVisualShape(pybullet.GEOM_BOX, halfExtents=[s / 2 for s in shape.size],
                                        rgbaColor=colour)
    if shape.kind == "cylinder":
        return client.createVisualShape(pybullet.GEOM_CYLINDER, radius=shape.radius, length=shape.height,
                                        rgbaColor=colour)
    if shape.kind == "mesh" and shape.mesh is not None:
        path = shape.mesh
        return _mesh(path, lambda: client.createVisualShape(pybullet.GEOM_MESH, fileName=str(path),
                                                            meshScale=[shape.scale] * 3, rgbaColor=colour))
    raise SymsynthError(f"unknown shape kind {shape.kind!r} (expected box, cylinder or mesh)")


def _mesh(path: Path, create: Callable[[], int]) -> int:
    """`create()`, a pybullet shape of the mesh file `path`; a file
    pybullet cannot read is a `SymsynthError` naming it (pybullet raises
    its own bare "createCollisionShape failed.")."""
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise SymsynthError(f"pybullet cannot read the mesh {path}: it reads {' and '.join(MESH_SUFFIXES)} "
                            "files only; convert it (trimesh.load(file).export('mesh.obj'))")
    try:
        return create()
    except pybullet.error as problem:
        raise SymsynthError(f"pybullet could not load the mesh {path}: {problem}") from None


# -- the robot ---------------------------------------------------------------------

@dataclass(frozen=True)
class RobotJoints:
    """A robot loaded from its URDF: the body and how its joints are addressed."""

    id: int  # the pybullet body
    infos: tuple  # getJointInfo of every joint, by joint index
    joints: tuple[int, ...]  # the controlled joints, in the order of a configuration
    movable: tuple[int, ...]  # every joint that is not fixed (pybullet's inverse kinematics order)
    held: dict[int, float]  # the other movable joints, set to these values and kept there
    ee: int  # the end-effector link (-1: the base)

    @property
    def parents(self) -> dict[int, int]:
        """link -> its parent link (the base, -1, has none)."""
        return {j: info[16] for j, info in enumerate(self.infos)}


def load_robot(client, robot: Robot, *, flags: int = 0,
               error: type[SymsynthError] = SymsynthError) -> RobotJoints:
    """Load `robot` (fixed base at its pose) into `client` with the URDF `flags`.

    The controlled joints are the scene's `joints`, or else every movable
    joint not named in `fixed`; the fixed ones are set to their value and
    every other movable joint to 0.  Problems raise `error` naming the URDF.
    """
    try:
        body = client.loadURDF(str(robot.urdf), basePosition=robot.base.xyz,
                               baseOrientation=robot.base.quat, useFixedBase=True, flags=flags)
    except pybullet.error as problem:  # it raises rather than return -1
        raise error(f"pybullet could not load the robot URDF {robot.urdf}: {problem}") from None
    infos = tuple(client.getJointInfo(body, j) for j in range(client.getNumJoints(body)))
    joint_index = {info[1].decode(): j for j, info in enumerate(infos)}
    link_index = {info[12].decode(): j for j, info in enumerate(infos)}
    link_index[client.getBodyInfo(body)[0].decode()] = -1
    movable = tuple(j for j, info in enumerate(infos) if info[2] != pybullet.JOINT_FIXED)
    fixed = dict(robot.fixed)
    names = robot.joints or tuple(infos[j][1].decode() for j in movable
                                  if infos[j][1].decode() not in fixed)
    for name in list(names) + list(fixed):
        if joint_index.get(name) not in movable:
            raise error(f"joint {name!r} is not a movable joint of {robot.urdf}")
    if robot.ee_link not in link_index:
        raise error(f"end-effector link {robot.ee_link!r} is not a link of {robot.urdf}")
    if len(robot.home) != len(names):
        raise error(f"home has {len(robot.home)} values for {len(names)} joints ({', '.join(names)})")
    joints = tuple(joint_index[n] for n in names)
    held = {joint_index[n]: float(v) for n, v in fixed.items()}
    for j in movable:
        if j not in joints and j not in held:
            held[j] = 0.0
    for j, value in held.items():
        client.resetJointState(body, j, value)
    return RobotJoints(body, infos, joints, movable, held, link_index[robot.ee_link])
