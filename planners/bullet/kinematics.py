"""Inverse kinematics with pybullet's null-space solver, restarts, and a
forward-kinematics check of every answer.

pybullet solves from the body's *current* joint values (passing
`currentPositions` instead shifts its answers by centimetres), so each
attempt sets the robot to its start first.  Attempt 0 starts at the seed,
the others at uniform random configurations from a fixed seed, so the same
question always gets the same answer.  A solution is accepted only when
pybullet's forward kinematics puts the end-effector link frame within
`POSITION` metres and `ANGLE` radians of the target and every joint is
within its limits (revolute joints are first moved by 2*pi into their
limits when that is possible).
"""

from __future__ import annotations

import math

import numpy as np

from symsynth.planning.protocol import Config
from symsynth.scene.geometry import Pose

from symsynth_planners.bullet.robot import RobotBody

POSITION = 1e-3
ANGLE = 1e-2
RESTARTS = 30
REFINES = 4  # solver calls per attempt, each continuing from the last answer
ITERATIONS = 100  # pybullet's own iterations per solver call


def inverse_kinematics(robot: RobotBody, pose: Pose, seed: Config) -> Config | None:
    """A configuration within the limits that puts the end-effector link at
    `pose` (world), verified by forward kinematics; None if none was found."""
    low, high = robot.limits[:, 0], robot.limits[:, 1]
    rng = np.random.default_rng(0)
    dofs = robot.movable
    held_at = [robot.fixed.get(j, 0.0) for j in dofs]
    column = {j: i for i, j in enumerate(dofs)}
    lower, upper = list(held_at), list(held_at)
    for k, j in enumerate(robot.joints):
        lower[column[j]], upper[column[j]] = float(low[k]), float(high[k])
    ranges = [u - l for l, u in zip(lower, upper)]
    try:
        for attempt in range(RESTARTS):
            start = np.asarray(seed, float) if attempt == 0 else rng.uniform(low, high)
            config = np.clip(start, low, high)
            for _ in range(REFINES):
                robot.set(config)
                rest = list(held_at)
                for k, j in enumerate(robot.joints):
                    rest[column[j]] = float(config[k])
                answer = robot.client.calculateInverseKinematics(
                    robot.id, robot.ee, pose.xyz, pose.quat, lowerLimits=lower, upperLimits=upper,
                    jointRanges=ranges, restPoses=rest, maxNumIterations=ITERATIONS,
                    residualThreshold=1e-7)
                config = _into_limits(np.array([answer[column[j]] for j in robot.joints]), low, high)
                if _reaches(robot, config, pose, low, high):
                    return tuple(float(v) for v in config)
                config = np.clip(config, low, high)
        return None
    finally:
        robot.set(robot.home)


def end_effector(robot: RobotBody, config: Config | np.ndarray) -> Pose:
    """The end-effector link pose (world) at `config`, by pybullet's forward kinematics."""
    robot.set(config)
    position, quat = robot.ee_pose()
    return Pose(tuple(position), tuple(quat))


def _reaches(robot: RobotBody, config: np.ndarray, pose: Pose, low, high) -> bool:
    if (config < low).any() or (config > high).any():
        return False
    reached = end_effector(robot, config)
    error = math.dist(reached.xyz, pose.xyz)
    return error <= POSITION and reached.angle_to(pose) <= ANGLE


def _into_limits(config: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    config = config.copy()
    for i, value in enumerate(config):
        for turn in (-2 * math.pi, 2 * math.pi):
            if not low[i] <= value <= high[i] and low[i] <= value + turn <= high[i]:
                config[i] = value + turn
    return config
