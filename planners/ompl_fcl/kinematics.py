"""The robot's forward kinematics and joint limits, read from its URDF by
yourdfpy.

yourdfpy parses the URDF (joints, origins, axes, mimics, limits, collision
elements) and is the reference forward kinematics (`reference_poses`).  Its
own `update_cfg` + `get_transform` costs about 1 ms for the Panda's 13 links
at a new configuration (trimesh's scene graph), which would make collision
checking FK-bound; so the hot path (`poses`) composes the same joint
transforms along the tree for a whole batch of configurations in numpy
(about 50 us for one configuration, 5 us each in a batch).  The two are
compared when a robot is loaded and must agree to 1e-9 (else
`PlannerError`); the tests compare both with pybullet's FK.

Conventions: a configuration has one value per *controlled* joint
(`Robot.joints`, or every actuated joint but the `fixed` ones), in radians
or metres.  Fixed joints keep their value; an actuated joint that is neither
controlled nor fixed stays at 0.  Mimic joints follow the joint they mimic
(yourdfpy applies them), so a `fixed` entry for a mimic joint is not needed
and is ignored.  Link poses are 4x4 matrices in the world frame: the URDF's
root link sits at `Robot.base`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yourdfpy

from symsynth.planning.protocol import Config, PlannerError
from symsynth.scene.geometry import Robot

CONTINUOUS = (-np.pi, np.pi)  # range given to joints without limits


class Kinematics:
    """Forward and inverse kinematics of one robot."""

    def __init__(self, robot: Robot):
        if not Path(robot.urdf).is_file():
            raise PlannerError(f"robot URDF {robot.urdf} does not exist")
        self.robot = robot
        self.urdf = yourdfpy.URDF.load(str(robot.urdf), build_scene_graph=True, load_meshes=False,
                                       build_collision_scene_graph=False, load_collision_meshes=False)
        actuated = list(self.urdf.actuated_joint_names)
        fixed = dict(robot.fixed)
        unknown = [j for j in (*robot.joints, *fixed) if j not in self.urdf.joint_map]
        if unknown:
            raise PlannerError(f"{robot.urdf} has no joint {', '.join(unknown)}")
        self.joints = robot.joints or tuple(j for j in actuated if j not in fixed)
        passive = [j for j in self.joints if j not in actuated]
        if passive:
            raise PlannerError(f"controlled joints must be actuated in {robot.urdf}: {', '.join(passive)}")
        if robot.ee_link not in self.urdf.link_map:
            raise PlannerError(f"{robot.urdf} has no end-effector link {robot.ee_link}")
        self.ee_link = robot.ee_link
        self._template = np.array([fixed.get(j, 0.0) for j in actuated], dtype=float)
        self._slots = np.array([actuated.index(j) for j in self.joints])
        self.limits = np.array([self._limit(j) for j in self.joints], dtype=float)
        self.base = robot.base.matrix()
        home = np.asarray(robot.home, dtype=float)
        if home.shape != (len(self.joints),):
            raise PlannerError(f"home has {home.size} values, the robot has {len(self.joints)} controlled "
                               f"joints ({', '.join(self.joints)})")
        self.home = home
        self.links = list(self.urdf.link_map)
        self._ee = self.links.index(self.ee_link)
        self._chain = self._tree()
        self._agree()

    def _tree(self) -> list[tuple[int, int, int]]:
        """Joints in tree order as (child link, parent link, joint), links as
        indices into `links`; fills the per-joint arrays `poses` uses."""
        actuated = list(self.urdf.actuated_joint_names)
        index = {link: i for i, link in enumerate(self.links)}
        chain: list[tuple[int, int, int]] = []
        frontier = [self.urdf.base_link]
        origins, axes, kinds, sources, scales, offsets = [], [], [], [], [], []
        while frontier:
            parent = frontier.pop(0)
            for joint in (j for j in self.urdf.robot.joints if j.parent == parent):
                if joint.type not in ("revolute", "continuous", "prismatic", "fixed"):
                    raise PlannerError(f"joint {joint.name} of {self.robot.urdf} is {joint.type}: "
                                       "only revolute, continuous, prismatic and fixed joints are supported")
                origins.append(np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float))
                axis = np.asarray(joint.axis if joint.axis is not None else (1.0, 0.0, 0.0), dtype=float)
                axes.append(axis / np.linalg.norm(axis) if np.any(axis) else axis)
                kinds.append(joint.type)
                mimic = joint.mimic
                name = mimic.joint if mimic is not None else joint.name
                # a fixed joint, or one mimicking a joint that is not actuated, gets the value 0
                sources.append(actuated.index(name) if joint.type != "fixed" and name in actuated else -1)
                scales.append(float(mimic.multiplier) if mimic and mimic.multiplier is not None else 1.0)
                offsets.append(float(mimic.offset) if mimic and mimic.offset is not None else 0.0)
                chain.append((index[joint.child], index[parent], len(chain)))
                frontier.append(joint.child)
        self._origins = np.array(origins).reshape(-1, 4, 4)
        self._axes = np.array(axes).reshape(-1, 3)
        x, y, z = self._axes.T
        zero = np.zeros_like(x)
        self._cross = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1),
                                np.stack([-y, x, zero], -1)], -2)  # (joints, 3, 3): v -> axis x v
        self._root = index[self.urdf.base_link]
        self._prismatic = np.array([k == "prismatic" for k in kinds])
        self._fixed = np.array([k == "fixed" for k in kinds])
        self._sources = np.array(sources, dtype=np.int64)
        self._scales, self._offsets = np.array(scales), np.array(offsets)
        return chain

    def _agree(self) -> None:
        rng = np.random.default_rng(0)
        for config in (self.home, *rng.uniform(self.limits[:, 0], self.limits[:, 1], (3, len(self.joints)))):
            fast = self.poses(config[None])[0]
            slow = np.array(self.reference_poses(config))
            if not np.allclose(fast, slow, rtol=0, atol=1e-9):
                raise PlannerError(f"forward kinematics of {self.robot.urdf} disagrees with yourdfpy's "
                                   f"(by {np.abs(fast - slow).max():.2g}) at {config.tolist()}")

    def _limit(self, joint: str) -> tuple[float, float]:
        spec = self.urdf.joint_map[joint]
        if spec.type == "continuous" or spec.limit is None or spec.limit.lower is None:
            return CONTINUOUS
        return float(spec.limit.lower), float(spec.limit.upper)

    @property
    def root(self) -> str:
        return self.urdf.base_link

    def parent_link(self, link: str) -> str | None:
        """The link this one hangs from in the URDF's tree (None for the root)."""
        return next((j.parent for j in self.urdf.robot.joints if j.child == link), None)

    def check(self, config: Config | np.ndarray) -> np.ndarray:
        q = np.asarray(config, dtype=float)
        if q.shape != (len(self.joints),):
            raise PlannerError(f"a configuration needs {len(self.joints)} values "
                               f"({', '.join(self.joints)}), got {q.size}")
        return q

    def _full(self, configs: np.ndarray) -> np.ndarray:
        """(B, d) controlled values -> (B, actuated) values, fixed joints filled in."""
        full = np.repeat(self._template[None], len(configs), axis=0)
        full[:, self._slots] = configs
        return full

    def poses(self, configs: np.ndarray) -> np.ndarray:
        """(B, d) configurations -> (B, links, 4, 4) world poses of `links`."""
        configs = np.asarray(configs, dtype=float)
        values = np.concatenate([self._full(configs), np.zeros((len(configs), 1))], axis=1)
        q = values[:, self._sources] * self._scales + self._offsets  # (B, joints); index -1 is the 0 column
        q[:, self._fixed] = 0.0
        local = self._origins @ _motions(self._axes, self._cross, self._prismatic, q)
        poses = np.empty((len(configs), len(self.links), 4, 4))
        poses[:, self._root] = self.base
        for child, parent, joint in self._chain:
            poses[:, child] = poses[:, parent] @ local[:, joint]
        return poses

    def reference_poses(self, config: Config) -> list[np.ndarray]:
        """World poses of `links` by yourdfpy's own forward kinematics."""
        self.urdf.update_cfg(self._full(self.check(config)[None])[0])
        return [self.base @ self.urdf.get_transform(link) for link in self.links]

    def ee_poses(self, configs: np.ndarray) -> np.ndarray:
        """(B, 4, 4) world poses of the end-effector link."""
        return self.poses(configs)[:, self._ee]


def _motions(axes: np.ndarray, cross: np.ndarray, prismatic: np.ndarray, q: np.ndarray) -> np.ndarray:
    """(B, joints, 4, 4) joint motions for values q (B, joints): rotation by
    q about the unit axis (Rodrigues, `cross` is the axis' cross-product
    matrix), or translation by q along it."""
    turn = np.where(prismatic, 0.0, q)[..., None, None]
    motion = np.broadcast_to(np.eye(4), q.shape + (4, 4)).copy()
    motion[..., :3, :3] += np.sin(turn) * cross + (1 - np.cos(turn)) * (cross @ cross)
    motion[..., :3, 3] = np.where(prismatic, q, 0.0)[..., None] * axes
    return motion
