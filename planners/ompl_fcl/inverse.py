"""Inverse kinematics by bounded least squares (scipy) over the batched
forward kinematics, verified by forward kinematics.

The residual is the end-effector's position error (metres) and rotation
error (a rotation vector, radians); the Jacobian is taken by forward
differences, all joints in one batched FK call.  scipy's `dogbox` method
converges on the Panda in tens of evaluations where the default `trf`
crawls along the redundant joint.  Starts: the caller's seed, home, then
`RESTARTS` configurations drawn from a fixed generator (so the answer is
deterministic).  Each start is solved twice: first with a small pull
towards the seed (weight `PULL`), which picks the solution near the seed out
of the redundant family, then without it, which meets the pose exactly.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

from symsynth.planning.protocol import Config
from symsynth.scene.geometry import Pose

from .kinematics import Kinematics

POSITION_TOLERANCE = 1e-3  # metres
ANGLE_TOLERANCE = 0.01  # radians
RESTARTS = 32  # random starts tried after the caller's seed and home
EVALUATIONS = 100  # per start and phase
PULL = 0.01  # weight of the pull towards the seed (residual units per radian)
RESTART_SEED = 20240
STEP = 1e-7  # forward-difference step, radians


def inverse_kinematics(kinematics: Kinematics, pose: Pose, seed: Config) -> Config | None:
    """A configuration within the limits whose end-effector pose is `pose`
    (1 mm, 0.01 rad), or None if every start fails."""
    target = pose.matrix()
    q0 = kinematics.check(seed)
    low, high = kinematics.limits[:, 0], kinematics.limits[:, 1]
    restarts = np.random.default_rng(RESTART_SEED).uniform(low, high, size=(RESTARTS, len(q0)))
    pull = PULL * np.eye(len(q0))

    def errors(q: np.ndarray) -> np.ndarray:
        return _errors(kinematics, q[None], target)[0]

    def jacobian(q: np.ndarray) -> np.ndarray:
        return _jacobian(kinematics, q, target)

    for start in (q0, kinematics.home, *restarts):
        near = _fit(kinematics, lambda q: np.concatenate([errors(q), PULL * (q - q0)]),
                    lambda q: np.vstack([jacobian(q), pull]), np.clip(start, low, high))
        exact = _fit(kinematics, errors, jacobian, near)
        if reaches(kinematics, exact, target):
            return tuple(float(v) for v in exact)
    return None


def reaches(kinematics: Kinematics, config: Config | np.ndarray, target: np.ndarray) -> bool:
    """`config` is within the limits and places the end-effector at `target`
    (4x4) within the tolerances."""
    q = kinematics.check(config)
    if np.any(q < kinematics.limits[:, 0]) or np.any(q > kinematics.limits[:, 1]):
        return False
    pose = kinematics.ee_poses(q[None])[0]
    turn = Rotation.from_matrix(target[:3, :3].T @ pose[:3, :3]).magnitude()
    return bool(np.linalg.norm(pose[:3, 3] - target[:3, 3]) <= POSITION_TOLERANCE and turn <= ANGLE_TOLERANCE)


def _fit(kinematics: Kinematics, errors: Callable, jacobian: Callable, start: np.ndarray) -> np.ndarray:
    bounds = (kinematics.limits[:, 0], kinematics.limits[:, 1])
    fit = least_squares(errors, start, jac=jacobian, bounds=bounds,
                        method="dogbox", xtol=1e-8, ftol=1e-10, gtol=1e-10, max_nfev=EVALUATIONS)
    return fit.x


def _errors(kinematics: Kinematics, configs: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(B, 6): position error (world) and rotation vector (target's frame)."""
    poses = kinematics.ee_poses(configs)
    turn = Rotation.from_matrix(target[:3, :3].T @ poses[:, :3, :3]).as_rotvec()
    return np.concatenate([poses[:, :3, 3] - target[:3, 3], turn], axis=1)


def _jacobian(kinematics: Kinematics, q: np.ndarray, target: np.ndarray) -> np.ndarray:
    errors = _errors(kinematics, q + np.vstack([np.zeros(len(q)), STEP * np.eye(len(q))]), target)
    return ((errors[1:] - errors[0]) / STEP).T
