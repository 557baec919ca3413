"""symsynth/bullet.py: a mesh or URDF pybullet cannot read is one message
naming the file, not pybullet's bare `pybullet.error` traceback."""

from __future__ import annotations

import pytest
import trimesh

from symsynth import bullet
from symsynth.errors import SymsynthError
from symsynth.scene.geometry import Pose, Robot, Shape


@pytest.fixture
def client():
    client = bullet.client()
    yield client
    client.disconnect()


def test_a_mesh_trimesh_reads_and_pybullet_does_not_is_named(tmp_path, client):
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    for suffix in (".obj", ".stl"):  # what pybullet reads
        box.export(tmp_path / f"box{suffix}")
        shape = Shape("mesh", mesh=tmp_path / f"box{suffix}")
        assert bullet.collision_shape(client, shape) >= 0
        assert bullet.visual_shape(client, shape, (1, 1, 1, 1)) >= 0
    for suffix in (".ply", ".glb"):
        path = tmp_path / f"box{suffix}"
        box.export(path)
        assert len(trimesh.load(path, force="mesh").faces) == 12
        shape = Shape("mesh", mesh=path)
        for make in (lambda: bullet.collision_shape(client, shape),
                     lambda: bullet.collision_shape(client, shape, concave=True),
                     lambda: bullet.visual_shape(client, shape, (1, 1, 1, 1))):
            with pytest.raises(SymsynthError, match=f"cannot read the mesh {path}: it reads .obj and .stl"):
                make()


def test_an_obj_pybullet_cannot_parse_is_named(tmp_path, client):
    path = tmp_path / "empty.obj"
    path.write_text("# no vertices\n")
    with pytest.raises(SymsynthError, match=f"could not load the mesh {path}: createCollisionShape failed"):
        bullet.collision_shape(client, Shape("mesh", mesh=path))


def test_a_urdf_pybullet_cannot_load_is_named(tmp_path, client):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text("<robot name='r'><link name='a'/><joint name='j' type='revolute'/></robot>\n")
    robot = Robot(urdf=urdf, base=Pose(), home=(0.0,), ee_link="a")
    with pytest.raises(SymsynthError, match=f"pybullet could not load the robot URDF {urdf}: Cannot load URDF"):
        bullet.load_robot(client, robot)
