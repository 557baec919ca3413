"""The robot as one pybullet multibody: joints by name, limits, the
end-effector link, and which of its link pairs may collide.

Self-collision (URDF_USE_SELF_COLLISION) is on for every pair of links
with collision geometry except *adjacent* ones: two links are adjacent when
the kinematic path between them runs only through links without collision
geometry.  Adjacent links touch by construction at their joint, so a
contact between them says nothing.  For the Franka Panda this excludes
exactly (link0, link1), (link1, link2), ..., (link6, link7), the parent-child
pairs, plus (link7, panda_hand), which are joined rigidly through the
geometry-less panda_link8 and overlap at every configuration, plus
(panda_hand, panda_leftfinger) and (panda_hand, panda_rightfinger).  The two
fingers are not adjacent (siblings); with the fingers open they never touch.
Everything else is checked, e.g. link5 against link7 and the hand, which
really meet when joint 6 is near its lower limit.
"""

from __future__ import annotations

import math

import numpy as np
from symsynth.bullet import pybullet as p

from symsynth.planning.protocol import Config, PlannerError
from symsynth.scene.geometry import Robot

from symsynth_planners.bullet.bodies import BASE, ROBOT, set_group


class RobotBody:
    """Loads `robot` into `client`; `set(config)` moves it."""

    def __init__(self, client, robot: Robot) -> None:
        self.client = client
        self.id = client.loadURDF(str(robot.urdf), basePosition=robot.base.xyz,
                                  baseOrientation=robot.base.quat, useFixedBase=True,
                                  flags=p.URDF_USE_SELF_COLLISION)
        if self.id < 0:
            raise PlannerError(f"pybullet could not load the robot URDF {robot.urdf}")
        infos = [client.getJointInfo(self.id, j) for j in range(client.getNumJoints(self.id))]
        joint_index = {info[1].decode(): j for j, info in enumerate(infos)}
        link_index = {info[12].decode(): j for j, info in enumerate(infos)}
        link_index[client.getBodyInfo(self.id)[0].decode()] = -1
        self.parent = {j: info[16] for j, info in enumerate(infos)}
        movable = [j for j, info in enumerate(infos) if info[2] != p.JOINT_FIXED]
        fixed = dict(robot.fixed)
        names = robot.joints or tuple(infos[j][1].decode() for j in movable
                                      if infos[j][1].decode() not in fixed)
        for name in list(names) + list(fixed):
            if joint_index.get(name) not in movable:
                raise PlannerError(f"joint {name!r} is not a movable joint of {robot.urdf}")
        if robot.ee_link not in link_index:
            raise PlannerError(f"end-effector link {robot.ee_link!r} is not a link of {robot.urdf}")
        if len(robot.home) != len(names):
            raise PlannerError(f"home has {len(robot.home)} values for {len(names)} joints ({', '.join(names)})")
        self.joints = [joint_index[n] for n in names]
        self.ee = link_index[robot.ee_link]
        self.movable = movable  # the order of pybullet's inverse kinematics arrays
        self.limits = np.array([_limits(infos[j]) for j in self.joints])
        # inverse kinematics keeps the other movable joints at their fixed value
        self.fixed = {joint_index[n]: float(v) for n, v in fixed.items()}
        for j in movable:
            if j not in self.joints and j not in self.fixed:
                self.fixed[j] = 0.0
        for j, value in self.fixed.items():
            client.resetJointState(self.id, j, value)
        self.home = tuple(float(v) for v in robot.home)
        self.links = [j for j in range(-1, len(infos)) if client.getCollisionShapeData(self.id, j)]
        self.adjacent = self._adjacent_pairs()
        for a, b in self.adjacent:
            client.setCollisionFilterPair(self.id, self.id, a, b, 0)
        for link in range(-1, len(infos)):
            set_group(client, self.id, link, BASE if link == -1 else ROBOT)
        self.hand = [j for j in range(-1, len(infos)) if self._below(j, self.ee)]
        self.set(self.home)

    def set(self, config: Config) -> None:
        self.client.resetJointStatesMultiDof(self.id, self.joints, [[float(v)] for v in config])

    def ee_pose(self) -> tuple[tuple, tuple]:
        """World position and quaternion of the end-effector link frame (the
        URDF frame, not the centre of mass) at the current configuration."""
        state = self.client.getLinkState(self.id, self.ee, computeForwardKinematics=True)
        return state[4], state[5]

    def _adjacent_pairs(self) -> list[tuple[int, int]]:
        pairs = []
        for link in self.links:
            up = self.parent.get(link, None)
            while up is not None and up not in self.links:
                up = self.parent.get(up)  # the base (-1) has no parent entry
            if up is not None:
                pairs.append((up, link))
        return pairs

    def _below(self, link: int, ancestor: int) -> bool:
        while link != ancestor and link in self.parent:
            link = self.parent[link]
        return link == ancestor


def _limits(info) -> tuple[float, float]:
    lower, upper = info[8], info[9]
    if lower > upper:  # continuous joint: pybullet reports (0, -1)
        return -math.pi, math.pi
    return lower, upper
