"""The `ompl-fcl` planner: yourdfpy kinematics (`kinematics`, `inverse`),
python-fcl collisions (`collision`, `shapes`, `bounds`), OMPL roadmaps
(`symsynth.planning.prm`).

Built for one physical scene (`scene.geometry`); see `kinematics` for the
configuration conventions and `collision` for which pairs are checked.
A motion is checked at the steps of `symsynth.planning.segment` (equal,
at most `step` apart, both ends included), and the check stops at
the first static collision.  Roadmap edges are checked the same way, ends
first and then by bisection, so that a blocked edge is rejected early.
The planner remembers the segments it found free that way; the edge checks
of its own roadmap then test only the location pairs (the self and static
pairs of the same configurations are known free: same answer, a third of
the work).  Another planner object, or another step, checks all.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import ClassVar

import numpy as np

from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import Config, Contacts, Mode, PlannerError, Roadmap
from symsynth.planning.segment import segment
from symsynth.scene.geometry import Geometry, Pose

from .collision import CollisionWorld
from .inverse import inverse_kinematics
from .kinematics import Kinematics


class OmplFclPlanner:
    """The `Planner` protocol for a scene whose `geometry` is a `Geometry`."""

    name: ClassVar[str] = "ompl-fcl"
    time_limited: ClassVar[bool] = True  # roadmap(..., seconds=S) is honoured

    def __init__(self, scene) -> None:
        geometry = getattr(scene, "geometry", None)
        if not isinstance(geometry, Geometry):
            raise PlannerError(f"the {self.name} planner needs a physical scene (one with geometry); "
                               f"{getattr(scene, 'name', scene)!r} has none")
        self.geometry = geometry
        self.kinematics = Kinematics(geometry.robot)
        self.world = CollisionWorld(self.kinematics, geometry)
        # segments (mode, start, goal, step) `roadmap` found free of
        # self and static contacts at every step: their edge checks need
        # only the location pairs
        self._free: set[tuple[Mode, bytes, bytes, float]] = set()

    @property
    def limits(self) -> np.ndarray:
        return self.kinematics.limits.copy()

    def inverse_kinematics(self, pose: Pose, seed: Config) -> Config | None:
        return inverse_kinematics(self.kinematics, pose, seed)

    def contacts(self, mode: Mode, config: Config) -> Contacts:
        return self.world.contacts(mode, config)

    def motion_contacts(self, mode: Mode, start: Config, goal: Config, step: float) -> Contacts:
        a, b = self.kinematics.check(start), self.kinematics.check(goal)
        configs = segment(a, b, step)
        known = (mode, a.tobytes(), b.tobytes(), step) in self._free
        return self.world.sweep(mode, configs, static=not known)

    def roadmap(self, mode: Mode, anchors: Mapping[str, Config], size: int, seed: int,
                seconds: float | None = None) -> Roadmap:
        step = self.geometry.planner.check_step
        self.world.held(mode)  # an unknown mode fails here, naming the known objects and grasps

        def valid(config: np.ndarray) -> bool:
            return not self.world.contacts(mode, config, locations=False).static

        def motion_valid(start: np.ndarray, goal: np.ndarray) -> bool:
            configs = segment(start, goal, step)
            if self.world.sweep(mode, configs[bisection(len(configs))], locations=False).static:
                return False
            self._free.add((mode, start.tobytes(), goal.tobytes(), step))
            return True

        return build_roadmap(self.limits, valid, motion_valid, anchors, size, seed, step, seconds)


def bisection(n: int) -> np.ndarray:
    """0..n-1 ordered ends first, then midpoints of ever finer halvings:
    a blocked segment is usually found blocked after a few checks."""
    order = list(dict.fromkeys([0, n - 1]))
    seen, step = set(order), n - 1
    while step > 1:
        for i in range(step // 2, n, step):
            if i not in seen:
                order.append(i)
                seen.add(i)
        step = (step + 1) // 2
    return np.array(order + [i for i in range(n) if i not in seen], dtype=np.int64)
