"""symsynth/scene/mesh.py: the one mesh reader of the scene loader and the
ompl-fcl planner, read once per file version, its problems in the reader's words."""

from __future__ import annotations

import textwrap

import numpy as np
import pytest
import trimesh

from symsynth.scene import load_scene
from symsynth.scene.load import SceneError
from symsynth.scene.mesh import MeshError, load_mesh
from symsynth_planners.ompl_fcl.shapes import scene_solid

SCENE = """\
name: meshes
robot: {}
objects:
  b: {mesh: {file: box.obj, scale: 2}, at: l1}
locations:
  l1: {xyz: [0.5, 0.1, 0]}
grasps:
  top: {xyz: [0, 0, 0.1434], rpy: [3.14159265, 0, 0]}
"""


def write_scene(tmp_path):
    path = tmp_path / "scene.yaml"
    path.write_text(textwrap.dedent(SCENE))
    return path


def test_a_scene_with_a_mesh_loads_and_its_file_is_read_once(tmp_path, monkeypatch):
    trimesh.creation.box((0.04, 0.04, 0.06)).export(tmp_path / "box.obj")
    reads = []
    load = trimesh.load
    monkeypatch.setattr(trimesh, "load", lambda *a, **kw: reads.append(a[0]) or load(*a, **kw))
    scene = load_scene(write_scene(tmp_path))
    shape = scene.geometry.shapes["b"]
    assert shape.kind == "mesh" and shape.mesh == tmp_path / "box.obj" and shape.scale == 2
    load_scene(write_scene(tmp_path))
    solid = scene_solid(shape)  # the ompl-fcl planner's solid of it
    assert np.allclose(sorted(2 * solid.half), [0.08, 0.08, 0.12])
    assert reads == [str(tmp_path / "box.obj")]
    # a new version of the file is read again
    trimesh.creation.icosphere(radius=0.05).export(tmp_path / "box.obj")
    assert np.allclose(load_mesh(tmp_path / "box.obj").extents, 0.1)
    assert len(reads) == 2


def test_a_mesh_trimesh_cannot_read_is_reported_in_its_words(tmp_path):
    (tmp_path / "bad.ply").write_text("ply\nformat ascii 1.0\nelement vertex 2\n")  # cut short
    path = write_scene(tmp_path)
    path.write_text(path.read_text().replace("box.obj", "bad.ply"))
    with pytest.raises(SceneError) as caught:
        load_scene(path)
    assert "objects.b.mesh.file: mesh file" in str(caught.value)
    assert "bad.ply' cannot be read by trimesh: IndexError: list index out of range" in str(caught.value)
    with pytest.raises(MeshError, match="cannot be read by trimesh: IndexError"):
        load_mesh(tmp_path / "bad.ply")
