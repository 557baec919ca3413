"""The robot as one pybullet multibody: joints by name, limits, the
end-effector link, and which of its link pairs may collide.

Self-collision (URDF_USE_SELF_COLLISION) is on for every pair of links
with collision geometry except *adjacent* ones (`symsynth.planning.adjacent`),
whose pairs are filtered out.
"""

from __future__ import annotations

import math

import numpy as np
from symsynth.bullet import load_robot, pybullet as p

from symsynth.planning.adjacent import adjacent_pairs
from symsynth.planning.protocol import Config, PlannerError
from symsynth.scene.geometry import Robot

from symsynth_planners.bullet.bodies import BASE, ROBOT, set_group


class RobotBody:
    """Loads `robot` into `client`; `set(config)` moves it."""

    def __init__(self, client, robot: Robot) -> None:
        self.client = client
        loaded = load_robot(client, robot, flags=p.URDF_USE_SELF_COLLISION, error=PlannerError)
        self.id = loaded.id
        infos = loaded.infos
        self.parent = loaded.parents
        self.joints = list(loaded.joints)
        self.ee = loaded.ee
        self.movable = list(loaded.movable)  # the order of pybullet's inverse kinematics arrays
        self.limits = np.array([_limits(infos[j]) for j in self.joints])
        # inverse kinematics keeps the other movable joints at their fixed value
        self.fixed = loaded.held
        self.home = tuple(float(v) for v in robot.home)
        self.links = [j for j in range(-1, len(infos)) if client.getCollisionShapeData(self.id, j)]
        self.adjacent = adjacent_pairs(self.links, self.parent.get)  # the base (-1) has no parent entry
        for a, b in self.adjacent:
            client.setCollisionFilterPair(self.id, self.id, a, b, 0)
        for link in range(-1, len(infos)):
            set_group(client, self.id, link, BASE if link == -1 else ROBOT)
        self.hand = [j for j in range(-1, len(infos)) if self._below(j, self.ee)]
        self.set(self.home)

    def set(self, config: Config | np.ndarray) -> None:
        self.client.resetJointStatesMultiDof(self.id, self.joints, [[float(v)] for v in config])

    def ee_pose(self) -> tuple[tuple, tuple]:
        """World position and quaternion of the end-effector link frame (the
        URDF frame, not the centre of mass) at the current configuration."""
        state = self.client.getLinkState(self.id, self.ee, computeForwardKinematics=True)
        return state[4], state[5]

    def _below(self, link: int, ancestor: int) -> bool:
        while link != ancestor and link in self.parent:
            link = self.parent[link]
        return link == ancestor


def _limits(info) -> tuple[float, float]:
    lower, upper = info[8], info[9]
    if lower > upper:  # continuous joint: pybullet reports (0, -1)
        return -math.pi, math.pi
    return lower, upper
