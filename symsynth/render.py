"""A picture of a physical scene: headless PyBullet (TinyRenderer) plus
labels drawn with Pillow.

The robot stands at `config` (or home), the static obstacles are grey, each
object stands at its initial place (a location of interest, or its Else
pose), and every place is marked by a thin square on the table, green for a
location of interest and orange for an Else sample, labelled with its name
(the label's box lies above and to the right of the place, so the place
itself stays visible).  An object is coloured by its first tag that names a
colour in `COLOURS`, else by a palette in object order.

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
from symsynth import bullet
from symsynth.bullet import pybullet as p
from PIL import Image, ImageDraw, ImageFont

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
BACKGROUND = (255, 255, 255)


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


def default_camera(scene: Scene, width: int, height: int) -> Camera:
    """Looking at the centre of the places (or 40 cm in front of the robot)
    from the front-right and above, 1.9 m away."""
    geometry = scene.geometry
    places = [pose.xyz for pose in geometry.places.values()]
    centre = np.mean(places, axis=0) if places else np.array(geometry.robot.base.xyz) + [0.4, 0.0, 0.0]
    target = (float(centre[0]) - 0.1, float(centre[1]), 0.2)
    yaw, pitch, distance = math.radians(35.0), math.radians(40.0), 1.9
    eye = (target[0] + distance * math.cos(pitch) * math.cos(yaw),
           target[1] + distance * math.cos(pitch) * math.sin(yaw),
           target[2] + distance * math.sin(pitch))
    return Camera(eye=eye, target=target, width=width, height=height)


def render_scene(scene: Scene, path: Path | str, *, width: int = 800, height: int = 600,
                 config: Sequence[float] | None = None, labels: bool = True,
                 camera: Camera | None = None) -> Camera:
    """Write a PNG picture of `scene` to `path`; returns the camera used."""
    if scene.geometry is None:
        raise SymsynthError(f"scene {scene.name!r} has no geometry to render (not a physical scene)")
    if width < 1 or height < 1:
        raise SymsynthError(f"image size must be positive, got {width}x{height}")
    camera = camera or default_camera(scene, width, height)
    camera = Camera(camera.eye, camera.target, camera.up, camera.fov, width, height, camera.near, camera.far)
    client = bullet.client()
    try:
        _build(client, scene, config)
        _, _, rgba, _, _ = client.getCameraImage(width, height, camera.view(), camera.projection(),
                                                 renderer=p.ER_TINY_RENDERER, shadow=0,
                                                 lightDirection=(0.4, 0.6, 1.0))
    finally:
        client.disconnect()
    image = Image.fromarray(np.reshape(np.asarray(rgba, dtype=np.uint8), (height, width, 4))[:, :, :3])
    if labels:
        _label(image, scene, camera)
    image.save(path, format="PNG")
    return camera


def _build(client, scene: Scene, config: Sequence[float] | None) -> None:
    geometry = scene.geometry
    robot = geometry.robot
    body = client.loadURDF(str(robot.urdf), basePosition=robot.base.xyz, baseOrientation=robot.base.quat,
                           useFixedBase=True)
    if body < 0:
        raise SymsynthError(f"pybullet could not load the robot URDF {robot.urdf}")
    joints = {client.getJointInfo(body, j)[1].decode(): j for j in range(client.getNumJoints(body))}
    values = tuple(robot.home if config is None else config)
    names = robot.joints or tuple(n for n, j in joints.items()
                                  if client.getJointInfo(body, j)[2] != p.JOINT_FIXED and n not in dict(robot.fixed))
    if len(values) != len(names):
        raise SymsynthError(f"a configuration has {len(values)} values; the robot has {len(names)} joints")
    for name, value in list(zip(names, values)) + list(robot.fixed):
        client.resetJointState(body, joints[name], float(value))
    for obstacle in geometry.obstacles:
        _visual(client, obstacle.shape, obstacle.pose, OBSTACLE)
    for k, spec in enumerate(scene.objects):
        pose = geometry.initial.get(spec.name) if spec.at == ELSE else geometry.places.get(spec.at)
        if pose is not None and spec.name in geometry.shapes:
            _visual(client, geometry.shapes[spec.name], pose, _colour(spec.tags, k))
    for name, pose in geometry.places.items():
        colour = LOCATION_MARK if name in scene.locations else ELSE_MARK
        mark = Shape("box", size=(MARK_SIZE, MARK_SIZE, MARK_THICKNESS))
        _visual(client, mark, pose @ Pose((0.0, 0.0, 0.0005)), colour)


def _visual(client, shape: Shape, pose: Pose, colour: RGBA) -> int:
    if shape.kind == "box":
        visual = client.createVisualShape(p.GEOM_BOX, halfExtents=[s / 2 for s in shape.size], rgbaColor=colour)
    elif shape.kind == "cylinder":
        visual = client.createVisualShape(p.GEOM_CYLINDER, radius=shape.radius, length=shape.height,
                                          rgbaColor=colour)
    else:
        visual = client.createVisualShape(p.GEOM_MESH, fileName=str(shape.mesh), meshScale=[shape.scale] * 3,
                                          rgbaColor=colour)
    centre = pose @ shape.centre_offset()
    return client.createMultiBody(baseMass=0, baseVisualShapeIndex=visual, basePosition=centre.xyz,
                                  baseOrientation=centre.quat)


def _colour(tags: frozenset[str], index: int) -> RGBA:
    for tag in sorted(tags):
        if tag in COLOURS:
            return COLOURS[tag]
    return PALETTE[index % len(PALETTE)]


def _label(image: Image.Image, scene: Scene, camera: Camera) -> None:
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default(size=max(10, image.height // 40))
    for name, pose in scene.geometry.places.items():
        u, v = camera.project(pose.xyz)
        if not (0 <= u < image.width and 0 <= v < image.height):
            continue
        left, top, right, bottom = draw.textbbox((0, 0), name, font=font)
        x, y = u + 6, v - 6 - (bottom - top) - 4  # box above-right of the place
        draw.rectangle((x - 2, y - 2, x + right - left + 2, y + bottom - top + 4), fill=(255, 255, 255),
                       outline=(60, 60, 60))
        draw.text((x - left, y - top), name, fill=(0, 0, 0), font=font)
        draw.line((u + 3, v - 3, x - 2, y + bottom - top + 4), fill=(60, 60, 60))  # the place stays visible
