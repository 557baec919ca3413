"""What a configuration touches, checked with python-fcl.

Three kinds of solid: *movers* (the robot's link hulls, placed by forward
kinematics, and in a holding mode the held object), *static* obstacles, and
*location* obstacles (at each place, one solid per distinct shape of the
objects but the held one: objects of one shape touch the same things).
For a batch of configurations the movers are placed in numpy, pairs are
culled by their oriented bounding boxes (`bounds`), and fcl's narrow phase
runs on the surviving pairs only, one configuration after another.

Pairs never checked (each a fixed property of the robot or the grasp, not of
a motion):
* solids of the same link, and of adjacent links
  (`symsynth.planning.adjacent`: a link and the nearest ancestor that has
  collision geometry; for the Panda, `hand` and `link7` are adjacent
  through the geometry-less `link8`);
* link pairs that touch at the home configuration (`home_contacts`; none
  for the Panda at its usual home);
* the root link against static and location obstacles: it is fixed to the
  world, so a contact there (the Panda's base standing on the table top) is
  the scene's, never the motion's;
* the held object against the end-effector link and the links below it
  (the hand and fingers holding it).
"""

from __future__ import annotations

from dataclasses import dataclass

import fcl
import numpy as np

from symsynth.planning.adjacent import adjacent_pairs
from symsynth.planning.protocol import Config, Contacts, Mode, PlannerError
from symsynth.scene.geometry import Geometry

from .bounds import axes_overlap
from .kinematics import Kinematics
from .shapes import Solid, link_solids, scene_solid

CHUNK = 256  # configurations placed and culled together (a whole segment, usually)
SELF, STATIC, PLACE = 0, 1, 2  # kinds of candidate pair, in the order they are checked


@dataclass(frozen=True)
class _Placed:
    """Solids at fixed world poses: fcl objects, bounding boxes, and a tag
    each (the obstacle's name, or the place a location solid stands at)."""

    objects: list[fcl.CollisionObject]
    boxes: np.ndarray  # (n, 4, 4) world poses of the bounding boxes
    halves: np.ndarray  # (n, 3)
    tags: list[str]

    @staticmethod
    def of(items: list[tuple[str, Solid, np.ndarray]]) -> _Placed:
        poses = [pose @ solid.offset for _, solid, pose in items]
        return _Placed(
            objects=[fcl.CollisionObject(s.geometry, _transform(p)) for (_, s, _), p in zip(items, poses)],
            boxes=np.array([p @ s.box for (_, s, _), p in zip(items, poses)]).reshape(-1, 4, 4),
            halves=np.array([s.half for _, s, _ in items]).reshape(-1, 3),
            tags=[tag for tag, _, _ in items])

    @staticmethod
    def concatenate(a: _Placed, b: _Placed) -> _Placed:
        return _Placed(a.objects + b.objects, np.concatenate([a.boxes, b.boxes]),
                       np.concatenate([a.halves, b.halves]), a.tags + b.tags)


@dataclass(frozen=True)
class _Table:
    """Candidate pairs as rows (kind, first, second): `first` a mover,
    `second` a mover or (numbered after the movers) a fixed solid; with
    each row's bounding-box half extents and the square of the sum of its
    two bounding spheres' radii (the first, cheapest cull)."""

    rows: list[tuple[int, int, int]]
    first: np.ndarray
    second: np.ndarray
    fixed: _Placed
    half_first: np.ndarray  # (rows, 3)
    half_second: np.ndarray  # (rows, 3)
    reach2: np.ndarray  # (rows,)


@dataclass(frozen=True)
class _Held:
    solid: Solid
    in_hand: np.ndarray  # the object's frame in the end-effector link's frame
    object: fcl.CollisionObject


class CollisionWorld:
    """The robot, the static obstacles and the location obstacles of one scene."""

    def __init__(self, kinematics: Kinematics, geometry: Geometry):
        self.kinematics, self.geometry = kinematics, geometry
        self.solids: list[Solid] = []
        self.owner: list[str] = []  # the link of each robot solid
        for link in kinematics.links:
            for solid in link_solids(kinematics.urdf, kinematics.robot.urdf, link):
                self.solids.append(solid)
                self.owner.append(link)
        self.links = sorted(set(self.owner), key=kinematics.links.index)
        self.objects = [fcl.CollisionObject(s.geometry, fcl.Transform()) for s in self.solids]
        self.owner_index = np.array([kinematics.links.index(link) for link in self.owner], dtype=np.int64)
        self.offsets = np.array([s.offset for s in self.solids]).reshape(-1, 4, 4)  # in the link frame
        self.boxes = np.array([s.offset @ s.box for s in self.solids]).reshape(-1, 4, 4)  # in the link frame
        self.halves = np.array([s.half for s in self.solids]).reshape(-1, 3)
        self.ee_index = kinematics.links.index(kinematics.ee_link)

        self.static = _Placed.of([(body.name, scene_solid(body.shape), body.pose.matrix())
                                  for body in geometry.obstacles])
        self._shape_solids = {shape: scene_solid(shape) for shape in geometry.shapes.values()}  # one a shape
        self._locations: dict[str | None, _Placed] = {}
        self._held: dict[Mode, _Held] = {}
        self._tables: dict[tuple[Mode, bool, bool], _Table] = {}

        self.adjacent = {frozenset(pair) for pair in adjacent_pairs(self.links, kinematics.parent_link)}
        self.home_contacts = self._touching(kinematics.home, self._pairs(self.adjacent))
        self.self_pairs = self._pairs(self.adjacent | self.home_contacts)
        n = len(self.solids)  # the held object's index among the movers
        below_ee = {link for link in kinematics.links if self._below(link, kinematics.ee_link)}
        arm = [(k, n) for k, link in enumerate(self.owner) if link not in below_ee]
        self.held_pairs = np.vstack([self.self_pairs, np.array(arm, dtype=np.int64).reshape(-1, 2)])
        self.grounded = np.array([k for k, link in enumerate(self.owner) if link != kinematics.root],
                                 dtype=np.int64)
        self.grounded_held = np.append(self.grounded, n)

    # -- the robot's own pairs --------------------------------------------------------------------

    def _below(self, link: str | None, ancestor: str) -> bool:
        while link is not None and link != ancestor:
            link = self.kinematics.parent_link(link)
        return link == ancestor

    def _pairs(self, excluded: set[frozenset[str]]) -> np.ndarray:
        """Solid index pairs (i < j) of different links not in `excluded`."""
        n = len(self.solids)
        return np.array([(i, j) for i in range(n) for j in range(i + 1, n)
                         if self.owner[i] != self.owner[j]
                         and frozenset((self.owner[i], self.owner[j])) not in excluded],
                        dtype=np.int64).reshape(-1, 2)

    def _touching(self, config: Config | np.ndarray, pairs: np.ndarray) -> set[frozenset[str]]:
        movers = self._movers(np.asarray(config, dtype=float)[None], None)
        return {frozenset((self.owner[i], self.owner[j])) for i, j in pairs
                if fcl.collide(movers.object(i), movers.object(j))}

    # -- modes ------------------------------------------------------------------------------------

    def locations(self, held: str | None) -> _Placed:
        """Location solids: at every place, one per distinct shape of the
        objects but `held` (as the pybullet planner's place bodies)."""
        if held not in self._locations:
            shapes = dict.fromkeys(shape for name, shape in self.geometry.shapes.items() if name != held)
            self._locations[held] = _Placed.of([
                (place, self._shape_solids[shape], pose.matrix()) for place, pose in self.geometry.places.items()
                for shape in shapes])
        return self._locations[held]

    def held(self, mode: Mode) -> _Held | None:
        """The held object of a holding mode (None for the empty hand)."""
        if mode.object is None:
            return None
        if mode not in self._held:
            if mode.object not in self.geometry.shapes or mode.grasp not in self.geometry.hand_frames:
                raise PlannerError(
                    f"mode {mode}: objects are {', '.join(sorted(self.geometry.shapes))}, "
                    f"grasps and contacts are {', '.join(sorted(self.geometry.hand_frames))}")
            solid = self._shape_solids[self.geometry.shapes[mode.object]]
            in_hand = np.linalg.inv(self.geometry.hand_frame(mode.grasp).pose.matrix())
            self._held[mode] = _Held(solid, in_hand, fcl.CollisionObject(solid.geometry, fcl.Transform()))
        return self._held[mode]

    # -- queries ----------------------------------------------------------------------------------

    def contacts(self, mode: Mode, config: Config | np.ndarray, locations: bool = True) -> Contacts:
        """Self, static and (if asked) location contacts of the robot and the
        held object at `config`."""
        return self.sweep(mode, self.kinematics.check(config)[None], locations)

    def sweep(self, mode: Mode, configs: np.ndarray, locations: bool = True, static: bool = True) -> Contacts:
        """The union of `contacts` over `configs` (B, d), taken in order and
        stopped at the first static contact.  Forward kinematics and culling
        run on `CHUNK` configurations at once; only fcl's narrow phase stops
        early.  (Culling in small first batches, to spare the work after an
        early contact, was slower: numpy's cost per call is most of it.)

        `static=False` leaves out the self and static pairs: only for
        configurations already known free of them (a roadmap edge checked
        when the roadmap was built), where it gives the same answer."""
        configs = np.asarray(configs, dtype=float)
        touched: set[str] = set()
        for start in range(0, len(configs), CHUNK):
            if self._batch(mode, configs[start:start + CHUNK], locations, static, touched):
                return Contacts(True, frozenset(touched))
        return Contacts(False, frozenset(touched))

    def _batch(self, mode: Mode, configs: np.ndarray, locations: bool, static: bool, touched: set[str]) -> bool:
        """Adds the location contacts along `configs` to `touched`; true at the
        first static contact.  Pairs are culled by bounding spheres (centres
        only, for every row), then by the separating-axis test on the pairs
        the spheres let through; fcl's narrow phase runs on the rest, by
        configuration, then row."""
        table = self._table(mode, locations, static)
        if not table.rows:
            return False
        movers = self._movers(configs, self.held(mode))
        fixed = table.fixed
        boxes = np.concatenate([movers.boxes, np.broadcast_to(fixed.boxes, (len(configs), *fixed.boxes.shape))],
                               axis=1)  # (B, movers + fixed, 4, 4)
        centres = boxes[:, :, :3, 3]
        gap = centres[:, table.second] - centres[:, table.first]
        near_b, near_r = np.nonzero(np.einsum("brk,brk->br", gap, gap) <= table.reach2)
        hit = axes_overlap(boxes[near_b, table.first[near_r]], table.half_first[near_r],
                           boxes[near_b, table.second[near_r]], table.half_second[near_r])
        moving = len(movers.halves)
        current = -1
        for b, row in zip(near_b[hit].tolist(), near_r[hit].tolist()):  # by configuration, then row
            if b != current:
                movers.at(b)
                current = b
            kind, k, other = table.rows[row]
            if kind == SELF:
                if fcl.collide(movers.object(k), movers.object(other)):
                    return True
            elif kind == STATIC:
                if fcl.collide(movers.object(k), fixed.objects[other - moving]):
                    return True
            elif fixed.tags[other - moving] not in touched and \
                    fcl.collide(movers.object(k), fixed.objects[other - moving]):
                touched.add(fixed.tags[other - moving])
        return False

    def _table(self, mode: Mode, locations: bool, static: bool = True) -> _Table:
        """The candidate pairs of a mode: self pairs first, then static, then
        location pairs (self and static ones only if `static`); movers are
        numbered first, fixed solids after them."""
        key = (mode, locations, static)
        if key not in self._tables:
            held = self.held(mode)
            pairs = self.self_pairs if held is None else self.held_pairs
            grounded = (self.grounded if held is None else self.grounded_held).tolist()
            places = self.locations(mode.object) if locations else _Placed.of([])
            fixed = _Placed.concatenate(self.static, places)
            moving, statics = len(self.solids) + (held is not None), len(self.static.tags)
            rows = [(SELF, i, j) for i, j in pairs.tolist()] if static else []
            rows += [(STATIC if f < statics else PLACE, k, moving + f)
                     for f in range(len(fixed.tags)) for k in grounded if static or f >= statics]
            first = np.array([r[1] for r in rows], dtype=np.int64)
            second = np.array([r[2] for r in rows], dtype=np.int64)
            halves = np.concatenate([self.halves if held is None else np.vstack([self.halves, held.solid.half]),
                                     fixed.halves])
            radius = np.sqrt(np.einsum("ij,ij->i", halves, halves))
            reach = radius[first] + radius[second]
            self._tables[key] = _Table(rows, first, second, fixed, halves[first], halves[second], reach * reach)
        return self._tables[key]

    def _movers(self, configs: np.ndarray, held: _Held | None) -> _Movers:
        """World poses and bounding boxes of the robot's solids (then the held
        object) at each configuration."""
        every = self.kinematics.poses(configs)
        links = every[:, self.owner_index]
        world = links @ self.offsets
        boxes, halves, objects = links @ self.boxes, self.halves, self.objects
        if held is not None:
            pose = every[:, self.ee_index] @ held.in_hand @ held.solid.offset
            world = np.concatenate([world, pose[:, None]], axis=1)
            boxes = np.concatenate([boxes, (pose @ held.solid.box)[:, None]], axis=1)
            halves = np.vstack([halves, held.solid.half])
            objects = objects + [held.object]
        return _Movers(world, boxes, halves, objects)


class _Movers:
    """The moving solids along a batch of configurations; `at(b)` selects one
    configuration, whose fcl transforms are set on first use."""

    def __init__(self, world: np.ndarray, boxes: np.ndarray, halves: np.ndarray, objects: list):
        self.world, self.boxes, self.halves, self.objects = world, boxes, halves, objects
        self.b = 0
        self.placed: set[int] = set()

    def at(self, b: int) -> None:
        self.b, self.placed = b, set()

    def object(self, k: int) -> fcl.CollisionObject:
        if k not in self.placed:
            self.objects[k].setTransform(_transform(self.world[self.b, k]))
            self.placed.add(k)
        return self.objects[k]


def _transform(pose: np.ndarray) -> fcl.Transform:
    return fcl.Transform(pose[:3, :3], pose[:3, 3])
