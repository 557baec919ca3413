"""A planner for a point robot in the unit square, as a test double.

Small enough to reason about by hand, yet a real implementation of the
`Planner` protocol: the configuration is the end-effector's (x, y); a static
obstacle is its box's footprint; the location obstacle at a place is a disc
of radius `PLACE_RADIUS` around it; holding an object makes the robot a disc
of radius `HELD_RADIUS`.  The roadmap is an 8-connected grid plus the anchors,
each joined to its nearest grid vertices.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from symsynth.planning.protocol import Config, Contacts, Mode, PlannerError, Roadmap
from symsynth.scene.geometry import Body, Geometry, Grasp, PlannerSettings, Pose, Robot, Shape
from symsynth.scene.model import ObjectSpec, Scene

PLACE_RADIUS = 0.05
HELD_RADIUS = 0.03
#: Where a grasp's anchor lies relative to its place: south, then east.
GRASP_OFFSETS = ((0.0, -0.08, 0.0), (0.08, 0.0, 0.0))


class PlanarPlanner:
    name = "planar"

    def __init__(self, scene: Scene):
        self.scene = scene
        self.geometry = scene.geometry
        self.places = {x: np.array(p.xyz[:2]) for x, p in self.geometry.places.items()}
        self.boxes = [(np.array(b.pose.xyz[:2]), np.array(b.shape.size[:2]) / 2) for b in self.geometry.obstacles]
        self.calls = 0

    @property
    def limits(self) -> np.ndarray:
        return np.array([[0.0, 1.0], [0.0, 1.0]])

    def inverse_kinematics(self, pose: Pose, seed: Config) -> Config | None:
        x, y = pose.xyz[:2]
        return (float(x), float(y)) if 0 <= x <= 1 and 0 <= y <= 1 else None

    def contacts(self, mode: Mode, config: Config) -> Contacts:
        self.calls += 1
        q = np.asarray(config, dtype=float)
        r = 0.0 if mode.object is None else HELD_RADIUS
        static = any(np.all(np.abs(q - c) < h + r) for c, h in self.boxes) or not (
            np.all(q >= 0) and np.all(q <= 1))
        touched = frozenset(x for x, p in self.places.items() if np.linalg.norm(q - p) < PLACE_RADIUS + r)
        return Contacts(static, touched)

    def motion_contacts(self, mode: Mode, start: Config, goal: Config, step: float) -> Contacts:
        a, b = np.asarray(start, float), np.asarray(goal, float)
        steps = max(1, math.ceil(np.linalg.norm(b - a) / step))
        result = Contacts()
        for t in np.linspace(0.0, 1.0, steps + 1):
            result = result | self.contacts(mode, tuple(a + t * (b - a)))
            if result.static:
                break
        return result

    def roadmap(self, mode: Mode, anchors: Mapping[str, Config], size: int, seed: int) -> Roadmap:
        side = max(2, int(round(math.sqrt(size))))
        grid = [(i / (side - 1), j / (side - 1)) for i in range(side) for j in range(side)]
        configs = grid + [tuple(q) for q in anchors.values()]
        names = {name: len(grid) + i for i, name in enumerate(anchors)}
        step = 1 / (side - 1)
        pairs = set()
        for i in range(side):
            for j in range(side):
                for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
                    if 0 <= i + di < side and 0 <= j + dj < side:
                        pairs.add((i * side + j, (i + di) * side + j + dj))
        points = np.array(grid)
        for name, v in names.items():
            near = np.argsort(np.linalg.norm(points - np.array(configs[v]), axis=1), kind="stable")[:4]
            pairs.update((int(u), v) for u in near)
        edges = [(u, v) for u, v in sorted(pairs)
                 if not self.motion_contacts(mode, configs[u], configs[v], step / 4).static]
        if not edges:
            raise PlannerError("planar roadmap has no edges")
        array = np.array(configs)
        e = np.array(edges, dtype=np.int64)
        lengths = np.linalg.norm(array[e[:, 0]] - array[e[:, 1]], axis=1)
        return Roadmap(array, e, lengths, names)


def planar_scene(places: dict[str, tuple[float, float]], objects: dict[str, str],
                 obstacles: dict[str, tuple[float, float, float, float]] | None = None,
                 else_samples: dict[str, tuple[float, float]] | None = None,
                 grasps: tuple[str, ...] = ("top",), per_radian: float = 10.0, k: int = 0,
                 task: str | None = None, roadmap_size: int = 121) -> Scene:
    """A scene for `PlanarPlanner`: `objects` maps names to their location
    (tag = name), obstacles are (x, y, half-width, half-height) boxes."""
    obstacles, else_samples = obstacles or {}, else_samples or {}
    all_places = {**places, **else_samples}
    geometry = Geometry(
        robot=Robot(urdf=Path(__file__), base=Pose(), home=(0.0, 0.0),
                    ee_link="point"),
        obstacles=tuple(Body(n, Shape("box", size=(2 * hw, 2 * hh, 0.1)), Pose((x, y, 0.0)))
                        for n, (x, y, hw, hh) in obstacles.items()),
        shapes={o: Shape("box", size=(0.04, 0.04, 0.04)) for o in objects},
        places={x: Pose((px, py, 0.0)) for x, (px, py) in all_places.items()},
        grasps={g: Grasp(g, Pose(GRASP_OFFSETS[i]), approach=0.0) for i, g in enumerate(grasps)},
        per_radian=per_radian,
        planner=PlannerSettings(name="planar", roadmap_size=roadmap_size, check_step=0.02, seed=0),
    )
    return Scene(name="planar", objects=tuple(ObjectSpec(o, frozenset({o, "block"}), at)
                                              for o, at in objects.items()),
                 locations=tuple(places), else_samples=tuple(else_samples), grasps=grasps,
                 k=k, task=task, geometry=geometry)


WALL = {"west": (0.225, 0.3, 0.225, 0.02), "east": (0.775, 0.3, 0.225, 0.02)}


def gap_scene(**kw):
    return planar_scene(places={"P": (0.5, 0.3), "l1": (0.5, 0.58), "l2": (0.8, 0.18), "l3": (0.35, 0.12)},
                        objects={"a": "P", "b": "l2"}, obstacles=WALL,
                        else_samples={"e1": (0.2, 0.18)}, task="F(at(b, l1))", **kw)
