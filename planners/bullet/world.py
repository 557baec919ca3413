"""One scene in a private pybullet client, and what the robot touches at
one configuration in one mode.

Bodies: the robot; one per static obstacle; per place (location of interest
or Else sample), one per *distinct* object shape, standing at the place's
pose and owned by the objects of that shape; one per distinct shape for the
held object.  A mode switches bodies on and off through their collision
groups (`bodies.py`): in mode `o/g` a place body counts only if an object
other than `o` owns it (the location obstacle is every shape but the held
one), and o's held body follows the hand at T_ee @ inverse(grasp.pose).

The held object is never compared with the end-effector link or the links
below it (the fingers hold it); against the rest of the robot it is a
static collision like any other.  A contact counts when pybullet reports a
negative distance (penetration); touching is not a collision.
"""

from __future__ import annotations

from symsynth import bullet

from symsynth.planning.protocol import Config, Contacts, Mode, PlannerError
from symsynth.scene.geometry import Geometry, Shape

from symsynth_planners.bullet.bodies import HELD, OFF, PARKED, PLACE, STATIC, make_body, set_group
from symsynth_planners.bullet.robot import RobotBody


class World:
    def __init__(self, geometry: Geometry) -> None:
        self.geometry = geometry
        self.client = bullet.client()
        self.robot = RobotBody(self.client, geometry.robot)
        self.static = {make_body(self.client, body.shape, body.pose, STATIC, concave=True): body.name
                       for body in geometry.obstacles}
        shapes: dict[Shape, list[str]] = {}
        for name, shape in geometry.shapes.items():
            shapes.setdefault(shape, []).append(name)
        self.place_bodies: list[tuple[int, frozenset[str]]] = []  # (body, owners)
        self.place_of: dict[int, str] = {}
        for place, pose in geometry.places.items():
            for shape, owners in shapes.items():
                body = make_body(self.client, shape, pose, PLACE)
                self.place_bodies.append((body, frozenset(owners)))
                self.place_of[body] = place
        self.held_body: dict[str, int] = {}
        for shape, owners in shapes.items():
            body = make_body(self.client, shape, None, OFF)
            for link in self.robot.hand:
                self.client.setCollisionFilterPair(body, self.robot.id, -1, link, 0)
            self.held_body.update((name, body) for name in owners)
        self.mode: tuple | None = None
        self.held: int | None = None
        self.offset: tuple[tuple[float, float, float], tuple[float, float, float, float]] | None = None

    def set_mode(self, mode: Mode, places: bool = True) -> None:
        """Switch bodies on and off for `mode`; `places=False` leaves every
        place body out (static checks only)."""
        if (mode, places) == self.mode:
            return
        grasp = mode.grasp
        if mode.object is not None:
            if mode.object not in self.held_body:
                raise PlannerError(f"mode {mode}: no object {mode.object!r} in the scene "
                                   f"(objects: {', '.join(sorted(self.held_body))})")
            if grasp is None or grasp not in self.geometry.hand_frames:
                raise PlannerError(f"mode {mode}: no grasp {mode.grasp!r} in the scene "
                                   f"(grasps and contacts: {', '.join(sorted(self.geometry.hand_frames))})")
        for body, owners in self.place_bodies:
            on = places and bool(owners - {mode.object})
            set_group(self.client, body, -1, PLACE if on else OFF)
        if self.held is not None:
            set_group(self.client, self.held, -1, OFF)
            self.client.resetBasePositionAndOrientation(self.held, *PARKED)
            self.held = None
        if mode.object is not None and grasp is not None:  # both are, or the checks above failed
            self.held = self.held_body[mode.object]
            shape = self.geometry.shapes[mode.object]
            offset = self.geometry.hand_frame(grasp).pose.inverse() @ shape.centre_offset()
            self.offset = (offset.xyz, offset.quat)
            set_group(self.client, self.held, -1, HELD)
        self.mode = (mode, places)

    def set_config(self, config: Config) -> None:
        self.robot.set(config)
        if self.held is not None and self.offset is not None:  # set with the held body
            position, quat = self.robot.ee_pose()
            position, quat = self.client.multiplyTransforms(position, quat, *self.offset)
            self.client.resetBasePositionAndOrientation(self.held, position, quat)

    def touching(self) -> Contacts:
        """The contacts at the current mode and configuration."""
        self.client.performCollisionDetection()
        static = False
        locations = set()
        for point in self.client.getContactPoints():
            if point[8] >= 0.0:
                continue
            place = self.place_of.get(point[1]) or self.place_of.get(point[2])
            if place is None:
                static = True  # self, static obstacle, or the held object against the arm
            else:
                locations.add(place)
        return Contacts(static, frozenset(locations))
