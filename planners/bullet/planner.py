"""`BulletPlanner`: the `Planner` protocol answered by PyBullet.

Each planner owns a private physics client (`World`), so several planners,
for several scenes, can live in one process.  Collision rules are those of
`world.py` (which bodies meet), `robot.py` (which link pairs may collide)
and `bodies.py` (collision groups); inverse kinematics is `kinematics.py`.
Segments are checked at the steps of `symsynth.planning.segment`, up to
the first static contact.
Roadmaps (`prm.build_roadmap`) check their edges at the scene's
`planner.check_step`, for static collisions only, with every place body
switched off.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import ClassVar

import numpy as np

from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import Config, Contacts, Mode, PlannerError, Roadmap
from symsynth.planning.segment import segment
from symsynth.scene.geometry import Pose
from symsynth.scene.model import Scene

from symsynth_planners.bullet.kinematics import inverse_kinematics
from symsynth_planners.bullet.world import World


class BulletPlanner:
    name: ClassVar[str] = "pybullet"
    time_limited: ClassVar[bool] = True  # roadmap(..., seconds=S) is honoured

    def __init__(self, scene: Scene) -> None:
        geometry = scene.geometry
        if geometry is None:
            raise PlannerError(f"scene {scene.name!r} has no geometry: the pybullet planner needs a "
                               "physical scene (a scene file with a 'robot' key)")
        missing = set(scene.object_names) - set(geometry.shapes)
        if missing:
            raise PlannerError(f"objects without a shape: {', '.join(sorted(missing))}")
        self.scene = scene
        self.settings = geometry.planner
        self.world = World(geometry)

    @property
    def limits(self) -> np.ndarray:
        return self.world.robot.limits.copy()

    def inverse_kinematics(self, pose: Pose, seed: Config) -> Config | None:
        return inverse_kinematics(self.world.robot, pose, self._config(seed))

    def contacts(self, mode: Mode, config: Config) -> Contacts:
        self.world.set_mode(mode)
        self.world.set_config(self._config(config))
        return self.world.touching()

    def motion_contacts(self, mode: Mode, start: Config, goal: Config, step: float) -> Contacts:
        """Stops at the first static contact, with the locations touched
        before that configuration (the protocol's rule, as ompl-fcl)."""
        self.world.set_mode(mode)
        locations: set[str] = set()
        for config in segment(self._config(start), self._config(goal), step):
            self.world.set_config(config)
            found = self.world.touching()
            if found.static:
                return Contacts(True, frozenset(locations))
            locations |= found.locations
        return Contacts(False, frozenset(locations))

    def roadmap(self, mode: Mode, anchors: Mapping[str, Config], size: int, seed: int,
                seconds: float | None = None) -> Roadmap:
        step = self.settings.check_step

        def valid(config) -> bool:
            self.world.set_mode(mode, places=False)
            self.world.set_config(config)
            return not self.world.touching().static

        def motion_valid(start, goal) -> bool:
            self.world.set_mode(mode, places=False)
            for config in segment(self._config(start), self._config(goal), step):
                self.world.set_config(config)
                if self.world.touching().static:
                    return False
            return True

        anchors = {name: self._config(config) for name, config in anchors.items()}
        return build_roadmap(self.limits, valid, motion_valid, anchors, size, seed, step, seconds)

    def _config(self, config) -> tuple[float, ...]:
        values = tuple(float(v) for v in config)
        if len(values) != len(self.world.robot.joints):
            raise PlannerError(f"a configuration has {len(values)} values; the robot has "
                               f"{len(self.world.robot.joints)} controlled joints")
        return values
