"""A picture of a physical scene: headless PyBullet (TinyRenderer) plus
labels drawn with Pillow.

The robot stands at home, the static obstacles are grey, each
object stands at its initial place (a location of interest, or its Else
pose), and every place is marked by a thin square on the table, green for a
location of interest and orange for an Else sample, labelled with its name
in a white box, and every object is labelled with its name in a dark box
(each box beside its point, never on it, so the place stays visible, and
moved round its point rather than over another label).  An object is coloured by its first tag that names a
colour in `execution.world.COLOURS`, else by a palette in object order.

The camera looks at the centre of the places from the front-right, far
enough to see the robot; `render_scene` returns it (`Camera`) so that a
caller can project its own points: `Camera.project` maps a world point to
pixel coordinates (x to the right, y down, (0, 0) the top-left pixel's
corner), the same projection the renderer used.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from symsynth.bullet import pybullet as p
from symsynth.errors import SymsynthError
from symsynth.files import atomic_output
from symsynth.execution.world import SimWorld
from symsynth.planning.support import bounds
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
    from above (40 degrees down), `distance` metres away: from the
    front-right (35 degrees) unless the static obstacles hide more of the
    places open to the sky from there than from another side (`YAWS`, in
    that order; on the shelf the board hides `out`, where the pulled block
    goes, from the front-right, and from the side it does not; `under`,
    beneath the board, is not counted)."""
    geometry = geometry_of(scene)
    places = [pose.xyz for pose in geometry.places.values()]
    centre = np.mean(places, axis=0) if places else np.array(geometry.robot.base.xyz) + [0.4, 0.0, 0.0]
    target = (float(centre[0]) - 0.1, float(centre[1]), 0.2)
    pitch = math.radians(40.0)
    boxes = [bounds(body.shape, body.pose) for body in geometry.obstacles]
    marks = [np.asarray(xyz, float) + [0.0, 0.0, MARK_HEIGHT] for xyz in places]
    marks = [m for m in marks if not any(_crosses(m + [0.0, 0.0, distance], m, box) for box in boxes)]
    best: tuple[int, tuple[float, float, float]] | None = None
    for yaw in map(math.radians, YAWS):
        eye = (target[0] + distance * math.cos(pitch) * math.cos(yaw),
               target[1] + distance * math.cos(pitch) * math.sin(yaw),
               target[2] + distance * math.sin(pitch))
        hidden = sum(any(_crosses(np.asarray(eye), mark, box) for box in boxes) for mark in marks)
        if best is None or hidden < best[0]:
            best = (hidden, eye)
    assert best is not None  # YAWS is not empty
    return Camera(eye=best[1], target=target, width=width, height=height)


YAWS = (35.0, -35.0, 90.0, -90.0)  # degrees about z, from +x: the sides a camera looks from
MARK_HEIGHT = 0.03  # metres above a place: the point that must be seen


def _crosses(start: np.ndarray, end: np.ndarray, box: tuple[np.ndarray, np.ndarray]) -> bool:
    """Whether the segment from `start` to `end` passes through the
    axis-aligned `box` (low, high) before reaching `end` (the slab method)."""
    low, high = box
    direction = end - start
    enter, leave = 0.0, 1.0 - 1e-9
    for axis in range(3):
        if abs(direction[axis]) < 1e-12:
            if not low[axis] <= start[axis] <= high[axis]:
                return False
            continue
        a, b = sorted(((low[axis] - start[axis]) / direction[axis], (high[axis] - start[axis]) / direction[axis]))
        enter, leave = max(enter, a), min(leave, b)
        if enter > leave:
            return False
    return True


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
        objects = {name: pose.xyz for name, pose in world.poses.items()}
    finally:
        world.close()
    if labels:
        label_places(image, scene, camera, objects)
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


Box = tuple[float, float, float, float]  # left, top, right, bottom in pixels

#: Where a label's box may go around its point, tried in this order: above
#: right (the first choice), above left, below right, below left, then the
#: same twice as far; the first that overlaps no label drawn yet is taken.
_SPOTS = [(sx * d, sy * d) for d in (1, 3) for sx, sy in ((1, -1), (-1, -1), (1, 1), (-1, 1))]


def label_places(image: Image.Image, scene: Scene, camera: Camera,
                 objects: Mapping[str, Sequence[float]] | None = None) -> list[tuple[str, Box]]:
    """Each place's name in a white box beside it, and each object's name
    (at `objects`, world points) in a dark one, with a leader line; a box
    moves round its point rather than cover another label or a labelled
    point.  Returns the boxes drawn."""
    draw = ImageDraw.Draw(image)
    font = ImageFont.load_default(size=max(10, image.height // 40))
    taken: list[Box] = []
    items = [(name, pose.xyz, False) for name, pose in geometry_of(scene).places.items()]
    items += [(name, (x, y, z + 0.06), True) for name, (x, y, z) in (objects or {}).items()]  # above its top
    shown = [(name, camera.project(point), is_object) for name, point, is_object in items]
    shown = [(name, (u, v), is_object) for name, (u, v), is_object in shown
             if 0 <= u < image.width and 0 <= v < image.height]
    taken += [(u - 4, v - 4, u + 4, v + 4) for _, (u, v), _ in shown]  # no box on a place or an object
    drawn: list[tuple[str, Box]] = []
    for name, (u, v), is_object in shown:
        left, top, right, bottom = draw.textbbox((0, 0), name, font=font)
        w, h = right - left + 4, bottom - top + 6
        box = _free_spot(u, v, w, h, taken, image.size)
        taken.append(box)
        x0, y0, x1, y1 = box
        near_x = x0 if x0 > u else x1  # the leader ends at the box's corner nearest the point
        near_y = y1 if y1 < v else y0
        sx, sy = (1 if near_x > u else -1), (1 if near_y > v else -1)
        draw.line((u + 3 * sx, v + 3 * sy, near_x, near_y), fill=(60, 60, 60))  # the point stays visible
        fill, ink = ((40, 40, 90), (255, 255, 255)) if is_object else ((255, 255, 255), (0, 0, 0))
        draw.rectangle(box, fill=fill, outline=(60, 60, 60))
        draw.text((x0 + 2 - left, y0 + 2 - top), name, fill=ink, font=font)
        drawn.append((name, box))
    return drawn


def _free_spot(u: float, v: float, w: float, h: float, taken: list[Box], size: tuple[int, int]) -> Box:
    """The first of `_SPOTS` for a w x h box at (u, v) that stays in the
    image and overlaps no box in `taken` (the first choice if none does)."""
    gap = 6
    spots = []
    for dx, dy in _SPOTS:
        x0 = u + dx * gap if dx > 0 else u + dx * gap - w
        y0 = v + dy * gap if dy > 0 else v + dy * gap - h
        spots.append((x0, y0, x0 + w, y0 + h))
    inside = [b for b in spots if b[0] >= 0 and b[1] >= 0 and b[2] < size[0] and b[3] < size[1]] or spots
    for box in inside:
        if not any(box[0] < t[2] and t[0] < box[2] and box[1] < t[3] and t[1] < box[3] for t in taken):
            return box
    return inside[0]
