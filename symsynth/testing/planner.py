"""The conformance suite every planner plugin must pass.

As in `dd`'s backend tests, `PlannerConformance` holds the tests;
`conformance("planner", NAME)` (`symsynth.testing`) runs them for a
registered planner, as tests/test_planner_conformance.py does for every
installed one.  The scenes are tiny and built here in Python: the
Franka Panda on a table, with blocks, walls and posts placed so that each
fact below follows from geometry, and every test first re-derives its
premise *without* the planner: forward kinematics read from the URDF
(`UrdfChain`), the Panda's collision meshes (trimesh), and boxes compared by
hand.  The planners need not agree numerically, only on these facts:

* the robot at home touches nothing; the hand inside the base or inside the
  table is a static collision; a motion's check stops at its first static
  contact, naming only the places touched before it;
* inverse kinematics meets the pose within 1 mm and 0.01 rad, inside the
  joint limits, and answers None for a pose out of reach (an anchor there is
  a `PlannerError` naming it);
* (1) a wall between two anchors: the straight motion collides statically,
  and the roadmap still joins them by edges none of which goes through it;
* (2) an object standing on the only short path: the straight motion names
  its place and nothing else, and with the place ignored the roadmap's path
  is that straight motion;
* (3) a gap between two posts: the empty hand passes, a long held object
  collides statically;
* (4) a location obstacle is every shape but the held one's: the held
  object's own place is no obstacle to it;
* a planner that declares `time_limited` grows its roadmap for the
  `seconds` it is given.
"""

from __future__ import annotations

import atexit
import dataclasses
import functools
import math
import time
import xml.etree.ElementTree as ElementTree
from collections.abc import Sequence
from typing import Any
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pybullet_data
import pytest
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from symsynth.planning.anchors import anchor_configs
from symsynth.planning.build import obtain_costmap
from symsynth.planning.protocol import Contacts, Mode, Planner, PlannerError, Roadmap
from symsynth.planning.registry import planner_class
from symsynth.scene.geometry import Body, Geometry, Grasp, Pose, Robot, Shape
from symsynth.scene.model import ObjectSpec, Scene, geometry_of
from symsynth.testing import Conformance

PANDA = Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"
MESHES = PANDA.parent / "meshes" / "collision"
JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGERS = (("panda_finger_joint1", 0.04), ("panda_finger_joint2", 0.04))
HOME = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
ROBOT = Robot(urdf=PANDA, base=Pose(), home=HOME, ee_link="panda_hand", joints=JOINTS, fixed=FINGERS)
CHECK_STEP = 0.05  # radians between collision checks along a segment
PALM = (0.0, 0.0, 0.02)  # points inside the hand's collision mesh (checked in a test)
PALM_LOW = (0.0, 0.0, 0.06)
PADS = {"leftfinger": (0.0, 0.01, 0.05), "rightfinger": (0.0, -0.01, 0.05)}  # inside each finger, its frame

TABLE = Body("table", Shape("box", size=(1.2, 1.6, 0.05)), Pose((0.3, 0.0, -0.05)))
BLOCK = Shape("box", size=(0.05, 0.05, 0.05))
PLATE = Shape("box", size=(0.12, 0.12, 0.05))  # as tall as a block: under the anchors' fingertips
BAR = Shape("box", size=(0.04, 0.4, 0.05))  # long along y
WALL = Body("wall", Shape("box", size=(0.3, 0.04, 0.3)), Pose((0.5, 0.0, 0.0)))
POSTS = (Body("left post", Shape("box", size=(0.1, 0.1, 0.5)), Pose((0.5, 0.2, 0.0))),
         Body("right post", Shape("box", size=(0.1, 0.1, 0.5)), Pose((0.5, -0.2, 0.0))))

# A configuration whose palm lies inside the base (test_self_collision
# checks it) and one whose palm lies inside the table top.
INTO_BASE = (1.42, -0.89, -2.63, -2.92, 2.41, 3.68, 2.33)
INTO_TABLE = (0.0, 1.6, 0.0, -0.5, 0.0, 1.8, 0.785)


def top_grasp(height: float, approach: float = 0.05, yaw: float = 0.0) -> Grasp:
    """The hand straight down over an object `height` tall, its fingertips
    2 cm below the top; `yaw` turns it about the vertical."""
    return Grasp("top", Pose.from_rpy((0.0, 0.0, height + 0.1034 - 0.02), (math.pi, 0.0, yaw)), approach)


def physical_scene(name: str, objects: dict[str, tuple[str, Shape]], places: dict[str, tuple],
                   obstacles: tuple[Body, ...] = (TABLE,), grasp: Grasp | None = None) -> Scene:
    """A scene of `objects` (name -> place, shape) at `places` (name -> xyz)."""
    grasp = grasp or top_grasp(0.05)
    geometry = Geometry(robot=ROBOT, obstacles=obstacles,
                        shapes={o: shape for o, (_, shape) in objects.items()},
                        places={x: Pose((float(xyz[0]), float(xyz[1]), float(xyz[2]))) for x, xyz in places.items()},
                        grasps={grasp.name: grasp})
    specs = tuple(ObjectSpec(o, frozenset({o}), at) for o, (at, _) in objects.items())
    return Scene(name, specs, tuple(places), (), (grasp.name,), geometry=geometry)


SCENES = {
    "nothing": lambda: physical_scene("nothing", {}, {}, obstacles=()),
    "table": lambda: physical_scene("table", {}, {}),
    "wall": lambda: physical_scene("wall", {"a": ("A", BLOCK)}, {"A": (0.5, -0.2, 0), "B": (0.5, 0.2, 0)},
                                   obstacles=(TABLE, WALL)),
    # M is raised 10 cm (a shelf that is not modelled): the hand flies over
    # what stands at A and B but through what stands at M.
    "passage": lambda: physical_scene("passage", {"a": ("A", BLOCK), "m": ("M", PLATE), "b": ("B", BLOCK)},
                                      {"A": (0.5, -0.2, 0), "M": (0.5, 0.0, 0.1), "B": (0.5, 0.2, 0)}),
    # The hand's fingers along x, so it is 6 cm thick across the 30 cm gap.
    "gap": lambda: physical_scene("gap", {"bar": ("shelf", BAR)}, {"shelf": (0.3, -0.45, 0)},
                                  obstacles=(TABLE,) + POSTS, grasp=top_grasp(0.05, yaw=math.pi / 2)),
    "single": lambda: physical_scene("single", {"a": ("x", BLOCK)}, {"x": (0.5, 0.0, 0)}),
    "far": lambda: physical_scene("far", {"a": ("near", BLOCK)}, {"near": (0.5, 0.0, 0), "far": (1.5, 0.0, 0)}),
}


@functools.cache
def scene(name: str) -> Scene:
    return SCENES[name]()


@functools.cache
def _planner(planner_name: str, scene_name: str) -> Planner:
    return planner_class(planner_name)(scene(scene_name))


# The kept planners let go while the modules they use are still there (a
# pybullet client left to the interpreter's last sweep fails in __del__).
atexit.register(_planner.cache_clear)


class UrdfChain:
    """Forward kinematics read straight from the URDF with numpy: the
    independent witness for every test's premise."""

    def __init__(self, urdf: Path) -> None:
        self.joints = {_attr(_find(j, "child"), "link"): j for j in ElementTree.parse(urdf).getroot().iter("joint")}
        self.chains: dict[str, list] = {}

    def limits(self, names: Sequence[str]) -> np.ndarray:
        by_name = {j.get("name"): j for j in self.joints.values()}
        return np.array([[float(_attr(_find(by_name[n], "limit"), k)) for k in ("lower", "upper")] for n in names])

    def chain(self, link: str) -> list[tuple[str, str, np.ndarray, np.ndarray]]:
        """(name, type, origin transform, axis) of the joints from the root to `link`."""
        if link not in self.chains:
            chain, child = [], link
            while child in self.joints:
                joint = self.joints[child]
                origin = _find(joint, "origin")
                axis = joint.find("axis")
                chain.append((joint.get("name"), joint.get("type"),
                              Pose.from_rpy(_floats(origin.get("xyz")), _floats(origin.get("rpy"))).matrix(),
                              np.array(_floats(axis.get("xyz") if axis is not None else "1 0 0"))))
                child = _attr(_find(joint, "parent"), "link")
            self.chains[link] = chain[::-1]
        return self.chains[link]

    def poses(self, configs: npt.ArrayLike, link: str = "panda_hand") -> np.ndarray:
        """(n, 4, 4) world poses of `link` at n configurations (fingers open)."""
        configs = np.atleast_2d(np.asarray(configs, float))
        values = {name: configs[:, i] for i, name in enumerate(JOINTS)}
        values |= {name: np.full(len(configs), value) for name, value in FINGERS}
        transform = np.broadcast_to(np.eye(4), (len(configs), 4, 4))
        for name, kind, origin, axis in self.chain(link):
            motion = np.tile(np.eye(4), (len(configs), 1, 1))
            if kind == "revolute":
                motion[:, :3, :3] = _rotations(axis, values[name])
            elif kind == "prismatic":
                motion[:, :3, 3] = axis[None, :] * values[name][:, None]
            transform = transform @ origin @ motion
        return transform

    def pose(self, config: Sequence[float], link: str = "panda_hand") -> np.ndarray:
        return self.poses([config], link)[0]

    def points(self, configs: npt.ArrayLike, local: Sequence[float], link: str = "panda_hand") -> np.ndarray:
        return (self.poses(configs, link) @ np.append(local, 1.0))[:, :3]

    def point(self, config: Sequence[float], local: Sequence[float], link: str = "panda_hand") -> np.ndarray:
        return self.points([config], local, link)[0]


def _floats(text: str | None) -> tuple[float, float, float]:
    x, y, z = (float(v) for v in (text or "0 0 0").split())
    return x, y, z


def _find(element: ElementTree.Element, path: str) -> ElementTree.Element:
    found = element.find(path)
    assert found is not None, f"the URDF has no {path} in {element.get('name')}"
    return found


def _attr(element: ElementTree.Element, name: str) -> str:
    value = element.get(name)
    assert value is not None, f"the URDF's {element.tag} has no {name}"
    return value


def _rotations(axis: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Rodrigues' formula, one rotation about `axis` per angle."""
    k = axis / np.linalg.norm(axis)
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return (np.eye(3) + np.sin(angles)[:, None, None] * cross
            + (1 - np.cos(angles))[:, None, None] * (cross @ cross))


URDF = UrdfChain(PANDA)


@functools.cache
def mesh(link: str) -> trimesh.Trimesh:
    """The collision mesh of a Panda link (`hand`, `link0`, `leftfinger`, ...)
    in the link's frame, as the URDF places it."""
    element = next(e for e in ElementTree.parse(PANDA).getroot().iter("link") if e.get("name") == f"panda_{link}")
    collision = _find(element, "collision")
    loaded = trimesh.load(MESHES / Path(_attr(_find(collision, "geometry/mesh"), "filename")).name, force="mesh")
    assert isinstance(loaded, trimesh.Trimesh)
    origin = collision.find("origin")
    if origin is not None:
        loaded.apply_transform(Pose.from_rpy(_floats(origin.get("xyz")), _floats(origin.get("rpy"))).matrix())
    return loaded


def inside_box(point: npt.ArrayLike, body_pose: Pose, size: Sequence[float], margin: float = 0.0) -> bool:
    """Whether `point` (world) is inside a box shape at `body_pose`, at least `margin` from its faces."""
    local = np.linalg.inv(body_pose.matrix()) @ np.append(point, 1.0)
    half = np.asarray(size) / 2
    centred = local[:3] - np.array([0.0, 0.0, half[2]])
    return bool(np.all(np.abs(centred) <= half - margin))


def segment(start: Sequence[float], goal: Sequence[float], step: float = CHECK_STEP / 5) -> np.ndarray:
    a, b = np.asarray(start, float), np.asarray(goal, float)
    steps = max(1, math.ceil(float(np.linalg.norm(b - a)) / step))
    return np.array([a + (b - a) * i / steps for i in range(steps + 1)])


def crossing(points: np.ndarray, plane_y: float = 0.0) -> np.ndarray | None:
    """Where a polyline first crosses the plane y = plane_y (linear between samples)."""
    for p, q in zip(points, points[1:]):
        if (p[1] - plane_y) * (q[1] - plane_y) <= 0 and p[1] != q[1]:
            return p + (q - p) * (plane_y - p[1]) / (q[1] - p[1])
    return None


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """The angle of the rotation from a to b (3x3 rotation matrices)."""
    return math.acos(max(-1.0, min(1.0, (np.trace(a.T @ b) - 1) / 2)))


def shortest(roadmap: Roadmap, start: int, goal: int, removed: Sequence[bool] | None = None) -> float:
    keep = np.ones(len(roadmap.edges), bool) if removed is None else ~np.asarray(removed, bool)
    n = len(roadmap.configs)
    edges, lengths = roadmap.edges[keep], roadmap.lengths[keep]
    graph = coo_matrix((lengths, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    return float(dijkstra(graph, directed=False, indices=start)[goal])


def held_pose(config: Sequence[float], grasp: Grasp) -> Pose:
    """The held object's frame: T_ee @ inverse(grasp.pose), by the URDF's kinematics."""
    return Pose.from_matrix(URDF.pose(config)) @ grasp.pose.inverse()


def box_corners(pose: Pose, size: Sequence[float]) -> np.ndarray:
    sx, sy, sz = size
    local = np.array([[x, y, z, 1.0] for x in (-sx / 2, sx / 2) for y in (-sy / 2, sy / 2) for z in (0.0, sz)])
    return (pose.matrix() @ local.T).T[:, :3]


def overlap(a_corners: np.ndarray, body: Body) -> float:
    """The smallest overlap, over the axes, of the bounding box of
    `a_corners` with an axis-aligned box obstacle (negative: apart)."""
    low_b = np.array(body.pose.xyz) - np.array(body.shape.size) * [0.5, 0.5, 0.0]
    high_b = low_b + np.array(body.shape.size)
    low_a, high_a = a_corners.min(axis=0), a_corners.max(axis=0)
    return float(np.min(np.minimum(high_a, high_b) - np.maximum(low_a, low_b)))


class PlannerConformance(Conformance):
    """The planner suite; `self.name` is the registered planner under test."""

    def planner(self, scene_name: str) -> Planner:
        return _planner(self.name, scene_name)

    def solve(self, scene_name: str, pose: Pose, seed: Sequence[float] = HOME) -> tuple[float, ...]:
        config = self.planner(scene_name).inverse_kinematics(pose, tuple(seed))
        assert config is not None, f"no inverse kinematics for {pose} in scene {scene_name}"
        return config

    def anchor(self, scene_name: str, place: str) -> tuple[float, ...]:
        geometry = geometry_of(scene(scene_name))
        return self.solve(scene_name, geometry.places[place] @ geometry.grasps["top"].pre_image())

    # --- the interface

    def test_is_a_planner_with_the_registered_name(self):
        planner = self.planner("table")
        assert isinstance(planner, Planner)
        assert type(planner).name == self.name

    def test_limits_are_the_urdf_limits(self):
        assert np.allclose(self.planner("table").limits, URDF.limits(JOINTS), atol=1e-6)

    def test_unknown_mode_is_a_planner_error(self):
        with pytest.raises(PlannerError, match="nobody"):
            self.planner("single").contacts(Mode("nobody", "top"), HOME)

    # --- contacts at one configuration

    def test_nothing_is_touched_at_home(self):
        for name in ("nothing", "table"):
            assert self.planner(name).contacts(Mode(), HOME) == Contacts()
        for mode in (Mode(), Mode("a", "top"), Mode("m", "top")):
            assert self.planner("passage").contacts(mode, HOME) == Contacts()

    def test_self_collision(self):
        """The palm lies inside the base link's mesh: a self-collision, in a
        scene without obstacles."""
        palm = URDF.point(INTO_BASE, PALM)
        assert mesh("hand").contains([PALM])[0]
        assert mesh("link0").contains([palm])[0], palm
        assert self.planner("nothing").contacts(Mode(), INTO_BASE) == Contacts(static=True)

    def test_table_is_a_static_obstacle(self):
        palm = URDF.point(INTO_TABLE, PALM)
        assert inside_box(palm, TABLE.pose, TABLE.shape.size, margin=0.015), palm
        assert self.planner("table").contacts(Mode(), INTO_TABLE).static
        assert self.planner("nothing").contacts(Mode(), INTO_TABLE) == Contacts()

    # --- inverse kinematics

    def test_inverse_kinematics_meets_the_pose_within_the_limits(self):
        geometry = geometry_of(scene("passage"))
        limits = URDF.limits(JOINTS)
        for place, pose in geometry.places.items():
            target = pose @ geometry.grasps["top"].pre_image()
            config = self.solve("passage", target)
            assert np.all(limits[:, 0] <= config) and np.all(config <= limits[:, 1]), (place, config)
            reached = URDF.pose(config)
            assert np.linalg.norm(reached[:3, 3] - target.xyz) <= 1e-3 + 1e-9, place
            assert angle_between(reached[:3, :3], target.matrix()[:3, :3]) <= 0.01 + 1e-9, place

    def test_inverse_kinematics_is_a_function_of_pose_and_seed(self):
        """The same (pose, seed) gives the same configuration after other
        questions, and from a new planner of the same scene."""
        geometry = geometry_of(scene("passage"))
        targets = [pose @ geometry.grasps["top"].pre_image() for pose in geometry.places.values()]
        planner = self.planner("passage")
        first: list[Any] = [planner.inverse_kinematics(t, HOME) for t in targets]
        assert all(c is not None for c in first)
        # other seeds in between: the robot state a solver leaves must not leak
        for t, c in zip(targets, first):
            planner.inverse_kinematics(t, tuple(np.add(c, 0.3)))
        again: list[Any] = [planner.inverse_kinematics(t, HOME) for t in reversed(targets)][::-1]
        fresh = planner_class(self.name)(scene("passage"))
        anew: list[Any] = [fresh.inverse_kinematics(t, HOME) for t in targets]
        for c, a, n in zip(first, again, anew):
            assert np.array_equal(c, a) and np.array_equal(c, n), (c, a, n)

    def test_unreachable_pose_has_no_inverse_kinematics(self):
        """(4) `far` is 1.5 m from the shoulder; the URDF's link offsets from
        joint 2 to the hand add up to less than 1 m."""
        geometry = geometry_of(scene("far"))
        target = geometry.places["far"] @ geometry.grasps["top"].pre_image()
        by_child = URDF.joints
        offsets = sum(float(np.linalg.norm(_floats(_find(by_child[link], "origin").get("xyz"))))
                      for link in ("panda_link3", "panda_link4", "panda_link5", "panda_link6", "panda_link7",
                                   "panda_link8", "panda_hand"))
        shoulder = np.array([0.0, 0.0, 0.333])  # joint 2's axis passes here whatever joint 1 is
        assert np.linalg.norm(np.array(target.xyz) - shoulder) > offsets + 0.3
        assert self.planner("far").inverse_kinematics(target, HOME) is None

    def test_unreachable_anchor_is_reported_by_name(self):
        with pytest.raises(PlannerError, match="far/top") as error:
            anchor_configs(self.planner("far"), scene("far"))
        assert "near/top" not in str(error.value)

    # --- (1) a wall between two anchors

    def test_wall_blocks_the_straight_motion(self):
        start, goal = self.anchor("wall", "A"), self.anchor("wall", "B")
        palm = URDF.points(segment(start, goal), PALM)
        cross = crossing(palm)
        assert cross is not None and inside_box(cross, WALL.pose, WALL.shape.size * np.array([1, 100, 1]),
                                                margin=0.03), cross
        planner = self.planner("wall")
        assert planner.contacts(Mode(), start) == Contacts() == planner.contacts(Mode(), goal)
        assert planner.motion_contacts(Mode(), start, goal, CHECK_STEP).static

    def test_roadmap_joins_the_anchors_around_the_wall(self):
        start, goal = self.anchor("wall", "A"), self.anchor("wall", "B")
        roadmap = self.planner("wall").roadmap(Mode(), {"A": start, "B": goal}, 40, 0)
        a, b = roadmap.anchors["A"], roadmap.anchors["B"]
        assert np.allclose(roadmap.configs[a], start) and np.allclose(roadmap.configs[b], goal)
        assert np.allclose(roadmap.lengths, np.linalg.norm(roadmap.configs[roadmap.edges[:, 0]]
                                                           - roadmap.configs[roadmap.edges[:, 1]], axis=1))
        assert math.isfinite(shortest(roadmap, a, b))
        assert shortest(roadmap, a, b) > np.linalg.norm(np.subtract(goal, start)) + 1e-6
        for i, j in roadmap.edges:  # no edge carries the palm through the wall
            palm = URDF.points(segment(roadmap.configs[i], roadmap.configs[j], CHECK_STEP), PALM)
            cross = crossing(palm)
            assert cross is None or not inside_box(cross, WALL.pose, WALL.shape.size * np.array([1, 100, 1])), \
                (i, j, cross)

    def test_anchor_in_collision_is_reported_by_name(self):
        with pytest.raises(PlannerError, match="inside"):
            self.planner("nothing").roadmap(Mode(), {"home": HOME, "inside": INTO_BASE}, 5, 0)

    # --- (2) a location obstacle on the only short path

    def test_straight_motion_names_the_place_in_the_way(self):
        start, goal = self.anchor("passage", "A"), self.anchor("passage", "B")
        low = URDF.points(segment(start, goal), PALM_LOW)
        m = geometry_of(scene("passage")).places["M"]
        cross = crossing(low)
        assert cross is not None and inside_box(cross, m, PLATE.size, margin=0.01), cross
        assert mesh("hand").contains([PALM_LOW])[0]
        planner = self.planner("passage")
        assert planner.motion_contacts(Mode(), start, goal, CHECK_STEP) == Contacts(locations=frozenset({"M"}))
        assert planner.motion_contacts(Mode(), goal, start, CHECK_STEP) == Contacts(locations=frozenset({"M"}))

    def test_with_the_place_ignored_the_path_is_short(self):
        start, goal = self.anchor("passage", "A"), self.anchor("passage", "B")
        planner = self.planner("passage")
        roadmap = planner.roadmap(Mode(), {"A": start, "B": goal}, 20, 0)
        a, b = roadmap.anchors["A"], roadmap.anchors["B"]
        straight = float(np.linalg.norm(np.subtract(goal, start)))
        assert shortest(roadmap, a, b) == pytest.approx(straight, abs=1e-9)
        blocked = [planner.motion_contacts(Mode(), roadmap.configs[i], roadmap.configs[j], CHECK_STEP).locations
                   for i, j in roadmap.edges]
        direct = [k for k, (i, j) in enumerate(roadmap.edges) if {i, j} == {a, b}]
        assert len(direct) == 1 and blocked[direct[0]] == {"M"}
        assert shortest(roadmap, a, b, ["M" in found for found in blocked]) > straight + 1e-6

    def test_roadmap_is_deterministic(self):
        start, goal = self.anchor("passage", "A"), self.anchor("passage", "B")
        first, second = (self.planner("passage").roadmap(Mode(), {"A": start, "B": goal}, 10, 3) for _ in "12")
        assert np.array_equal(first.configs, second.configs) and np.array_equal(first.edges, second.edges)

    def test_a_time_limit_grows_the_roadmap_for_that_long(self):
        """A planner that says it honours `seconds` (`time_limited`) grows
        for that long, well past the `size` it is also given.  One that does
        not say so never sees `seconds`: a scene asking for a time limit is
        refused, from the class, before the planner is built."""
        if not getattr(planner_class(self.name), "time_limited", False):
            table = scene("table")
            timed = dataclasses.replace(geometry_of(table).planner, seconds=0.3)
            timed_scene = dataclasses.replace(table, geometry=dataclasses.replace(geometry_of(table), planner=timed))
            with pytest.raises(PlannerError, match="has no roadmap time limit"):
                obtain_costmap(timed_scene, planner_name=self.name, use_cache=False, progress=False)
            return
        planner = self.planner("table")
        start = time.perf_counter()
        roadmap = planner.roadmap(Mode(), {"home": HOME}, 5, 0, seconds=0.3)
        assert time.perf_counter() - start >= 0.3
        assert len(roadmap.configs) > 5 + 1

    # --- (3) a held object too long for a gap

    def gap_configs(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """The bar 12 cm above the table between the posts, and 56 cm up, above them."""
        grasp = geometry_of(scene("gap")).grasps["top"]
        low = self.solve("gap", Pose((0.5, 0.0, 0.12)) @ grasp.pose)
        high = self.solve("gap", Pose((0.5, 0.0, 0.56)) @ grasp.pose, low)
        return low, high

    def test_empty_hand_passes_the_gap(self):
        low, high = self.gap_configs()
        for link in ("hand", "leftfinger", "rightfinger"):
            frame = URDF.pose(low, f"panda_{link}")
            points = (frame @ np.c_[mesh(link).vertices, np.ones(len(mesh(link).vertices))].T).T[:, :3]
            assert np.all(np.abs(points[:, 1]) < 0.15 - 0.05), link  # inside the gap, 5 cm clear
            assert np.all(points[:, 2] < 0.5), link  # and below the posts' tops
        planner = self.planner("gap")
        assert planner.motion_contacts(Mode(), high, low, CHECK_STEP) == Contacts()

    def test_long_held_object_collides_in_the_gap(self):
        low, high = self.gap_configs()
        grasp = geometry_of(scene("gap")).grasps["top"]
        assert all(overlap(box_corners(held_pose(low, grasp), BAR.size), post) > 0.02 for post in POSTS)
        assert box_corners(held_pose(high, grasp), BAR.size)[:, 2].min() > 0.5 + 0.02
        planner, holding = self.planner("gap"), Mode("bar", "top")
        assert planner.contacts(holding, low) == Contacts(static=True)
        assert planner.contacts(holding, high) == Contacts()
        assert planner.motion_contacts(holding, high, low, CHECK_STEP).static

    # --- (4) location obstacles and modes

    def finger_in_block(self) -> tuple[float, ...]:
        """The hand 5 cm along y and 1 cm up from the top grasp of the block
        at x: one finger stands inside that block."""
        geometry = geometry_of(scene("single"))
        config = self.solve("single", Pose((0.0, 0.05, 0.01)) @ geometry.places["x"] @ geometry.grasps["top"].pose)
        pads = [URDF.point(config, pad, f"panda_{finger}") for finger, pad in PADS.items()]
        assert all(mesh(finger).contains([pad])[0] for finger, pad in PADS.items())
        assert any(inside_box(pad, geometry.places["x"], BLOCK.size, margin=0.005) for pad in pads), pads
        return config

    def test_the_held_object_is_not_its_own_obstacle(self):
        """With a single object, holding it leaves no location obstacle."""
        config = self.finger_in_block()
        grasp = geometry_of(scene("single")).grasps["top"]
        assert box_corners(held_pose(config, grasp), BLOCK.size)[:, 2].min() > 0.005  # above the table
        planner = self.planner("single")
        assert planner.contacts(Mode(), config) == Contacts(locations=frozenset({"x"}))
        assert planner.contacts(Mode("a", "top"), config) == Contacts()

    def test_motion_contacts_stop_at_the_first_static_contact(self):
        """From the finger in the block (x, no static contact) into the table
        (static): x, touched before the table, is named; from the table
        back, the first configuration is static and nothing is named."""
        config = self.finger_in_block()
        assert inside_box(URDF.point(INTO_TABLE, PALM), TABLE.pose, TABLE.shape.size, margin=0.015)
        planner = self.planner("single")
        assert planner.contacts(Mode(), config) == Contacts(locations=frozenset({"x"}))
        assert planner.motion_contacts(Mode(), config, INTO_TABLE, CHECK_STEP) == \
            Contacts(static=True, locations=frozenset({"x"}))
        assert planner.motion_contacts(Mode(), INTO_TABLE, config, CHECK_STEP) == Contacts(static=True)

    def test_motion_contacts_include_both_ends(self):
        config = self.finger_in_block()
        planner = self.planner("single")
        assert planner.motion_contacts(Mode(), HOME, config, CHECK_STEP).locations == {"x"}
        assert planner.motion_contacts(Mode(), config, HOME, CHECK_STEP).locations == {"x"}
        assert planner.motion_contacts(Mode(), config, config, CHECK_STEP).locations == {"x"}
        coarse = 10 * float(np.linalg.norm(np.subtract(config, HOME)))  # one step: the ends alone
        assert planner.motion_contacts(Mode(), HOME, config, coarse).locations == {"x"}
        assert planner.motion_contacts(Mode(), config, HOME, coarse).locations == {"x"}
