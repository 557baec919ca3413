"""The simulated world: the scene in a PyBullet client, objects where they
really are.

This is ground truth for the simulator, independent of the planner that
made the costmap: the robot is loaded from its URDF with visual and
collision geometry, the static obstacles and the objects are bodies of
their shapes, and every place is marked on the table by a thin square
(visual only; green for a location of interest, orange for an Else sample).

The simulation is kinematic: configurations are set, not integrated, and
an object stands exactly where it was put (a block set down on top of two
columns rests there; a block put where nothing holds it up floats).  A
held object is rigidly attached to the end-effector link at the grasp's
transform, the kinematic form of a fixed constraint.

`touching` reports penetration deeper than `PENETRATION` metres between
the robot or the held object and anything else (objects, obstacles);
touching is not a collision, as for the planners.  The robot's root link
stands on the table and is never compared with the obstacles.
Self-collision is the planner's question (`Planner.contacts`), asked by
the simulator when it plans at run time.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from symsynth import bullet
from symsynth.errors import SymsynthError
from symsynth.scene.geometry import Pose, Shape
from symsynth.scene.model import ELSE, Scene

RGBA = tuple[float, float, float, float]
COLOURS: dict[str, RGBA] = {
    "white": (0.95, 0.95, 0.95, 1), "black": (0.12, 0.12, 0.12, 1), "red": (0.85, 0.15, 0.15, 1),
    "green": (0.2, 0.7, 0.25, 1), "blue": (0.2, 0.35, 0.85, 1), "yellow": (0.95, 0.85, 0.2, 1),
    "orange": (0.95, 0.55, 0.1, 1), "purple": (0.55, 0.25, 0.7, 1), "grey": (0.5, 0.5, 0.5, 1),
    "gray": (0.5, 0.5, 0.5, 1), "brown": (0.55, 0.35, 0.2, 1), "pink": (0.95, 0.55, 0.7, 1),
}
PALETTE: tuple[RGBA, ...] = ((0.25, 0.45, 0.85, 1), (0.85, 0.3, 0.3, 1), (0.9, 0.75, 0.2, 1),
                             (0.55, 0.3, 0.7, 1), (0.3, 0.7, 0.7, 1))
OBSTACLE: RGBA = (0.62, 0.6, 0.57, 1)
LOCATION_MARK: RGBA = (0.1, 0.75, 0.2, 1)
ELSE_MARK: RGBA = (0.95, 0.5, 0.05, 1)
MARK_SIZE = 0.07  # metres, side of a place's square
MARK_THICKNESS = 0.002
PENETRATION = 1e-3  # metres: shallower contacts are touching, not colliding


class SimWorld:
    """One scene in a private PyBullet client (`gui=True`: a window)."""

    def __init__(self, scene: Scene, *, gui: bool = False) -> None:
        geometry = scene.geometry
        if geometry is None:
            raise SymsynthError(f"scene {scene.name!r} has no geometry (not a physical scene)")
        self.scene = scene
        self.geometry = geometry
        self.client = bullet.client(gui=gui)
        loaded = bullet.load_robot(self.client, geometry.robot)
        self.robot = loaded.id
        self.joints = list(loaded.joints)
        self.ee_link = loaded.ee
        self.obstacles = {self._body(body.shape, body.pose, OBSTACLE, concave=True): body.name
                          for body in geometry.obstacles}
        self.bodies: dict[str, int] = {}
        self.poses: dict[str, Pose] = {}
        for k, spec in enumerate(scene.objects):
            pose = self._initial_pose(spec.name, spec.at)
            self.bodies[spec.name] = self._body(geometry.shapes[spec.name], pose, colour_of(spec.tags, k),
                                                mass=self.mass(spec.name))
            self.poses[spec.name] = pose
        mark = Shape("box", size=(MARK_SIZE, MARK_SIZE, MARK_THICKNESS))
        for name, pose in geometry.places.items():
            colour = LOCATION_MARK if name in scene.locations else ELSE_MARK
            self._body(mark, pose @ Pose((0.0, 0.0, 0.0005)), colour, collision=False)
        self.held: str | None = None
        self.grasp: str | None = None
        self._in_hand = self._centre = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))  # (xyz, quat), set by attach
        self.config: tuple[float, ...] = ()
        self.set_config(geometry.robot.home)

    def close(self) -> None:
        self.client.disconnect()

    def mass(self, name: str) -> float:
        """Object `name`'s mass in kg: 0 in the kinematic world (a body
        PyBullet never moves); the physical world's (`physics.py`) weighs."""
        return 0.0

    # -- the robot ------------------------------------------------------------

    def set_config(self, config: Sequence[float]) -> None:
        config = tuple(float(v) for v in config)
        if len(config) != len(self.joints):
            raise SymsynthError(f"a configuration has {len(config)} values; the robot has "
                                f"{len(self.joints)} controlled joints")
        self.client.resetJointStatesMultiDof(self.robot, self.joints, [[v] for v in config])
        self.config = config
        if self.held is not None:  # pybullet's transform product: Pose's (numpy) cost more than the rest
            ee = self.ee_pose()
            xyz, quat = self.client.multiplyTransforms(ee.xyz, ee.quat, *self._in_hand)
            self.poses[self.held] = Pose(tuple(xyz), tuple(quat))
            centre = self.client.multiplyTransforms(xyz, quat, *self._centre)
            self.client.resetBasePositionAndOrientation(self.bodies[self.held], *centre)

    def ee_pose(self) -> Pose:
        """The end-effector link frame (the URDF frame) in the world."""
        state = self.client.getLinkState(self.robot, self.ee_link, computeForwardKinematics=True)
        return Pose(tuple(state[4]), tuple(state[5]))

    # -- the objects ----------------------------------------------------------

    def place(self, name: str, pose: Pose) -> None:
        """Put object `name` at `pose` (the human's hand, or a drop)."""
        if name == self.held:
            raise SymsynthError(f"{name} is in the robot's hand")
        self._place_body(name, pose)

    def attach(self, name: str, grasp: str) -> None:
        self.held, self.grasp = name, grasp
        in_hand = self.geometry.hand_frame(grasp).pose.inverse()  # the object's frame in the hand's
        centre = self.geometry.shapes[name].centre_offset()
        self._in_hand = (in_hand.xyz, in_hand.quat)
        self._centre = (centre.xyz, centre.quat)
        self.set_config(self.config)

    def detach(self) -> None:
        self.held, self.grasp = None, None

    def blocked(self, name: str, pose: Pose) -> set[str]:
        """What object `name` would penetrate at `pose`: other objects, the
        robot (`robot`) or obstacles.  The object goes back where it was."""
        before = self.poses[name]
        self._place_body(name, pose)
        hits = self._hits(self.bodies[name], ignore={name})
        self._place_body(name, before)
        return hits

    def stands(self, name: str, pose: Pose) -> bool:
        """Whether object `name`, let go at `pose`, stays there: in the
        kinematic world, always (nothing falls)."""
        return True

    def touching(self, ignore: Iterable[str] = (), *, obstacles: bool = True) -> set[str]:
        """What the robot and the held object penetrate at the current
        configuration: object names, obstacle names; `ignore` leaves
        objects out (the one the fingers close around), `obstacles=False`
        the static obstacles (for a caller that asks the planner about them)."""
        ignore = set(ignore) | ({self.held} if self.held else set())
        found = set()
        for name, body in self.bodies.items():
            if name not in ignore and self._penetrates(self.robot, body):
                found.add(name)
        for body, name in self.obstacles.items() if obstacles else ():
            if any(c[3] != -1 and c[8] < -PENETRATION
                   for c in self.client.getClosestPoints(self.robot, body, 0.0)):
                found.add(name)
        if self.held is not None:
            found |= self._hits(self.bodies[self.held], ignore=ignore, robot=False, obstacles=obstacles)
        return found

    # -- helpers --------------------------------------------------------------

    def _initial_pose(self, name: str, at: str) -> Pose:
        """A location's pose, the object's own Else pose, or else the first
        Else sample no other object stands on."""
        geometry = self.geometry
        if at != ELSE:
            return geometry.places[at]
        if name in geometry.initial:
            return geometry.initial[name]
        taken = set(self.poses.values()) | {geometry.initial[o.name] for o in self.scene.objects
                                             if o.name in geometry.initial}
        for sample in self.scene.else_samples:
            if geometry.places[sample] not in taken:
                return geometry.places[sample]
        raise SymsynthError(f"object {name!r} starts at {ELSE} without a pose, and every Else sample "
                            "is taken: give it one (xyz)")

    def _hits(self, body: int, ignore: set[str], robot: bool = True, obstacles: bool = True) -> set[str]:
        found = {name for name, other in self.bodies.items()
                 if name not in ignore and other != body and self._penetrates(body, other)}
        if obstacles:
            found |= {name for other, name in self.obstacles.items() if self._penetrates(body, other)}
        if robot and self._penetrates(body, self.robot):
            found.add("robot")
        return found

    def _penetrates(self, a: int, b: int) -> bool:
        return any(c[8] < -PENETRATION for c in self.client.getClosestPoints(a, b, 0.0))

    def _place_body(self, name: str, pose: Pose) -> None:
        self.poses[name] = pose
        centre = pose @ self.geometry.shapes[name].centre_offset()
        self.client.resetBasePositionAndOrientation(self.bodies[name], centre.xyz, centre.quat)

    def _body(self, shape: Shape, pose: Pose, colour: RGBA, *, collision: bool = True,
              concave: bool = False, mass: float = 0.0) -> int:
        solid = bullet.collision_shape(self.client, shape, concave=concave) if collision else -1
        centre = pose @ shape.centre_offset()
        return self.client.createMultiBody(baseMass=mass, baseCollisionShapeIndex=solid,
                                           baseVisualShapeIndex=bullet.visual_shape(self.client, shape, colour),
                                           basePosition=centre.xyz, baseOrientation=centre.quat)


def colour_of(tags: frozenset[str], index: int) -> RGBA:
    """An object's colour: its first tag (sorted) that names one, else the
    palette's colour for its index."""
    for tag in sorted(tags):
        if tag in COLOURS:
            return COLOURS[tag]
    return PALETTE[index % len(PALETTE)]
