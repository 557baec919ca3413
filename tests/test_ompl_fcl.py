"""The `ompl-fcl` planner and the shared roadmap builder (`symsynth.planning.prm`).

Expectations come from elsewhere than the code under test: pybullet's
forward kinematics for the Panda, the Panda's collision meshes read with
trimesh, fcl's own box-box test, and a 2-D roadmap whose free space is
decided by hand.  The planner-independent facts (walls, gaps, places) are in
the conformance suite; here are the ones specific to this implementation.
"""

from __future__ import annotations

import functools
import math
import time
from pathlib import Path

import fcl
import numpy as np
import pybullet
import pybullet_data
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import Contacts, Mode, PlannerError
from symsynth.scene.geometry import Body, Geometry, Grasp, Pose, Robot, Shape
from symsynth.scene.model import ObjectSpec, Scene
from symsynth_planners.ompl_fcl import OmplFclPlanner
from symsynth_planners.ompl_fcl.bounds import axes_overlap
from symsynth_planners.ompl_fcl.shapes import resolve_mesh

PANDA = Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"
JOINTS = tuple(f"panda_joint{i}" for i in range(1, 8))
FINGERS = (("panda_finger_joint1", 0.04), ("panda_finger_joint2", 0.04))
HOME = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
ROBOT = Robot(urdf=PANDA, base=Pose(), home=HOME, ee_link="panda_hand", joints=JOINTS, fixed=FINGERS)
TABLE = Body("table", Shape("box", size=(1.2, 1.6, 0.05)), Pose((0.3, 0.0, -0.05)))
BLOCK = Shape("box", size=(0.05, 0.05, 0.05))
TOP = Grasp("top", Pose.from_rpy((0.0, 0.0, 0.05 + 0.1034 - 0.02), (math.pi, 0.0, 0.0)))
PALM = (0.0, 0.0, 0.02)  # inside the hand's collision mesh (asserted below)


def physical(objects: dict[str, tuple[str, Shape]], places: dict[str, Pose], obstacles=(TABLE,),
             grasps: tuple[Grasp, ...] = (TOP,), robot: Robot = ROBOT) -> Scene:
    geometry = Geometry(robot=robot, obstacles=tuple(obstacles),
                        shapes={o: s for o, (_, s) in objects.items()}, places=dict(places),
                        grasps={g.name: g for g in grasps})
    specs = tuple(ObjectSpec(o, frozenset({o}), at) for o, (at, _) in objects.items())
    return Scene("test", specs, tuple(places), (), tuple(g.name for g in grasps), geometry=geometry)


@functools.cache
def planner_for(name: str) -> OmplFclPlanner:
    return OmplFclPlanner(SCENES[name]())


# --- pybullet as the independent witness -----------------------------------------------------

@functools.cache
def _bullet() -> tuple[int, int, dict[str, int]]:
    client = pybullet.connect(pybullet.DIRECT)
    body = pybullet.loadURDF(str(PANDA), useFixedBase=True, physicsClientId=client)
    links = {}
    for j in range(pybullet.getNumJoints(body, physicsClientId=client)):
        info = pybullet.getJointInfo(body, j, physicsClientId=client)
        links[info[12].decode()] = j
        links[info[1].decode()] = j  # joints by name too: a joint's index is its child link's
    return client, body, links


def bullet_pose(config, link: str = "panda_hand") -> np.ndarray:
    """pybullet's world pose of a link's URDF frame at `config` (fingers open)."""
    client, body, index = _bullet()
    for name, value in (*zip(JOINTS, config), *FINGERS):
        pybullet.resetJointState(body, index[name], value, physicsClientId=client)
    if link == "panda_link0":  # pybullet gives the base's inertial frame: undo its offset
        position, orientation = pybullet.getBasePositionAndOrientation(body, physicsClientId=client)
        inertial = pybullet.getDynamicsInfo(body, -1, physicsClientId=client)[3:5]
        return _matrix(position, orientation) @ np.linalg.inv(_matrix(*inertial))
    state = pybullet.getLinkState(body, index[link], computeForwardKinematics=True, physicsClientId=client)
    return _matrix(state[4], state[5])


def _matrix(position, orientation) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = Rotation.from_quat(orientation).as_matrix()
    pose[:3, 3] = position
    return pose


def bullet_limits() -> np.ndarray:
    client, body, index = _bullet()
    return np.array([pybullet.getJointInfo(body, index[j], physicsClientId=client)[8:10] for j in JOINTS])


@functools.cache
def link_mesh(link: str) -> trimesh.Trimesh:
    """The Panda's collision mesh of a link, in the link frame (the Panda's
    collision elements have no origin but the right finger's, unused here)."""
    name = link.removeprefix("panda_").replace("leftfinger", "finger")
    return trimesh.load(PANDA.parent / "meshes" / "collision" / f"{name}.obj", force="mesh")


def world_point(config, local, link: str = "panda_hand") -> np.ndarray:
    return (bullet_pose(config, link) @ np.append(local, 1.0))[:3]


def robot_points(config) -> np.ndarray:
    """Every collision-mesh vertex of the arm and hand, in the world."""
    links = [f"panda_link{i}" for i in range(8)] + ["panda_hand", "panda_leftfinger"]
    return np.vstack([(bullet_pose(config, link) @ np.c_[link_mesh(link).vertices,
                                                          np.ones(len(link_mesh(link).vertices))].T).T[:, :3]
                      for link in links])


def box_at(centre, size) -> Pose:
    """The pose of a box shape (frame at its bottom face) centred at `centre`."""
    return Pose((float(centre[0]), float(centre[1]), float(centre[2] - size[2] / 2)))


SCENES = {
    "table": lambda: physical({}, {}),
    "two places": lambda: physical({"a": ("A", BLOCK)},
                                   {"A": Pose((0.5, -0.2, 0.0)), "B": Pose((0.5, 0.2, 0.0))}),
}


# --- kinematics ------------------------------------------------------------------------------

def test_forward_kinematics_matches_pybullet():
    planner = planner_for("table")
    kinematics = planner.kinematics
    rng = np.random.default_rng(7)
    configs = np.vstack([HOME, rng.uniform(bullet_limits()[:, 0], bullet_limits()[:, 1], (3, 7))])
    fast = kinematics.poses(configs)
    for config, poses in zip(configs, fast):
        reference = kinematics.reference_poses(config)
        for link, pose, slow in zip(kinematics.links, poses, reference):
            expected = bullet_pose(config, link)
            assert np.allclose(pose, expected, atol=1e-6), (link, config)
            assert np.allclose(slow, expected, atol=1e-6), (link, config)


def test_limits_are_pybullets():
    assert np.allclose(planner_for("table").limits, bullet_limits(), atol=1e-9)


def test_inverse_kinematics_round_trip():
    planner = planner_for("table")
    limits = bullet_limits()
    rng = np.random.default_rng(11)
    for config in rng.uniform(limits[:, 0], limits[:, 1], (4, 7)):
        target = bullet_pose(config)
        found = planner.inverse_kinematics(Pose.from_matrix(target), HOME)
        assert found is not None, config
        assert np.all(limits[:, 0] <= found) and np.all(np.array(found) <= limits[:, 1])
        reached = bullet_pose(found)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-3
        assert Rotation.from_matrix(reached[:3, :3].T @ target[:3, :3]).magnitude() <= 0.01


def test_inverse_kinematics_stays_near_the_seed():
    """The seed itself is a solution: it comes back (up to the solver's tolerance)."""
    planner = planner_for("table")
    seed = (0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.5)
    found = planner.inverse_kinematics(Pose.from_matrix(bullet_pose(seed)), seed)
    assert np.allclose(found, seed, atol=1e-4)


def test_unreachable_pose_has_no_inverse_kinematics():
    assert planner_for("table").inverse_kinematics(Pose((2.0, 0.0, 0.3)), HOME) is None


def test_package_paths_resolve_against_the_urdf_directory(tmp_path):
    urdf = tmp_path / "robot.urdf"
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "a.obj").write_text("")
    assert resolve_mesh(urdf, "package://meshes/a.obj") == tmp_path / "meshes" / "a.obj"
    assert resolve_mesh(urdf, "package://my_robot/meshes/a.obj") == tmp_path / "meshes" / "a.obj"
    assert resolve_mesh(urdf, "meshes/a.obj") == tmp_path / "meshes" / "a.obj"


# --- collisions ------------------------------------------------------------------------------

def test_adjacent_links_are_the_urdfs_and_nothing_touches_at_home():
    world = planner_for("table").world
    chain = ["panda_link0", "panda_link1", "panda_link2", "panda_link3", "panda_link4", "panda_link5",
             "panda_link6", "panda_link7", "panda_hand"]  # link8 has no geometry: hand hangs from link7
    expected = {frozenset(pair) for pair in zip(chain, chain[1:])}
    expected |= {frozenset(("panda_hand", finger)) for finger in ("panda_leftfinger", "panda_rightfinger")}
    assert world.adjacent == expected
    assert world.home_contacts == set()


def test_a_box_on_a_link_collides_and_half_a_metre_away_does_not():
    """A 2 cm box around a point inside link 4's mesh at home; then 0.5 m
    further along y, more than 20 cm from every vertex of the robot."""
    inner = link_mesh("panda_link4").centroid
    assert link_mesh("panda_link4").contains([inner])[0]
    centre = world_point(HOME, inner, "panda_link4")
    size = (0.02, 0.02, 0.02)
    touching = Body("box", Shape("box", size=size), box_at(centre, size))
    away_centre = centre + (0.0, 0.5, 0.0)
    away = Body("box", Shape("box", size=size), box_at(away_centre, size))
    assert np.min(np.linalg.norm(robot_points(HOME) - away_centre, axis=1)) > 0.2
    assert OmplFclPlanner(physical({}, {}, obstacles=(TABLE, touching))).contacts(Mode(), HOME) \
        == Contacts(static=True)
    assert OmplFclPlanner(physical({}, {}, obstacles=(TABLE, away))).contacts(Mode(), HOME) == Contacts()


def test_location_obstacle_is_reported_by_name():
    """A block placed around the palm at home is the location `palm`; the
    block at `aside` stands 30 cm from every robot vertex."""
    assert link_mesh("panda_hand").contains([PALM])[0]
    palm = world_point(HOME, PALM)
    places = {"palm": box_at(palm, BLOCK.size), "aside": Pose((0.5, 0.4, 0.0))}
    assert np.min(np.linalg.norm(robot_points(HOME) - (0.5, 0.4, 0.025), axis=1)) > 0.3
    planner = OmplFclPlanner(physical({"a": ("aside", BLOCK)}, places))
    assert planner.contacts(Mode(), HOME) == Contacts(locations=frozenset({"palm"}))


def test_location_solids_are_one_per_distinct_shape_of_the_objects_not_held():
    """`a` and `b` are the same block, `c` a taller one: every place gets a
    block and a tall block, except when the tall one is held."""
    tall = Shape("box", size=(0.05, 0.05, 0.2))
    places = {"A": Pose((0.5, -0.2, 0.0)), "B": Pose((0.5, 0.2, 0.0)), "C": Pose((0.3, 0.0, 0.0))}
    world = OmplFclPlanner(physical({"a": ("A", BLOCK), "b": ("B", BLOCK), "c": ("C", tall)}, places)).world
    both = [size for _ in places for size in (BLOCK.size, tall.size)]
    for held, sizes in ((None, both), ("a", both), ("c", [BLOCK.size] * 3)):
        solids = world.locations(held)
        assert solids.tags == [place for place in places for _ in range(len(sizes) // 3)]
        assert np.allclose(2 * solids.halves, sizes)


def hanging(length: float) -> Grasp:
    """The hand `length` above the object's frame, pointing down."""
    return Grasp("hang", Pose.from_rpy((0.0, 0.0, length), (math.pi, 0.0, 0.0)))


def held_centre(config, grasp: Grasp, size) -> np.ndarray:
    """The held box's centre: T_ee @ inverse(grasp.pose), by pybullet's FK."""
    frame = bullet_pose(config) @ np.linalg.inv(grasp.pose.matrix())
    return (frame @ np.array([0.0, 0.0, size[2] / 2, 1.0]))[:3]


def test_held_object_makes_contact_and_its_hand_does_not_count():
    """An object 30 cm under the hand: an obstacle around it collides in the
    holding mode only; a location obstacle around it is reported by name."""
    grasp = hanging(0.3)
    centre = held_centre(HOME, grasp, BLOCK.size)
    assert np.min(np.linalg.norm(robot_points(HOME) - centre, axis=1)) > 0.1
    small = (0.02, 0.02, 0.02)
    stone = Body("stone", Shape("box", size=small), box_at(centre, small))
    objects = {"a": ("far", BLOCK), "b": ("below", BLOCK)}
    places = {"far": Pose((0.5, 0.4, 0.0)), "below": box_at(centre, BLOCK.size)}
    with_stone = OmplFclPlanner(physical(objects, places, obstacles=(TABLE, stone), grasps=(grasp,)))
    assert with_stone.contacts(Mode("a", "hang"), HOME).static
    assert not with_stone.contacts(Mode(), HOME).static
    planner = OmplFclPlanner(physical(objects, places, grasps=(grasp,)))
    assert planner.contacts(Mode("a", "hang"), HOME) == Contacts(locations=frozenset({"below"}))
    # holding b: the obstacle at `below` is a's shape, which is b's too; at `far` stands nothing else
    assert planner.contacts(Mode("b", "hang"), HOME) == Contacts(locations=frozenset({"below"}))


def test_held_object_between_the_fingers_is_no_collision():
    """A 9 cm wide object held by the top grasp: the open fingers (8 cm
    apart) cut into it, which does not count; the same box as an obstacle
    does collide with them."""
    wide = Shape("box", size=(0.05, 0.09, 0.05))  # y: the fingers' axis at this grasp
    centre = held_centre(HOME, TOP, wide.size)
    pad = (0.0, 0.003, 0.05)  # near the left finger's inner face, 3 mm deep
    finger = world_point(HOME, pad, "panda_leftfinger")
    assert link_mesh("panda_leftfinger").contains([pad])[0]
    local = np.linalg.inv(bullet_pose(HOME) @ np.linalg.inv(TOP.pose.matrix())) @ np.append(finger, 1.0)
    assert np.all(np.abs(local[:2]) <= np.array(wide.size[:2]) / 2) and 0 <= local[2] <= wide.size[2]
    planner = OmplFclPlanner(physical({"w": ("far", wide)}, {"far": Pose((0.5, 0.4, 0.0))}))
    assert planner.contacts(Mode("w", "top"), HOME) == Contacts()
    obstacle = Body("same box", wide, box_at(centre, wide.size))
    assert OmplFclPlanner(physical({}, {}, obstacles=(TABLE, obstacle))).contacts(Mode(), HOME).static


def test_scene_without_geometry_or_unknown_joint_is_a_planner_error():
    bare = Scene("bare", (), (), (), ())
    with pytest.raises(PlannerError, match="physical scene"):
        OmplFclPlanner(bare)
    robot = Robot(urdf=PANDA, base=Pose(), home=HOME, ee_link="panda_hand", joints=JOINTS[:6] + ("elbow",))
    with pytest.raises(PlannerError, match="elbow"):
        OmplFclPlanner(physical({}, {}, robot=robot))


def test_oriented_boxes_overlap_exactly_when_fcl_says_so():
    rng = np.random.default_rng(3)
    n = 3000
    poses = np.tile(np.eye(4), (2, n, 1, 1))
    poses[:, :, :3, :3] = Rotation.random(2 * n, random_state=4).as_matrix().reshape(2, n, 3, 3)
    poses[:, :, :3, 3] = rng.uniform(-0.5, 0.5, (2, n, 3))
    halves = rng.uniform(0.02, 0.3, (2, n, 3))
    found = axes_overlap(poses[0], halves[0], poses[1], halves[1])
    truth = [fcl.collide(*(fcl.CollisionObject(fcl.Box(*(2 * halves[s, k])),
                                               fcl.Transform(poses[s, k, :3, :3], poses[s, k, :3, 3]))
                           for s in (0, 1))) > 0 for k in range(n)]
    assert found.tolist() == truth
    assert 0.1 < np.mean(truth) < 0.9  # both answers occur


def test_motion_contacts_stop_at_a_static_collision():
    """From inside a static obstacle the motion is static whatever follows."""
    inner = link_mesh("panda_link4").centroid
    centre = world_point(HOME, inner, "panda_link4")
    size = (0.02, 0.02, 0.02)
    planner = OmplFclPlanner(physical({}, {}, obstacles=(Body("box", Shape("box", size=size),
                                                              box_at(centre, size)),)))
    far = (1.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
    assert planner.motion_contacts(Mode(), HOME, far, 0.05).static
    assert planner.motion_contacts(Mode(), far, HOME, 0.05).static


# --- roadmaps on the Panda -------------------------------------------------------------------

def panda_roadmap(seed: int):
    planner = planner_for("two places")
    geometry = planner.geometry
    anchors = {"home": HOME}
    for place in ("A", "B"):
        anchors[f"{place}/top"] = planner.inverse_kinematics(geometry.places[place] @ TOP.pre_image(), HOME)
    return planner, anchors, planner.roadmap(Mode(), anchors, 25, seed)


def components(n: int, edges: np.ndarray) -> list[int]:
    """Component labels by union-find."""
    parent = list(range(n))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, j in edges:
        parent[root(int(i))] = root(int(j))
    return [root(i) for i in range(n)]


def test_panda_roadmap_edges_are_collision_free_and_anchors_connected():
    planner, anchors, roadmap = panda_roadmap(seed=1)
    step = planner.geometry.planner.check_step
    assert len(roadmap.configs) >= 25 + len(anchors)
    for name, config in anchors.items():
        assert np.array_equal(roadmap.configs[roadmap.anchors[name]], config)
    labels = components(len(roadmap.configs), roadmap.edges)
    assert len({labels[i] for i in roadmap.anchors.values()}) == 1
    assert np.all(roadmap.edges[:, 0] < roadmap.edges[:, 1])
    assert len({tuple(e) for e in roadmap.edges.tolist()}) == len(roadmap.edges)
    assert np.allclose(roadmap.lengths,
                       [math.dist(roadmap.configs[i], roadmap.configs[j]) for i, j in roadmap.edges])
    fresh = OmplFclPlanner(SCENES["two places"]())  # checks every pair: it did not build the roadmap
    for i, j in roadmap.edges:
        assert not fresh.motion_contacts(Mode(), roadmap.configs[i], roadmap.configs[j], step).static


def test_edge_checks_of_the_planner_that_built_the_roadmap_match_a_fresh_one():
    """The planner that grew a roadmap skips the self and static pairs on its
    edges (it found them free); a fresh planner checks every pair."""
    planner, _, roadmap = panda_roadmap(seed=2)
    step = planner.geometry.planner.check_step
    fresh = OmplFclPlanner(SCENES["two places"]())
    found = [planner.motion_contacts(Mode(), roadmap.configs[i], roadmap.configs[j], step)
             for i, j in roadmap.edges]
    expected = [fresh.motion_contacts(Mode(), roadmap.configs[i], roadmap.configs[j], step)
                for i, j in roadmap.edges]
    assert found == expected
    assert any(c.locations for c in expected) and not any(c.static for c in expected)


def every_pair_contacts(planner: OmplFclPlanner, mode: Mode, config) -> Contacts:
    """`contacts` without culling: fcl on every candidate pair, in order."""
    world = planner.world
    table = world._table(mode, True)
    poses = world.kinematics.poses(np.asarray(config, dtype=float)[None])[0]
    objects = list(world.objects)
    placed = [poses[i] @ o for i, o in zip(world.owner_index, world.offsets)]
    held = world.held(mode)
    if held is not None:
        objects.append(held.object)
        placed.append(poses[world.ee_index] @ held.in_hand @ held.solid.offset)
    for obj, pose in zip(objects, placed):
        obj.setTransform(fcl.Transform(pose[:3, :3], pose[:3, 3]))
    moving, static, touched = len(objects), False, set()
    for kind, k, other in table.rows:
        second = objects[other] if other < moving else table.fixed.objects[other - moving]
        if fcl.collide(objects[k], second):
            if kind == 2:
                touched.add(table.fixed.tags[other - moving])
            else:
                static = True
    return static, frozenset(touched)


def test_culled_contacts_equal_every_pair_checked():
    """Bounding-sphere and separating-axis culling never hide a contact nor
    invent one: random configurations (many of them in contact) give what
    fcl says on every pair."""
    scene = physical({"a": ("A", BLOCK), "b": ("B", BLOCK)},
                     {"A": Pose((0.5, -0.2, 0.0)), "B": Pose((0.5, 0.2, 0.0)), "C": Pose((0.3, 0.0, 0.0))})
    planner = OmplFclPlanner(scene)
    rng = np.random.default_rng(3)
    limits = planner.limits
    anchors = [planner.inverse_kinematics(pose @ TOP.pre_image(), HOME) for pose in scene.geometry.places.values()]
    near = np.clip(np.repeat(anchors, 50, axis=0) + rng.normal(0.0, 0.2, (150, 7)), limits[:, 0], limits[:, 1])
    configs = np.vstack([rng.uniform(limits[:, 0], limits[:, 1], (100, 7)), near])
    kinds = {"static": 0, "places": 0}
    for mode in (Mode(), Mode("a", "top")):
        for config in configs:
            static, touched = every_pair_contacts(planner, mode, config)
            found = planner.world.sweep(mode, config[None])
            assert found.static == static, (mode, config.tolist())
            if not static:  # when static, the check may stop before all places are seen
                assert found.locations == touched, (mode, config.tolist())
            kinds["static"] += static
            kinds["places"] += bool(touched) and not static
    assert kinds["static"] > 10 and kinds["places"] > 3, kinds


def test_panda_roadmap_same_seed_same_roadmap():
    _, _, first = panda_roadmap(seed=5)
    _, _, again = panda_roadmap(seed=5)
    _, _, other = panda_roadmap(seed=6)
    assert np.array_equal(first.configs, again.configs) and np.array_equal(first.edges, again.edges)
    assert first.anchors == again.anchors
    assert not np.array_equal(first.configs, other.configs)


# --- the roadmap builder on a square decided by hand ------------------------------------------

LIMITS = np.array([[0.0, 1.0], [0.0, 1.0]])
STEP = 0.005  # the check step passed on; the motion checks below are exact


def wall_free(q) -> bool:
    """The unit square without a wall at x in [0.45, 0.55] below y = 0.8."""
    return not (0.45 <= q[0] <= 0.55 and q[1] < 0.8)


def crosses_wall(a, b) -> bool:
    """Whether segment a-b meets the wall rectangle (exact: clip the segment
    to the wall's x range, then compare the y range it spans there)."""
    (x0, y0), (x1, y1) = a, b
    if max(x0, x1) < 0.45 or min(x0, x1) > 0.55:
        return False
    if x0 == x1:
        return min(y0, y1) < 0.8
    t = sorted(((0.45 - x0) / (x1 - x0), (0.55 - x0) / (x1 - x0)))
    t0, t1 = max(t[0], 0.0), min(t[1], 1.0)
    return t0 <= t1 and min(y0 + (y1 - y0) * t0, y0 + (y1 - y0) * t1) < 0.8


def clear_of_wall(a, b) -> bool:
    return not crosses_wall(a, b)


def test_square_roadmap_goes_around_the_wall():
    anchors = {"west": (0.1, 0.1), "east": (0.9, 0.1), "again": (0.1, 0.1)}
    roadmap = build_roadmap(LIMITS, wall_free, clear_of_wall, anchors, 60, 0, STEP)
    assert roadmap.anchors["west"] == roadmap.anchors["again"] == 0 and roadmap.anchors["east"] == 1
    assert np.allclose(roadmap.configs[:2], [(0.1, 0.1), (0.9, 0.1)])
    assert not any(crosses_wall(roadmap.configs[i], roadmap.configs[j]) for i, j in roadmap.edges)
    labels = components(len(roadmap.configs), roadmap.edges)
    assert labels[0] == labels[1]
    assert all(wall_free(q) for q in roadmap.configs)


def test_square_roadmap_is_reproducible_per_seed():
    anchors = {"west": (0.1, 0.1), "east": (0.9, 0.1)}
    first, again, other = (build_roadmap(LIMITS, wall_free, clear_of_wall, anchors, 40, seed, STEP)
                           for seed in (2, 2, 3))
    assert np.array_equal(first.configs, again.configs) and np.array_equal(first.edges, again.edges)
    assert not np.array_equal(first.configs, other.configs)


def test_square_roadmap_with_a_time_limit_grows_until_the_time_is_up():
    """With `seconds`, `size` is not used: the roadmap grows for that long.
    Its milestones are still the seed's sequence, so the size-limited
    roadmap of the same seed is a prefix of it."""
    anchors = {"west": (0.1, 0.1), "east": (0.9, 0.1)}
    start = time.perf_counter()
    timed = build_roadmap(LIMITS, wall_free, clear_of_wall, anchors, 5, 4, STEP, seconds=0.3)
    took = time.perf_counter() - start
    sized = build_roadmap(LIMITS, wall_free, clear_of_wall, anchors, 5, 4, STEP)
    assert 0.3 <= took < 0.3 * 3 + 2.0  # GROWTH = 3 times the limit at most, plus set-up
    assert len(timed.configs) > max(50, len(sized.configs))
    assert np.array_equal(timed.configs[:len(sized.configs)], sized.configs)
    assert not any(crosses_wall(timed.configs[i], timed.configs[j]) for i, j in timed.edges)
    labels = components(len(timed.configs), timed.edges)
    assert labels[timed.anchors["west"]] == labels[timed.anchors["east"]]


def test_unconnectable_anchors_with_a_time_limit_are_named_after_three_times_the_limit():
    def split(q):
        return not 0.2 <= q[0] <= 0.3

    def same_side(a, b):
        return (a[0] < 0.2) == (b[0] < 0.2) and split(a) and split(b)

    start = time.perf_counter()
    with pytest.raises(PlannerError, match=r"not connected to the roadmap after 0.3 s of growth \(\d+ samples"):
        build_roadmap(LIMITS, split, same_side, {"west": (0.1, 0.5), "east": (0.9, 0.5)}, 30, 0, STEP,
                      seconds=0.1)
    assert time.perf_counter() - start >= 0.3
    with pytest.raises(PlannerError, match="time limit must be positive"):
        build_roadmap(LIMITS, wall_free, clear_of_wall, {"ok": (0.1, 0.1)}, 5, 0, STEP, seconds=0.0)


def test_a_check_step_that_is_not_a_positive_number_is_a_planner_error():
    for step in (0.0, -1.0, float("nan")):
        with pytest.raises(PlannerError, match="check step > 0"):
            build_roadmap(LIMITS, wall_free, clear_of_wall, {"ok": (0.1, 0.1)}, 5, 0, step)


def test_unconnectable_anchors_are_named():
    """A wall from bottom to top: the west anchors can never reach the east
    side, where most of the square is."""
    def split(q):
        return not 0.2 <= q[0] <= 0.3

    def same_side(a, b):
        return (a[0] < 0.2) == (b[0] < 0.2) and split(a) and split(b)

    anchors = {"west": (0.1, 0.5), "west too": (0.1, 0.6), "east": (0.9, 0.5)}
    with pytest.raises(PlannerError, match="not connected") as error:
        build_roadmap(LIMITS, split, same_side, anchors, 30, 0, STEP)
    assert "west, west too" in str(error.value) and "east" not in str(error.value).split(":")[-1]


def test_anchor_in_collision_or_outside_the_limits_is_named():
    with pytest.raises(PlannerError, match="in static collision: inside"):
        build_roadmap(LIMITS, wall_free, clear_of_wall, {"ok": (0.1, 0.1), "inside": (0.5, 0.5)}, 5, 0, STEP)
    with pytest.raises(PlannerError, match="outside the joint limits: out"):
        build_roadmap(LIMITS, wall_free, clear_of_wall, {"out": (1.5, 0.1)}, 5, 0, STEP)
