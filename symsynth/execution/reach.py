"""The hand moved a few millimetres: Newton steps on PyBullet's Jacobian.

`reach(world, config, pose)` is a configuration near `config` whose
end-effector is at `pose`: from `config`, each step moves the joints by the
least-squares (smallest) change that the Jacobian at the current
configuration says cancels the hand's error (position and rotation
vector, world frame), until the hand is within `REACHED` (metres, radians)
of the pose; None after `NEWTON_STEPS` steps, or where a joint leaves its
limits.  For a pose close to `config`'s hand (a grasp on an object a
physical world moved a few millimetres from its place) it converges in two
or three steps, where a general inverse kinematics solver, with its
restarts, costs ten milliseconds.  The robot is put back where it stood
(set, not stepped).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from symsynth.bullet import pybullet
from symsynth.execution.world import SimWorld
from symsynth.planning.protocol import Config
from symsynth.scene.geometry import Pose

REACHED = (1e-6, 1e-5)  # metres, radians
NEWTON_STEPS = 8


def reach(world: SimWorld, config: Config, pose: Pose) -> Config | None:
    """A configuration near `config` with the hand at `pose` (module doc)."""
    client, robot = world.client, world.robot
    infos = [client.getJointInfo(robot, j) for j in range(client.getNumJoints(robot))]
    movable = [j for j, info in enumerate(infos) if info[2] != pybullet.JOINT_FIXED]
    columns = [movable.index(j) for j in world.joints]
    low, high = (np.array([infos[j][k] for j in world.joints]) for k in (8, 9))
    link = client.getLinkState(robot, world.ee_link)
    origin = client.invertTransform(link[2], link[3])[0]  # the link frame's origin, in its centre of mass frame
    target = Rotation.from_quat(pose.quat)
    before = world.config
    q = np.asarray(config, float)
    try:
        for _ in range(NEWTON_STEPS):
            SimWorld.set_config(world, q.tolist())
            hand = world.ee_pose()
            error = np.concatenate([np.subtract(pose.xyz, hand.xyz),
                                    (target * Rotation.from_quat(hand.quat).inv()).as_rotvec()])
            if np.linalg.norm(error[:3]) <= REACHED[0] and np.linalg.norm(error[3:]) <= REACHED[1]:
                return tuple(float(v) for v in q)
            at = [s[0] for s in client.getJointStates(robot, movable)]
            linear, angular = client.calculateJacobian(robot, world.ee_link, origin, at, [0.0] * len(at),
                                                       [0.0] * len(at))
            jacobian = np.vstack([np.asarray(linear)[:, columns], np.asarray(angular)[:, columns]])
            q = q + np.linalg.lstsq(jacobian, error, rcond=None)[0]  # J dq = error, the smallest dq
            if np.any(q < low) or np.any(q > high):
                return None
        return None
    finally:
        SimWorld.set_config(world, before)
