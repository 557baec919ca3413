"""The physical part of a scene (issue 4): poses, shapes, the robot.

Only planners and the simulator read it; the game sees `Scene` alone.
Conventions, fixed here once:

* Poses are a position in metres and a quaternion `(x, y, z, w)`, in the
  world frame unless said otherwise.
* An object's frame is the centre of its bottom face; a location's pose is
  where that frame sits when an object stands there.  Objects of different
  heights therefore all stand on the table at the same location pose.
* A grasp is the pose of the robot's end-effector link in the object's frame.
  Its *pre-image* (the anchor `x/g`) is that pose moved back by `approach`
  metres along the end-effector's z axis (the direction it closes in).
* Every object shares the grasps: the anchor `x/g` does not depend on which
  object stands at `x` (semantics §5 has one anchor per place and grasp).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]  # x, y, z, w


def vec3(values: Iterable[float]) -> Vec3:
    """Three numbers as a `Vec3` of floats (a ValueError if not three)."""
    x, y, z = values
    return float(x), float(y), float(z)


@dataclass(frozen=True)
class Pose:
    xyz: Vec3 = (0.0, 0.0, 0.0)
    quat: Quat = (0.0, 0.0, 0.0, 1.0)

    @staticmethod
    def from_rpy(xyz: Vec3, rpy: Vec3) -> Pose:
        """Roll, pitch, yaw in radians (extrinsic x, y, z: URDF's convention)."""
        r, p, y = (a / 2 for a in rpy)
        cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
        quat = (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
                cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)
        return Pose(vec3(xyz), quat)

    @staticmethod
    def from_matrix(matrix: np.ndarray) -> Pose:
        m = np.asarray(matrix, dtype=float)
        x, y, z, w = (float(v) for v in _quat_of(m[:3, :3]))
        return Pose(vec3(m[:3, 3]), (x, y, z, w))

    def matrix(self) -> np.ndarray:
        """The 4x4 homogeneous transform."""
        x, y, z, w = self.quat
        n = math.sqrt(x * x + y * y + z * z + w * w)
        x, y, z, w = x / n, y / n, z / n, w / n
        m = np.eye(4)
        m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        m[:3, 3] = self.xyz
        return m

    def __matmul__(self, other: Pose) -> Pose:
        """Composition: `a @ b` is b expressed in a's parent frame."""
        return Pose.from_matrix(self.matrix() @ other.matrix())

    def inverse(self) -> Pose:
        return Pose.from_matrix(np.linalg.inv(self.matrix()))

    def angle_to(self, other: Pose) -> float:
        """The angle of the rotation between the two orientations, radians in [0, pi]."""
        na, nb = math.sqrt(sum(v * v for v in self.quat)), math.sqrt(sum(v * v for v in other.quat))
        dot = abs(sum(x * y for x, y in zip(self.quat, other.quat))) / (na * nb)
        return 2 * math.acos(min(1.0, dot))


def point_text(xyz: Sequence[float]) -> str:
    """A point for messages: "(x, y, z)" in metres, to the millimetre (also
    a configuration, in radians)."""
    return "(" + ", ".join(f"{v:.3f}" for v in xyz) + ")"


def _quat_of(r: np.ndarray) -> Quat:
    trace = r[0, 0] + r[1, 1] + r[2, 2]
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        return ((r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, s / 4)
    i = int(np.argmax([r[0, 0], r[1, 1], r[2, 2]]))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2 * math.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
    q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
    q[i], q[j], q[k] = s / 4, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    return (q[0], q[1], q[2], q[3])


@dataclass(frozen=True)
class Shape:
    """A box (`size`: full extents), a cylinder (`radius`, `height`) or a mesh
    file (`mesh`, `scale`).  Boxes and cylinders have their frame at the
    centre of the bottom face; a mesh is used as authored."""

    kind: str  # "box" | "cylinder" | "mesh"
    size: Vec3 = (0.0, 0.0, 0.0)
    radius: float = 0.0
    height: float = 0.0
    mesh: Path | None = None
    scale: float = 1.0

    def centre_offset(self) -> Pose:
        """The geometric centre in the shape's own frame (primitives are
        built centred, then lifted by this)."""
        if self.kind == "box":
            return Pose((0.0, 0.0, self.size[2] / 2))
        if self.kind == "cylinder":
            return Pose((0.0, 0.0, self.height / 2))
        return Pose()


@dataclass(frozen=True)
class Body:
    """A static obstacle."""

    name: str
    shape: Shape
    pose: Pose


@dataclass(frozen=True)
class Robot:
    urdf: Path  # resolved: absolute
    base: Pose
    home: tuple[float, ...]  # one value per controlled joint
    ee_link: str
    joints: tuple[str, ...] = ()  # controlled joints; () = every movable joint but the fixed ones
    fixed: tuple[tuple[str, float], ...] = ()  # joints held at a value (e.g. open fingers)
    #: The widest an object may be, across the fingers (the hand's y axis),
    #: for the hand to close on it; None: not checked.
    opening: float | None = None


@dataclass(frozen=True)
class Grasp:
    name: str
    pose: Pose  # end-effector link in the object's frame
    approach: float = 0.05  # metres, back along the end-effector's z axis
    #: Places where this grasp or contact has no anchor by the scene's
    #: declaration (`absent_at`: semantics §5's absent anchors).  Left out
    #: of the repr, which cache keys read: `cache.cache_key` adds it itself.
    absent_at: frozenset[str] = field(default=frozenset(), repr=False)

    def pre_image(self) -> Pose:
        """End-effector pose of the anchor, in the object's frame."""
        return self.pose @ Pose((0.0, 0.0, -self.approach))


@dataclass(frozen=True)
class Contact(Grasp):
    """A contact (semantics §1, v2): a pose of the end-effector relative to
    the object, reached like a grasp's through its pre-image, from which the
    displacement primitive `primitive` slides the object; the hand never
    closes."""

    primitive: str = ""


@dataclass(frozen=True)
class Material:
    """What the physical world needs of a body beyond its shape (a scene's
    `physics:` block); None: the physical world's default."""

    mass: float | None = None  # kg (objects only: obstacles are static)
    friction: float | None = None  # Coulomb coefficient


@dataclass(frozen=True)
class PlannerSettings:
    name: str = "ompl-fcl"
    roadmap_size: int = 300  # vertices per mode, anchors not counted
    seconds: float | None = None  # a time limit per roadmap instead of a size
    check_step: float = 0.05  # radians between collision checks along a segment (YAML: check_step)
    seed: int = 0


@dataclass(frozen=True)
class Geometry:
    """Everything a planner needs beyond the abstract scene."""

    robot: Robot
    obstacles: tuple[Body, ...]
    shapes: dict[str, Shape]  # object name -> shape
    places: dict[str, Pose]  # locations of interest and Else samples -> pose
    grasps: dict[str, Grasp]
    initial: dict[str, Pose] = field(default_factory=dict)  # objects at Else -> pose
    per_radian: float = 1.0
    planner: PlannerSettings = PlannerSettings()
    contacts: dict[str, Contact] = field(default_factory=dict)
    #: Fixed costs of displacement primitives set by the scene (`costs: {push: 2}`).
    primitive_costs: dict[str, float] = field(default_factory=dict)
    #: Materials of objects and obstacles by name (`physics:` blocks); only the
    #: physical simulator reads them, so they stay out of the repr (cache keys read it).
    materials: dict[str, Material] = field(default_factory=dict, repr=False)

    def hand_frame(self, name: str) -> Grasp:
        """The grasp or contact `name`: where the end-effector stands on an
        object (a slide carries the object in its contact's frame)."""
        return self.grasps[name] if name in self.grasps else self.contacts[name]

    def across_fingers(self, obj: str, grasp: str) -> float | None:
        """Object `obj`'s extent along the hand's y axis (the fingers'
        closing direction) held with `grasp`; None for a mesh."""
        across = self.grasps[grasp].pose.matrix()[:3, 1]
        shape = self.shapes[obj]
        if shape.kind == "box":
            return float(np.abs(across) @ np.asarray(shape.size))
        if shape.kind == "cylinder":
            return 2 * shape.radius * math.hypot(across[0], across[1]) + shape.height * abs(float(across[2]))
        return None

    @property
    def hand_frames(self) -> dict[str, Grasp]:
        return {**self.grasps, **self.contacts}

    @property
    def absent(self) -> frozenset[str]:
        """The anchors `x/a` the scene declares absent (`absent_at` of its
        grasps and contacts): no robot configuration, semantics §5."""
        return frozenset(f"{x}/{a}" for a, frame in self.hand_frames.items() for x in frame.absent_at)
