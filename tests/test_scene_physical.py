"""The physical form of a scene file: poses, shapes, the robot, Else samples.

Expected values are computed independently (scipy's rotations, distances
measured here), never read back from what the loader printed."""

import math
import textwrap
from pathlib import Path

import numpy as np
import pybullet_data
import pytest
from scipy.spatial.transform import Rotation

from symsynth.errors import SymsynthWarning
from symsynth.scene import load_scene
from symsynth.scene.geometry import Grasp, Pose
from symsynth.scene.load import SceneError

BASE = """\
name: phys
robot: {}
obstacles:
  table: {box: [1.0, 1.2, 0.04], xyz: [0.35, 0, -0.04]}
objects:
  w: {tags: [block, white], box: [0.04, 0.04, 0.06], at: l1}
  b: {box: [0.04, 0.16, 0.06], xyz: [0.3, 0.3, 0]}
  c: {cylinder: {radius: 0.02, height: 0.05}, at: l2}
locations:
  l1: {xyz: [0.5, 0.1, 0]}
  l2: {xyz: [0.5, -0.1, 0], rpy: [0, 0, 1.5707963]}
else:
  samples: 3
  region: {min: [0.3, -0.4], max: [0.7, 0.4]}
  clearance: 0.12
grasps:
  top: {xyz: [0, 0, 0.1434], rpy: [3.14159265, 0, 0], approach: 0.05}
costs: {per_radian: 10, grab: 4, drop: 6}
planner: {name: pybullet, roadmap_size: 50, check_step: 0.1, seed: 3}
human: {k: 2}
task: "F(at(b, l1))"
"""


def load(tmp_path, text=BASE, name="scene.yaml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return load_scene(path)


def problems(tmp_path, text):
    with pytest.raises(SceneError) as caught:
        load(tmp_path, text)
    return str(caught.value)


def test_physical_scene_is_read(tmp_path):
    scene = load(tmp_path)
    g = scene.geometry
    assert scene.locations == ("l1", "l2") and scene.else_samples == ("e1", "e2", "e3")
    assert scene.grasps == ("top",) and (scene.grab_cost, scene.drop_cost, scene.k) == (4, 6, 2)
    assert [o.at for o in scene.objects] == ["l1", "Else", "l2"]
    assert g.per_radian == 10 and g.planner.name == "pybullet" and g.planner.seed == 3
    assert g.robot.urdf == Path(pybullet_data.getDataPath()) / "franka_panda/panda.urdf"
    assert g.robot.joints == tuple(f"panda_joint{i}" for i in range(1, 8))
    assert len(g.robot.home) == 7 and g.robot.ee_link == "panda_hand"
    assert g.shapes["c"].kind == "cylinder" and g.shapes["c"].radius == 0.02
    assert g.initial == {"b": Pose((0.3, 0.3, 0.0))}
    expected = Rotation.from_euler("xyz", [0, 0, 1.5707963]).as_quat()
    assert np.allclose(g.places["l2"].quat, expected)


def test_the_planners_old_key_resolution_is_read_with_a_located_deprecation_warning(tmp_path):
    """`planner.resolution` was renamed `check_step` (radians between
    collision checks): 'resolution' means only the game's cost unit.  The
    old key still loads, with a warning naming the file, line and key;
    both keys at once are an error."""
    assert load(tmp_path).geometry.planner.check_step == 0.1
    with pytest.warns(SymsynthWarning, match=r"scene\.yaml:19: planner\.resolution: deprecated: rename it check_step"):
        scene = load(tmp_path, BASE.replace("check_step: 0.1", "resolution: 0.25"))
    assert scene.geometry.planner.check_step == 0.25
    assert "planner.resolution: give check_step only (resolution is its old name)" in problems(
        tmp_path, BASE.replace("check_step: 0.1", "check_step: 0.1, resolution: 0.25"))


def test_else_samples_are_seeded_and_keep_their_distance(tmp_path):
    first, again = load(tmp_path).geometry, load(tmp_path, name="again.yaml").geometry
    assert first.places == again.places  # same seed, same samples
    other = load(tmp_path, BASE.replace("seed: 3", "seed: 4"), "other.yaml").geometry
    assert other.places["e2"] != first.places["e2"]
    points = [np.array(p.xyz[:2]) for p in first.places.values()]
    for i, a in enumerate(points):
        for b in points[:i]:
            assert np.linalg.norm(a - b) >= 0.12 - 1e-12
    for name in ("e1", "e2", "e3"):
        x, y, _ = first.places[name].xyz
        assert 0.3 <= x <= 0.7 and -0.4 <= y <= 0.4


def test_an_object_starting_at_else_stands_on_the_first_sample(tmp_path):
    """b starts at Else at (0.3, 0.3): that pose is e1, so the costmap has
    motions to where b really is; the drawn samples keep their distance to it."""
    g = load(tmp_path).geometry
    assert g.places["e1"] == g.initial["b"] == Pose((0.3, 0.3, 0.0))
    for name in ("e2", "e3"):
        assert np.linalg.norm(np.subtract(g.places[name].xyz[:2], (0.3, 0.3))) >= 0.12 - 1e-12
    two = load(tmp_path, BASE.replace("at: l2}", "at: Else, xyz: [0.7, -0.3, 0]}"), "two.yaml")
    assert two.geometry.places["e2"] == Pose((0.7, -0.3, 0.0)) and len(two.else_samples) == 3
    more = load(tmp_path, BASE.replace("samples: 3", "samples: 1"), "more.yaml")
    assert more.else_samples == ("e1",) and more.geometry.places["e1"] == Pose((0.3, 0.3, 0.0))


REGION = """else:
  samples: 3
  region: {min: [0.3, -0.4], max: [0.7, 0.4]}
  clearance: 0.12
"""


def test_an_object_at_else_off_the_given_samples_is_reported(tmp_path):
    """b starts at Else at (0.3, 0.3): given samples must include that pose,
    or the costmap has no motion to where b stands."""
    assert REGION in BASE
    off = problems(tmp_path, BASE.replace(REGION, "else_samples:\n  e1: {xyz: [0.6, 0.3, 0]}\n"))
    assert ("scene.yaml:7: objects.b.xyz: b starts at Else at (0.300, 0.300, 0.000), which is not one of "
            "else_samples (e1); add its pose to else_samples") in off
    turned = problems(tmp_path, BASE.replace(REGION, "else_samples:\n  e1: {xyz: [0.3, 0.3, 0], rpy: [0, 0, 1]}\n"))
    assert "objects.b.xyz: b starts at Else at (0.300, 0.300, 0.000), which is not one of else_samples" in turned
    none = problems(tmp_path, BASE.replace(REGION, ""))
    assert "objects.b.xyz: b starts at Else at (0.300, 0.300, 0.000), which is not an Else sample: the scene " \
           "has none" in none
    given = load(tmp_path, BASE.replace(REGION, "else_samples:\n  e1: {xyz: [0.6, 0.3, 0]}\n"
                                                "  e2: {xyz: [0.30, 0.3, 0.0]}\n"), "given.yaml")
    assert given.else_samples == ("e1", "e2") and given.geometry.places["e2"] == given.geometry.initial["b"]


def test_too_many_else_samples_is_reported(tmp_path):
    text = BASE.replace("samples: 3", "samples: 40")
    assert "could not place 40 samples" in problems(tmp_path, text)


def test_pose_algebra_matches_scipy():
    a = Pose.from_rpy((0.1, -0.2, 0.3), (0.4, -1.1, 2.5))
    b = Pose.from_rpy((1.0, 2.0, -0.5), (-2.0, 0.3, 0.2))
    ra = Rotation.from_euler("xyz", [0.4, -1.1, 2.5])
    rb = Rotation.from_euler("xyz", [-2.0, 0.3, 0.2])
    both = a @ b
    assert np.allclose(both.xyz, ra.apply([1.0, 2.0, -0.5]) + [0.1, -0.2, 0.3])
    assert math.isclose(abs(np.dot(both.quat, (ra * rb).as_quat())), 1.0, abs_tol=1e-9)
    assert np.allclose((a @ a.inverse()).matrix(), np.eye(4))


def test_angle_between_poses_is_scipys_relative_rotation_angle():
    a = Pose.from_rpy((0.0, 0.0, 0.0), (0.4, -1.1, 2.5))
    b = Pose.from_rpy((1.0, 2.0, -0.5), (-2.0, 0.3, 0.2))
    ra = Rotation.from_euler("xyz", [0.4, -1.1, 2.5])
    rb = Rotation.from_euler("xyz", [-2.0, 0.3, 0.2])
    expected = (ra.inv() * rb).magnitude()
    assert math.isclose(a.angle_to(b), expected, abs_tol=1e-9)
    assert math.isclose(b.angle_to(a), expected, abs_tol=1e-9)
    flipped = Pose(b.xyz, tuple(-2.0 * v for v in b.quat))  # the same orientation, not a unit quaternion
    assert math.isclose(a.angle_to(flipped), expected, abs_tol=1e-9)
    assert math.isclose(a.angle_to(Pose((5.0, 0.0, 0.0), a.quat)), 0.0, abs_tol=1e-7)  # position plays no part


def test_grasp_pre_image_backs_off_along_the_hand_axis():
    down = Grasp("top", Pose.from_rpy((0, 0, 0.15), (math.pi, 0, 0)), approach=0.05)
    assert np.allclose(down.pre_image().xyz, (0, 0, 0.20))  # hand points down: back off upwards
    side = Grasp("side", Pose.from_rpy((-0.1, 0, 0.04), (0, math.pi / 2, 0)), approach=0.04)
    assert np.allclose(side.pre_image().xyz, (-0.14, 0, 0.04))


def test_bundled_physical_scenes_load():
    for name in ("arch", "line"):
        scene = load_scene(f"scenes/{name}.yaml")
        assert scene.geometry is not None and scene.k == 5 and scene.task


@pytest.mark.parametrize("edit, expected", [
    (("robot: {}", "robot: {urdf: nowhere.urdf}"),
     "scene.yaml:2: robot.urdf: URDF 'nowhere.urdf' not found"),
    (("robot: {}", "robot: {home: [0, 1]}"),
     "robot.home: expected 7 joint values"),
    (("robot: {}", "robot: {ee_link: paw}"),
     "robot.ee_link: link 'paw' not in panda.urdf"),
    (("robot: {}", "robot: {joints: [panda_joint1, elbow]}"),
     "joint 'elbow' is not a movable joint"),
    (("box: [0.04, 0.04, 0.06], at: l1", "at: l1"),
     "scene.yaml:6: objects.w: expected exactly one shape: box, cylinder, mesh"),
    (("l1: {xyz: [0.5, 0.1, 0]}", "l1: {xyz: [0.5, 0.1]}"),
     "scene.yaml:10: locations.l1.xyz: [0.5, 0.1] is too short"),
    (("top: {xyz", "top: {xz"), "grasps.top: Additional properties are not allowed"),
    (("check_step: 0.1", "check_step: 0"), "planner.check_step: 0 is less than or equal"),
    (("roadmap_size: 50,", "roadmap_size: 50, seconds: 2,"),
     "scene.yaml:19: planner.seconds: give the roadmap either a size (roadmap_size) or a time limit (seconds), not both"),
    (("costs: {per_radian: 10, grab: 4, drop: 6}", "costs: {per_radian: -1}"),
     "costs.per_radian: -1 is less than the minimum of 0"),
    (("w: {tags: [block, white], box", "w: {tags: [block, white], mesh: {file: no.obj}, box"),
     "objects.w: expected exactly one shape"),
])
def test_physical_problems_name_file_line_and_key(tmp_path, edit, expected):
    old, new = edit
    assert old in BASE
    assert expected in problems(tmp_path, BASE.replace(old, new))


@pytest.mark.parametrize("edit, expected", [
    # an endless roadmap growth, an OMPL traceback, a robot nowhere
    (("roadmap_size: 50,", "seconds: .inf,"),
     "scene.yaml:19: planner.seconds: expected a finite number, found .inf"),
    (("check_step: 0.1", "check_step: .nan"),
     "scene.yaml:19: planner.check_step: expected a finite number, found .nan"),
    (("robot: {}", "robot: {home: [0, .nan, 0, -2.356, 0, 1.571, 0.785]}"),
     "scene.yaml:2: robot.home.1: expected a finite number, found .nan"),
    (("l1: {xyz: [0.5, 0.1, 0]}", "l1: {xyz: [0.5, -.inf, 0]}"),
     "scene.yaml:10: locations.l1.xyz.1: expected a finite number, found -.inf"),
    (("costs: {per_radian: 10, grab: 4, drop: 6}", "costs: {per_radian: 10, grab: .inf, drop: 6}"),
     "scene.yaml:18: costs.grab: expected a finite number, found .inf"),
])
def test_numbers_that_are_not_finite_are_reported(tmp_path, edit, expected):
    old, new = edit
    assert old in BASE
    found = problems(tmp_path, BASE.replace(old, new))
    assert expected in found and "1 problem in the scene" in found


def test_a_number_the_schema_refuses_is_reported_once(tmp_path):
    found = problems(tmp_path, BASE.replace("roadmap_size: 50, check_step: 0.1",
                                            "roadmap_size: .inf, check_step: .nan"))
    assert "2 problems in the scene" in found
    assert "planner.roadmap_size: expected integer, found inf" in found
    assert "planner.check_step: expected a finite number, found .nan" in found


def test_an_abstract_scene_with_an_infinite_cost_is_reported(tmp_path):
    text = "name: a\nobjects: {w: {at: l1}}\nlocations: [l1]\nprimitives: {grab: .inf}\n"
    assert "scene.yaml:4: primitives.grab: expected a finite number, found .inf" in problems(tmp_path, text)


def test_missing_mesh_file_is_reported(tmp_path):
    text = BASE.replace("box: [0.04, 0.16, 0.06]", "mesh: {file: meshes/lintel.obj}")
    assert "objects.b.mesh.file: mesh file" in problems(tmp_path, text)


def test_a_file_that_is_no_mesh_is_reported_before_any_planner_reads_it(tmp_path):
    # pybullet's collision shapes crash the interpreter on such a file
    (tmp_path / "junk.stl").write_bytes(b"garbage, not a mesh\n\x00\x01")
    text = BASE.replace("box: [0.04, 0.16, 0.06]", "mesh: {file: junk.stl}")
    assert "objects.b.mesh.file: mesh file" in problems(tmp_path, text)
    assert "junk.stl' has no triangles" in problems(tmp_path, text)


def test_list_of_locations_in_a_physical_scene_explains_itself(tmp_path):
    text = BASE.replace("locations:\n  l1: {xyz: [0.5, 0.1, 0]}\n  l2: {xyz: [0.5, -0.1, 0], "
                        "rpy: [0, 0, 1.5707963]}", "locations: [l1, l2]")
    assert "locations: expected a mapping from names to poses" in problems(tmp_path, text)


def test_named_poses_in_an_abstract_scene_explain_themselves(tmp_path):
    text = "name: a\nobjects: {w: {at: l1}}\nlocations: {l1: {xyz: [0, 0, 0]}}\n"
    assert "named poses are for physical scenes" in problems(tmp_path, text)
