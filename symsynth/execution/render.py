"""A picture of a physical scene: headless PyBullet (TinyRenderer) plus
labels drawn with Pillow.

The robot stands at home, the static obstacles are grey, each
object stands at its initial place (a location of interest, or its Else
pose), and every place is marked by a thin square on the table, green for a
location of interest and orange for an Else sample, labelled with its name
(the label's box lies above and to the right of the place, so the place
itself stays visible).  An object is coloured by its first tag that names a
colour in `execution.world.COLOURS`, else by a palette in object order.

The camera looks at the centre of the places from the front-right, far
enough to see the robot; `render_scene` returns it (`Camera`) so that a
caller can project its own points: `Camera.project` maps a world point to
pixel coordinates (x to the right, y down, (0, 0) the top-left pixel's
corner), the same projection the renderer used.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from symsynth.bullet import pybullet as p
from symsynth.errors import SymsynthError
from symsynth.files import atomic_output
from symsynth.execution.world import SimWorld
from symsynth.scene.model import Scene, geometry_of


@dataclass(frozen=True)
class Camera:
    """A pinhole camera: `fov` is the vertical field of view in degrees."""

    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    up: tuple[float, float, float] = (0.0, 0.0, 1.0)
    fov: float = 45.0
    width: int = 800
    height: int = 600
    near: float = 0.05
    far: float = 20.0

    def view(self) -> list[float]:
        return p.computeViewMatrix(self.eye, self.target, self.up)

    def projection(self) -> list[float]:
        return p.computeProjectionMatrixFOV(self.fov, self.width / self.height, self.near, self.far)

    def project(self, point: Sequence[float]) -> tuple[float, float]:
        """Pixel coordinates of a world point (through pybullet's matrices,
        stored column-major)."""
        view = np.array(self.view()).reshape(4, 4).T
        projection = np.array(self.projection()).reshape(4, 4).T
        clip = projection @ view @ np.append(np.asarray(point, float), 1.0)
        x, y = clip[0] / clip[3], clip[1] / clip[3]
        return (x + 1) / 2 * self.width, (1 - y) / 2 * self.height


def default_camera(scene: Scene, width: int, height: int, distance: float = 1.9) -> Camera:
    """Looking at the centre of the places (or 40 cm in front of the robot)
    from the front-right and above, `distance` metres away."""
    geometry = geometry_of(scene)
    places = [pose.xyz for pose in geometry.places.values()]
    centre = np.mean(places, axis=0) if places else np.array(geometry.robot.base.xyz) + [0.4, 0.0, 0.0]
    target = (float(centre[0]) - 0.1, float(centre[1]), 0.2)
    yaw, pitch = math.radians(35.0), math.radians(40.0)
    eye = (target[0] + distance * math.cos(pitch) * math.cos(yaw),
           target[1] + distance * math.cos(pitch) * math.sin(yaw),
           target[2] + distance * math.sin(pitch))
    return Camera(eye=eye, target=target, width=width, height=height)


def render_scene(scene: Scene, path: Path | str, *, width: int = 800, height: int = 600,
                 labels: bool = True) -> Camera:
    """Write a PNG picture of `scene` to `path`; returns the camera used."""
    if scene.geometry is None:
        raise SymsynthError(f"scene {scene.name!r} has no geometry to render (not a physical scene)")
    if width < 1 or height < 1:
        raise SymsynthError(f"image size must be positive, got {width}x{height}")
    camera = default_camera(scene, width, height)
    world = SimWorld(scene)
    try:
        image = snapshot(world, camera)
    finally:
        world.close()
    if labels:
        label_places(image, scene, camera)
    with atomic_output(path, "image") as temporary:
        image.save(temporary, format="PNG")
    return camera


def snapshot(world: SimWorld, camera: Camera) -> Image.Image:
    """The world as `camera` sees it (TinyRenderer: no display, no GPU)."""
    _, _, rgba, _, _ = world.client.getCameraImage(camera.width, camera.height, camera.view(),
                                                   camera.projection(), renderer=p.ER_TINY_RENDERER,
                                                   shadow=0, lightDirection=(0.4, 0.6, 1.0))
    pixels = np.reshape(np.asarray(rgba, dtype=np.uint8), (camera.height, camera.width, 4))
    return Image.fromarray(pixels[:, :, :3])


def label_places(image: Image.Image, scene: Scene, camera: Camera) -> None:
    """Each place's name in a box above and to its right, with a leader line."""
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default(size=max(10, image.height // 40))
    for name, pose in geometry_of(scene).places.items():
        u, v = camera.project(pose.xyz)
        if not (0 <= u < image.width and 0 <= v < image.height):
            continue
        left, top, right, bottom = draw.textbbox((0, 0), name, font=font)
        x, y = u + 6, v - 6 - (bottom - top) - 4  # box above-right of the place
        draw.rectangle((x - 2, y - 2, x + right - left + 2, y + bottom - top + 4), fill=(255, 255, 255),
                       outline=(60, 60, 60))
        draw.text((x - left, y - top), name, fill=(0, 0, 0), font=font)
        draw.line((u + 3, v - 3, x - 2, y + bottom - top + 4), fill=(60, 60, 60))  # the place stays visible
