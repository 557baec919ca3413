"""The scene picture: a PNG of the asked size, not blank, whose place
markers are where an independent pinhole projection puts them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from PIL import Image

from symsynth.errors import SymsynthError
from symsynth.execution.render import Camera, render_scene
from symsynth.scene.geometry import Pose
from symsynth.scene.model import ObjectSpec, Scene
from support.paper import SCENES
from symsynth.testing.planner import BLOCK, physical_scene

WIDTH, HEIGHT = 320, 240


def picture_scene() -> Scene:
    """l1 and the Else sample e1 are empty; l2 holds a block; w stands at Else."""
    base = physical_scene("picture", {"b": ("l2", BLOCK)}, {"l1": (0.5, 0.25, 0), "l2": (0.5, -0.2, 0)})
    geometry = base.geometry
    places = dict(geometry.places) | {"e1": Pose((0.35, -0.4, 0.0))}
    geometry = type(geometry)(robot=geometry.robot, obstacles=geometry.obstacles,
                              shapes=dict(geometry.shapes) | {"w": BLOCK}, places=places,
                              grasps=geometry.grasps, initial={"w": Pose((0.65, 0.0, 0.0))})
    objects = base.objects + (ObjectSpec("w", frozenset({"w", "white"}), "Else"),)
    return Scene("picture", objects, base.locations, ("e1",), base.grasps, geometry=geometry)


def pinhole(camera: Camera, point) -> tuple[float, float]:
    """Pixel coordinates by a look-at pinhole camera, written out here."""
    eye, target, up = (np.array(v, float) for v in (camera.eye, camera.target, camera.up))
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    true_up = np.cross(right, forward)
    d = np.asarray(point, float) - eye
    x, y, z = d @ right, d @ true_up, d @ forward
    focal = (camera.height / 2) / math.tan(math.radians(camera.fov) / 2)
    return camera.width / 2 + focal * x / z, camera.height / 2 - focal * y / z


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    path = tmp_path_factory.mktemp("render") / "scene.png"
    camera = render_scene(picture_scene(), path, width=WIDTH, height=HEIGHT)
    return path, camera


def test_png_of_the_asked_size_and_not_blank(rendered):
    path, _ = rendered
    with Image.open(path) as image:
        assert image.format == "PNG" and image.size == (WIDTH, HEIGHT)
        pixels = np.asarray(image.convert("RGB"), float)
    assert pixels.std() > 20  # a blank or one-colour picture has (almost) none


def test_the_camera_projects_as_a_pinhole(rendered):
    _, camera = rendered
    for point in [(0.5, 0.25, 0.0), (0.35, -0.4, 0.0), (0.0, 0.0, 0.5), (0.8, 0.3, 0.2)]:
        assert camera.project(point) == pytest.approx(pinhole(camera, point), abs=0.5)


def test_markers_are_where_the_pinhole_puts_them(rendered):
    path, camera = rendered
    pixels = np.asarray(Image.open(path).convert("RGB"), int)
    u, v = pinhole(camera, (0.5, 0.25, 0.0))  # l1: a location of interest, empty
    r, g, b = pixels[int(v), int(u)]
    assert g > r + 60 and g > b + 60, (r, g, b)  # green
    u, v = pinhole(camera, (0.35, -0.4, 0.0))  # e1: an Else sample, empty
    r, g, b = pixels[int(v), int(u)]
    assert r > g + 40 and g > b + 40, (r, g, b)  # orange
    u, v = pinhole(camera, (0.5, 0.4, 0.0))  # bare table 15 cm beside l1: grey
    r, g, b = pixels[int(v), int(u)]
    assert max(r, g, b) - min(r, g, b) < 30, (r, g, b)


def test_labels_are_drawn_beside_the_places(rendered, tmp_path):
    path, camera = rendered
    bare = tmp_path / "bare.png"
    render_scene(picture_scene(), bare, width=WIDTH, height=HEIGHT, labels=False)
    labelled, plain = (np.asarray(Image.open(p).convert("RGB"), int) for p in (path, bare))
    changed = np.argwhere(np.any(labelled != plain, axis=2))  # (row, column) pairs
    for place in ((0.5, 0.25, 0.0), (0.35, -0.4, 0.0)):
        u, v = pinhole(camera, place)
        near = changed[(np.abs(changed[:, 1] - u) < 40) & (np.abs(changed[:, 0] - v) < 30)]
        assert len(near) > 20, place
        assert np.array_equal(labelled[int(v), int(u)], plain[int(v), int(u)])  # the place stays visible


def test_abstract_scene_is_refused(tmp_path):
    scene = Scene("abstract", (), ("l1",), (), ("top",))
    with pytest.raises(SymsynthError, match="no geometry"):
        render_scene(scene, tmp_path / "x.png")


def test_labels_name_the_objects_and_cover_no_other_label_or_point():
    """On the shelf, `out` (on the shelf top) and `under` (below it) project
    a few pixels apart: their labels overlapped, and the objects had none."""
    from PIL import Image as PILImage

    from symsynth.execution.render import default_camera, label_places
    from symsynth.scene import load_scene

    scene = load_scene(SCENES / "shelf.yaml")
    places = scene.geometry.places
    objects = {o.name: places[o.at].xyz for o in scene.objects if o.at in places}
    camera = default_camera(scene, 800, 600)
    drawn = label_places(PILImage.new("RGB", (800, 600)), scene, camera, objects)
    assert {name for name, _ in drawn} == set(places) | set(objects)
    points = [camera.project(p.xyz) for p in places.values()] + [camera.project(xyz) for xyz in objects.values()]
    for i, (name, (x0, y0, x1, y1)) in enumerate(drawn):
        for other, (a0, b0, a1, b1) in drawn[i + 1:]:
            assert x1 <= a0 or a1 <= x0 or y1 <= b0 or b1 <= y0, (name, other)
        assert not any(x0 <= u <= x1 and y0 <= v <= y1 for u, v in points), name


def test_the_camera_sees_every_place_open_to_the_sky_where_one_side_can():
    """From the front-right the shelf's board hides `out`, where the pulled
    block goes: the camera looks from the side instead, and a ray from its
    eye (PyBullet's ray test, in the scene's world) reaches `out` and every
    other place not beneath the board without meeting an obstacle.  The
    line, with nothing to hide its places, keeps the front-right view."""
    from symsynth.execution.render import default_camera
    from symsynth.execution.world import SimWorld
    from symsynth.scene import load_scene

    for name, sideways in (("shelf", True), ("line", False)):
        scene = load_scene(SCENES / f"{name}.yaml")
        camera = default_camera(scene, 480, 360)
        world = SimWorld(scene)
        try:
            for place, pose in scene.geometry.places.items():
                if place == "under":
                    continue
                mark = (pose.xyz[0], pose.xyz[1], pose.xyz[2] + 0.03)
                hit = world.client.rayTest(camera.eye, mark)[0]
                assert hit[0] not in world.obstacles, (name, place)
        finally:
            world.close()
        assert (abs(camera.eye[0] - camera.target[0]) < 0.01) == sideways, name
