"""The physical world: the scene in PyBullet with dynamics
(`symsynth simulate --world physics`).

`PhysicsWorld` is a `SimWorld` whose objects have mass and friction and
move only as PyBullet integrates them:

- **Dynamics.**  DIRECT mode, gravity 9.81 m/s², a fixed time step of
  `TIME_STEP` (1/240 s, PyBullet's default) with its default 50 solver
  iterations; nothing depends on the wall clock, so the same seed gives the
  same run.  Objects weigh their `physics: {mass}` (default: their volume at
  `DENSITY`, 500 kg/m³, wood; `MESH_MASS` for a mesh), and slide with their
  `friction` (default `FRICTION`; PyBullet multiplies two bodies'
  coefficients, so a block on the table slides with 0.5 x 0.5 by default).
  Static obstacles (the table) take a `physics: {friction}` too.
- **The robot** follows a path by position control of its joints with the
  URDF's force limits (87 N m and 12 N m for the Panda): the target moves
  along the path, each leg in the time its fastest joint needs at
  `SPEED_FRACTION` of its URDF velocity limit (a piece of a leg, at most
  `CLEAR_STRIDE` long, that keeps the robot `CLEAR` from every object at
  `CLEAR_FRACTION`, but the path's last; a slide's
  hand at most `SLIDE_SPEED` near the object), and at the path's end the robot is held on
  its last configuration until every joint is within `ARRIVED` radians of
  it (at most `CONVERGE_STEPS`; the path's last leg slows to rest over
  `STOP_STEPS`, without which the arm, stopped at once, overshot its end by up
  to 24 mrad and took 20 steps to come back; within `PASSING` at a transit's end or on
  the way up from a drop, where the hand is empty and touches nothing).
  A path's cost is the radians of the path commanded, as the costmap
  measures it.
- **The gripper** is the robot's `fixed` joints (the Panda's fingers, held
  open at 4 cm): `close_hand` drives them to their lower limit with their
  force limit (20 N), and when *both* fingers then touch the object
  (contact points read from PyBullet) and it stopped them short of closing
  fully (`STOPPED`: fingers on its top close all the way), the grasp is
  firmed by a fixed constraint between the hand and the object at their
  relative pose of that moment (`FIRM_FORCE` at most).  PyBullet's friction grasps slip with
  small, light blocks over long transfers; the constraint stands for the
  real gripper's grip, and is made only where the fingers hold the object.
  Fingers that close on nothing make no constraint: the object stays where
  it is, and the observation says so.  `open_hand` removes the constraint
  and opens the fingers: the object is released where the hand put it and
  settles under gravity.  The fingers move until the hand's opening stops
  changing (`FINGER_REST`) or they are within `OPEN_ENOUGH` of their
  target, at most `GRIP_STEPS`.
- **Settling.**  After a release, a slide or a human's move, the world is
  stepped until every object moves slower than `REST_SPEED` (m/s) and
  `REST_SPIN` (rad/s) for `REST_STEPS` steps in a row, at most
  `SETTLE_STEPS`; only then are the poses read (`poses`, what `observe`
  reads).
- **Sleep.**  An object whose velocities' squares sum below `REST_SPEED`²
  (slower than 5 mm/s and 5 mrad/s) for PyBullet's 2 s sleeps: it is not
  integrated, and what rests on the table alone costs the step nothing.
  A contact with anything awake (the fingers, a block put on it) wakes it
  in the step it happens; a pose or velocity set from outside does not,
  so an object put somewhere before the world is stepped (a human's move,
  a stand check's) is woken (`_wake`); one put somewhere and back
  (`blocked`) is not.
- **Human moves** are kinematic (no human body is simulated): the object
  is put at rest on its new pose (not within `CLEARANCE` of the robot) and
  settles.  A human puts an object only where it stands (`stands`): not in
  the air (on `top` of an arch without its supports), not where it tips
  over (a lintel on one support), and does not pull an object out from
  under another.
- **Randomization** (`Randomization`, seeded): each object's mass and
  friction, and the table's friction, scaled by a factor drawn uniformly
  in [1 - r, 1 + r]; each object's initial pose shifted on the table by up
  to `pose` metres in x and y.

`simulate`'s world when none is asked for is chosen in `world_choice`.

Collision checks (`touching`, `blocked`, a motion's evidence path checked
before it is followed) still set configurations without stepping, as in the
kinematic world, and put the robot back where it was commanded to stand.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Iterator, Sequence

import numpy as np

from symsynth.bullet import pybullet
from symsynth.execution.randomization import Randomization
from symsynth.execution.world import SimWorld
from symsynth.scene.geometry import Pose
from symsynth.scene.model import Scene

TIME_STEP = 1.0 / 240.0  # seconds
GRAVITY = 9.81  # m/s²
DENSITY = 500.0  # kg/m³: an object's default mass is its volume's
MESH_MASS = 0.1  # kg: the default for a mesh (its volume is not computed)
FRICTION = 0.5  # objects' and obstacles' default Coulomb coefficient
FINGER_FRICTION = 1.0  # the gripper's pads
SPEED_FRACTION = 0.5  # of each joint's URDF velocity limit, along a motion
CLEAR_FRACTION = 1.0  # ... on a transit's or transfer's legs `CLEAR` from every object
CLEAR = 0.03  # metres (5 cm until session 21: arch's adversarial runs 10 % longer, no run better)
CLEAR_STRIDE = 0.1  # radians between the configurations of a leg checked to be clear
DEFAULT_SPEED = 1.0  # rad/s (m/s) for a joint whose URDF gives no velocity limit
DEFAULT_EFFORT = 100.0  # N m (N) for a joint whose URDF gives no force limit
DEFAULT_GRIP = 20.0  # N for a gripper joint whose URDF gives none
SLIDE_SPEED = 0.075  # m/s: the hand's speed along a slide, at most (at 0.1 the pull overshoots)
POSITION_GAIN = 0.1  # PyBullet's position control gains (its defaults: 0.1, 1.0)
VELOCITY_GAIN = 1.0
ARRIVED = 2e-3  # radians: every joint this close to the end of its path
PASSING = 2e-2  # ... and where nothing is at stake there (the hand empty, touching nothing)
CONVERGE_STEPS = 240
STOP_STEPS = 8  # a path's last leg slows to rest over these steps (1/30 s; stopped at once, the arm overshot by 24 mrad)
GRIP_STEPS = 60  # steps the fingers take at most to close or open (4 cm at 0.2 m/s is 48)
FINGER_REST = 0.01  # m/s: the opening changing slower than this has stopped (free fingers close at 0.8)
OPEN_ENOUGH = 3e-3  # metres: a finger this close to its target is there (the last mm are a slow tail)
STOPPED = 1e-3  # metres: a finger this far from fully closed was stopped by the object
FIRM_FORCE = 200.0  # newtons: the firming constraint's strength
CLEARANCE = 0.005  # metres: the closest a human puts an object to the robot
REST_SPEED = 5e-3  # m/s
REST_SPIN = 0.05  # rad/s
REST_STEPS = 5
SETTLE_STEPS = 480  # 2 s
STAND_STEPS = 24  # 0.1 s: an object let go where nothing holds it falls 5 cm in that time
STAND_SHIFT = 2e-3  # metres, and radians: an object that moved more did not stand
FRAME_STEPS = 96  # 0.4 s of the world between two frames of a recording (a motion: 0.4 rad or so) ...
SLIDE_FRAME_STEPS = 48  # ... and 0.2 s along a slide (the object 1.5 cm further at 7.5 cm/s)


Watch = Callable[["PhysicsWorld"], None]


class PhysicsWorld(SimWorld):
    """The scene with dynamics (module doc); `seed` draws the randomization."""

    def __init__(self, scene: Scene, *, gui: bool = False, randomization: Randomization | None = None,
                 seed: int = 0, firm: bool = True) -> None:
        self.randomization = randomization or Randomization()
        self.firm = firm  # False: grasps held by the fingers' friction alone (no constraint)
        self._rng = np.random.default_rng(seed)
        self._scale = {o.name: self._draw("mass") for o in scene.objects}
        super().__init__(scene, gui=gui)
        client = self.client
        # the calls made every step, looked up once (the client's own lookup costs as much as the call)
        self._step_simulation, self._motors = client.stepSimulation, client.setJointMotorControlArray
        self._contacts = client.getContactPoints
        client.setGravity(0, 0, -GRAVITY)
        client.setTimeStep(TIME_STEP)
        for body, name in self.obstacles.items():
            client.changeDynamics(body, -1, lateralFriction=self._friction(name))
        for name, body in self.bodies.items():
            client.changeDynamics(body, -1, lateralFriction=self._friction(name), spinningFriction=0.001,
                                  rollingFriction=0.0, sleepThreshold=REST_SPEED ** 2,
                                  activationState=pybullet.ACTIVATION_STATE_ENABLE_SLEEPING)
        self.fingers = tuple(sorted(self._held_joints()))
        for j in self.fingers:
            client.changeDynamics(self.robot, j, lateralFriction=FINGER_FRICTION)
        infos = [self.client.getJointInfo(self.robot, j) for j in self.joints]
        self._efforts = [info[10] or DEFAULT_EFFORT for info in infos]
        self._speeds = np.array([SPEED_FRACTION * (info[11] or DEFAULT_SPEED) for info in infos])
        self._open = {j: value for j, value in self._held_joints().items()}
        self._grip = dict(self._open)
        self._grip_forces = [self.client.getJointInfo(self.robot, j)[10] or DEFAULT_GRIP for j in self._grip]
        self._still = [0.0] * len(self.joints)
        self._gains = ([POSITION_GAIN] * len(self.joints), [VELOCITY_GAIN] * len(self.joints))
        self._grip_gains = ([POSITION_GAIN] * len(self._grip), [VELOCITY_GAIN] * len(self._grip))
        self._sent_grip: list[float] | None = None
        self._constraint: int | None = None
        self._stands: dict[tuple, bool] = {}
        self.watch: Watch | None = None  # called after every step (a test's or a verifier's eye)
        self.frame: Callable[[], None] | None = None  # a recording's camera, every `frame_every` steps
        self.frame_every = FRAME_STEPS  # steps of the world between frames of a recording
        self.steps = 0
        self.touches: set[str] = set()  # objects the robot touched while `watching`
        self.watching = False
        self._names = {body: name for name, body in self.bodies.items()}
        self._uncentre = {name: self.geometry.shapes[name].centre_offset().inverse() for name in self.bodies}
        self._jitter(self.randomization.pose)
        self._command(self.config)
        self.settle()

    # -- materials and randomization -----------------------------------------

    def mass(self, name: str) -> float:
        material = self.geometry.materials.get(name)
        if material is not None and material.mass is not None:
            base = material.mass
        else:
            shape = self.geometry.shapes[name]
            if shape.kind == "box":
                base = DENSITY * float(np.prod(shape.size))
            elif shape.kind == "cylinder":
                base = DENSITY * math.pi * shape.radius ** 2 * shape.height
            else:
                base = MESH_MASS
        return base * self._scale.get(name, 1.0)

    def _friction(self, name: str) -> float:
        material = self.geometry.materials.get(name)
        base = FRICTION if material is None or material.friction is None else material.friction
        return base * self._draw("friction")

    def _draw(self, key: str) -> float:
        r = getattr(self.randomization, key)
        return float(self._rng.uniform(1 - r, 1 + r)) if r > 0 else 1.0

    def _jitter(self, distance: float) -> None:
        if distance <= 0:
            return
        for name in self.scene.object_names:
            dx, dy = self._rng.uniform(-distance, distance, 2)
            pose = self.poses[name]
            self._place_body(name, Pose((pose.xyz[0] + float(dx), pose.xyz[1] + float(dy), pose.xyz[2]),
                                        pose.quat))

    def _held_joints(self) -> dict[int, float]:
        """The gripper: the movable joints not controlled by configurations."""
        movable = [j for j in range(self.client.getNumJoints(self.robot))
                   if self.client.getJointInfo(self.robot, j)[2] != pybullet.JOINT_FIXED]
        return {j: self.client.getJointState(self.robot, j)[0] for j in movable if j not in self.joints}

    # -- stepping -------------------------------------------------------------

    def step(self) -> None:
        self._flush()
        self._step_simulation()
        self.steps += 1
        if self.watching:  # one query for every body the robot touches
            for contact in self._contacts(bodyA=self.robot):
                name = self._names.get(contact[2])
                if name is not None and name != self.held:
                    self.touches.add(name)
        if self.watch is not None:
            self.watch(self)
        if self.frame is not None and self.steps % self.frame_every == 0:
            self.frame()

    @contextlib.contextmanager
    def watched(self) -> Iterator[set[str]]:
        """The objects the robot touches (PyBullet's contact points, read
        after each step) while the block runs, other than the one held."""
        self.touches, self.watching = set(), True
        try:
            yield self.touches
        finally:
            self.watching = False

    def settle(self, calm: int = 0) -> int:
        """Step until every object rests (module doc), `calm` steps of rest
        already seen; the poses are read then.  Returns the steps taken."""
        taken = 0
        while taken < SETTLE_STEPS and calm < REST_STEPS:
            self.step()
            taken += 1
            calm = calm + 1 if self._resting() else 0
        self.sync()
        return taken

    def _resting(self) -> bool:
        for name, body in self.bodies.items():
            if name == self.held:
                continue
            linear, angular = self.client.getBaseVelocity(body)
            if np.linalg.norm(linear) > REST_SPEED or np.linalg.norm(angular) > REST_SPIN:
                return False
        return True

    def sync(self) -> None:
        """Read every object's pose from PyBullet into `poses`."""
        for name, body in self.bodies.items():
            xyz, quat = self.client.getBasePositionAndOrientation(body)
            self.poses[name] = Pose(tuple(xyz), tuple(quat)) @ self._uncentre[name]

    def _wake(self, name: str) -> None:
        """Object `name`, put somewhere from outside, is integrated again
        (module doc: Sleep)."""
        self.client.changeDynamics(self.bodies[name], -1, activationState=pybullet.ACTIVATION_STATE_WAKE_UP)

    # -- the robot ------------------------------------------------------------

    def follow(self, path: Sequence[Sequence[float]], hand_speed: float | None = None,
               careful: Callable[[np.ndarray, np.ndarray], bool] | None = None, clear: bool = False,
               settle: bool = False, passing: bool = False) -> None:
        """Drive the joints along `path` by position control (module doc),
        then hold the last configuration until the robot is on it.  Each
        leg takes the time its fastest joint needs at `SPEED_FRACTION` of
        its velocity limit (with `clear`, a leg is cut in pieces at most
        `CLEAR_STRIDE` apart, and a piece at whose two ends the robot and
        what it holds stand `CLEAR` from every object goes at
        `CLEAR_FRACTION`, but the path's last piece: `_clear_pieces`), or,
        where `careful(hand's start, hand's end)` holds for the leg (every
        leg when `careful` is None), its hand's straight-line travel at
        `hand_speed` (m/s) if that is longer; the last leg's target slows
        to rest over `STOP_STEPS` (`_stopping`).  With `settle`, the world is
        then stepped until the objects rest too (`settle`), their rest
        counted while the robot is held on its last configuration.  The
        hold ends with every joint within `ARRIVED` radians, or with
        `passing` within `PASSING` where the hand is then empty and touches
        nothing (`_tolerance`)."""
        if len(path) == 0:
            return
        hand = self._hand_points(path) if hand_speed is not None else None
        legs = np.asarray(path, float)
        slow = [hand is not None and hand_speed is not None and (careful is None or careful(hand[k], hand[k + 1]))
                for k in range(len(legs) - 1)]
        hand_legs = [float(np.linalg.norm(hand[k + 1] - hand[k])) if slow[k] and hand is not None else 0.0
                     for k in range(len(slow))]
        if clear:
            legs, slow, hand_legs, far = self._clear_pieces(legs, slow, hand_legs)
        else:
            far = [False] * len(slow)
        for k, (a, b) in enumerate(zip(legs, legs[1:])):
            seconds = float(np.max(np.abs(b - a) / (self._speeds * (CLEAR_FRACTION / SPEED_FRACTION if far[k] else 1.0))))
            if slow[k] and hand_speed is not None:
                seconds = max(seconds, hand_legs[k] / hand_speed)
            n = max(1, math.ceil(seconds / TIME_STEP))
            velocity = (b - a) / (n * TIME_STEP)
            self._command(a, velocity)  # the fingers' targets, if changed (nothing is stepped)
            fractions, rates = _stopping(n) if k == len(legs) - 2 else _steady(n)
            for target, speeds in zip((a + np.outer(fractions, b - a)).tolist(), np.outer(rates, velocity).tolist()):
                self._set(self.joints, target, speeds, self._efforts, self._gains)
                self.step()
        goal = np.asarray(path[-1], float)
        self._command(goal)
        calm, arrived = 0, self._tolerance(passing)
        for _ in range(CONVERGE_STEPS):
            if self.tracking_error(goal) <= arrived:
                break
            self.step()
            if settle:
                calm = calm + 1 if self._resting() else 0
        self.config = tuple(float(v) for v in goal)
        if settle:
            self.settle(calm)
        else:
            self.sync()

    def _clear_pieces(self, legs: np.ndarray, slow: list[bool], hand_legs: list[float]
                      ) -> tuple[np.ndarray, list[bool], list[float], list[bool]]:
        """`legs` with every leg but the `slow` ones cut in pieces at most
        `CLEAR_STRIDE` radians apart (a slow leg stays whole, with its hand's
        travel `hand_legs`), and whether each piece is clear: the robot and
        the object it holds farther than `CLEAR` from every other object,
        and the held object from the obstacles, at both its ends (set, not
        stepped; the robot is put back where it was).  Consecutive pieces
        of one leg that are both clear, or both not, are joined again."""
        start = self.config
        held = self.bodies.get(self.held) if self.held is not None else None
        others = [body for name, body in self.bodies.items() if name != self.held]
        seen: dict[int, bool] = {}

        def clear(index: int, config: np.ndarray) -> bool:  # each configuration checked once
            if index not in seen:
                SimWorld.set_config(self, config.tolist())
                seen[index] = not any(self.client.getClosestPoints(self.robot, body, CLEAR) for body in others) \
                    and (held is None or not any(self.client.getClosestPoints(held, body, CLEAR)
                                                 for body in [*others, *self.obstacles]))
            return seen[index]

        configs, pieces, travel, far, leg = [legs[0]], [], [], [], []
        for k, (a, b) in enumerate(zip(legs, legs[1:])):
            parts = 1 if slow[k] else max(1, math.ceil(float(np.max(np.abs(b - a))) / CLEAR_STRIDE))
            for i in range(1, parts + 1):
                configs.append(a + (b - a) * (i / parts))
                pieces.append(slow[k])
                travel.append(hand_legs[k])
                leg.append(k)
                n = len(configs) - 1
                far.append(not slow[k] and clear(n - 1, configs[n - 1]) and clear(n, configs[n]))
        SimWorld.set_config(self, start)
        if far:
            far[-1] = False  # the robot arrives at the path's end at the usual speed
        # consecutive pieces of one leg at one speed lie on one line: driven as one (each rounded its steps up)
        ends = [0, *(j for j in range(1, len(far)) if leg[j - 1] != leg[j] or far[j - 1] != far[j]), len(far)]
        return (np.asarray([configs[j] for j in ends]), [pieces[j] for j in ends[:-1]], [travel[j] for j in ends[:-1]],
                [far[j] for j in ends[:-1]])

    def _hand_points(self, path: Sequence[Sequence[float]]) -> np.ndarray:
        """The end-effector's position at each configuration of `path`
        (forward kinematics; the robot is put back where it was)."""
        start = self.config
        points = []
        for config in path:
            SimWorld.set_config(self, config)
            points.append(self.ee_pose().xyz)
        SimWorld.set_config(self, start)
        return np.asarray(points, float)

    def _tolerance(self, passing: bool) -> float:
        """The tolerance a path's end is held to: with `passing`, `PASSING`
        where the hand is empty and touches nothing (a transit's end, the
        way up from a drop: the next path starts where this one was
        commanded to, and its own end is held), `ARRIVED` else."""
        if passing and self.held is None and not self.client.getContactPoints(bodyA=self.robot):
            return PASSING
        return ARRIVED

    def tracking_error(self, goal: Sequence[float] | np.ndarray) -> float:
        actual = [s[0] for s in self.client.getJointStates(self.robot, self.joints)]
        return float(np.max(np.abs(np.subtract(actual, goal))))

    def set_config(self, config: Sequence[float]) -> None:
        """Put the robot at `config` without stepping (a collision check);
        the joints' targets follow, sent before the world is stepped next
        (`_flush`: a collision check sets many configurations in a row)."""
        super().set_config(config)
        self._stale = True

    def _flush(self) -> None:
        """Send the joints' targets to the configuration last set, if it was
        set since they were last sent."""
        if self._stale:
            self._command(self.config)

    def _command(self, target: Sequence[float] | np.ndarray, velocity: np.ndarray | None = None) -> None:
        """The joints' position targets (and velocities: 0 without), and the
        fingers' when `_grip` changed since they were last sent (PyBullet
        keeps a motor's target until it is sent another)."""
        self._set(self.joints, np.asarray(target, float).tolist(),
                  self._still if velocity is None else velocity.tolist(), self._efforts, self._gains)
        self._stale = False
        grip = [self._grip[j] for j in self._grip]
        if grip != self._sent_grip:
            self._set(list(self._grip), grip, [0.0] * len(grip), self._grip_forces, self._grip_gains)
            self._sent_grip = grip

    def _set(self, joints: list[int], targets: list[float], velocities: list[float], forces: list[float],
             gains: tuple[list[float], list[float]]) -> None:
        self._motors(
            self.robot, joints, pybullet.POSITION_CONTROL, targetPositions=targets, targetVelocities=velocities,
            forces=forces, positionGains=gains[0], velocityGains=gains[1])

    # -- the hand -------------------------------------------------------------

    def close_hand(self, name: str | None = None, grasp: str | None = None) -> bool:
        """Close the fingers; when both then touch object `name`, firm the
        grasp (module doc) and hold it with `grasp`.  Whether it is held."""
        self._grip = {j: self.client.getJointInfo(self.robot, j)[8] for j in self._open}
        self._move_fingers()
        if name is None or grasp is None or not self.fingers_touch(name):
            return False
        self.held, self.grasp = name, grasp
        if self.firm:
            self._firm(name)
        self.sync()
        in_hand = self.ee_pose().inverse() @ self.poses[name]  # as held, for collision checks
        centre_offset = self.geometry.shapes[name].centre_offset()
        self._in_hand = (in_hand.xyz, in_hand.quat)
        self._centre = (centre_offset.xyz, centre_offset.quat)
        return True

    def _firm(self, name: str) -> None:
        """The fixed constraint between the hand and object `name`, at their
        pose relative to each other now."""
        body = self.bodies[name]
        link = self.client.getLinkState(self.robot, self.ee_link, computeForwardKinematics=True)
        centre = self.client.getBasePositionAndOrientation(body)
        inverse = self.client.invertTransform(link[0], link[1])
        xyz, quat = self.client.multiplyTransforms(inverse[0], inverse[1], centre[0], centre[1])
        self._constraint = self.client.createConstraint(
            self.robot, self.ee_link, body, -1, pybullet.JOINT_FIXED, [0, 0, 0], parentFramePosition=xyz,
            childFramePosition=[0, 0, 0], parentFrameOrientation=quat)
        self.client.changeConstraint(self._constraint, maxForce=FIRM_FORCE)

    def open_hand(self) -> None:
        """Remove the firming constraint and open the fingers: the object,
        released, settles."""
        if self._constraint is not None:
            self.client.removeConstraint(self._constraint)
            self._constraint = None
        self.held, self.grasp = None, None
        self._grip = dict(self._open)
        self._move_fingers()
        self.settle()

    def _move_fingers(self) -> None:
        """Drive the fingers to their targets (`_grip`) until the hand's
        opening stops changing: the fingers' speeds summed slower than
        `FINGER_REST` for `REST_STEPS` steps in a row, after `REST_STEPS`
        steps at least (closed on the object: the two may still drift
        together while they press it, the opening does not change; or at
        their limit), or every finger within `OPEN_ENOUGH` of its target;
        at most `GRIP_STEPS`."""
        self._command(self.config)
        fingers = list(self.fingers)
        targets = [self._grip[j] for j in fingers]
        calm = 0
        for taken in range(1, GRIP_STEPS + 1):
            self.step()
            states = self.client.getJointStates(self.robot, fingers)
            calm = calm + 1 if abs(sum(state[1] for state in states)) < FINGER_REST else 0
            if taken > REST_STEPS and (calm >= REST_STEPS or all(
                    abs(state[0] - target) <= OPEN_ENOUGH for state, target in zip(states, targets))):
                break

    def fingers_touch(self, name: str) -> bool:
        """Whether the fingers hold object `name` between them: every finger
        touches it (PyBullet's contact points) and stopped short of closing
        fully (fingers pressed on its top, or beside it, close all the way)."""
        body = self.bodies[name]
        closed = [self.client.getJointInfo(self.robot, j)[8] for j in self.fingers]
        at = [s[0] for s in self.client.getJointStates(self.robot, list(self.fingers))]
        return (all(self.client.getContactPoints(self.robot, body, j, -1) for j in self.fingers)
                and all(a > c + STOPPED for a, c in zip(at, closed)))

    def robot_touches(self, name: str) -> bool:
        return bool(self.client.getContactPoints(self.robot, self.bodies[name]))

    # -- the objects ----------------------------------------------------------

    def place(self, name: str, pose: Pose) -> None:
        """Put object `name` at `pose` at rest (a human's hand: kinematic),
        then let it settle."""
        super().place(name, pose)
        self._wake(name)
        self.client.resetBaseVelocity(self.bodies[name], [0, 0, 0], [0, 0, 0])
        self.settle()

    def stands(self, name: str, pose: Pose) -> bool:
        """Whether object `name`, taken from where it is and put at rest at
        `pose`, stays there under gravity, and every other object stays
        where it is (nothing stood on it).  At once where it lies on a
        static obstacle (the table, a board) and nothing touches it where it
        is; else the world is stepped `STAND_STEPS` from the move and put
        back as it was (PyBullet's saved state): no object may have moved
        more than `STAND_SHIFT` metres or radians.  Remembered while the
        objects stand where they are (to 0.1 mm)."""
        key = (name, pose, tuple(sorted((n, _rounded(p)) for n, p in self.poses.items() if n != self.held)))
        if key not in self._stands:
            self._stands[key] = self._stays(name, pose)
        return self._stands[key]

    def _stays(self, name: str, pose: Pose) -> bool:
        body = self.bodies[name]
        before = self.poses[name]
        others = [b for n, b in self.bodies.items() if n not in (name, self.held)]
        if not any(self.client.getContactPoints(body, other) for other in others):
            self._place_body(name, pose)
            on_obstacle = any(self.client.getClosestPoints(body, o, STAND_SHIFT) for o in self.obstacles)
            self._place_body(name, before)
            if on_obstacle:
                return True
        self._flush()
        saved = self.client.saveState()
        bodies = [body, *others]
        start = [self.client.getBasePositionAndOrientation(b) for b in bodies]
        try:
            self._place_body(name, pose)
            self._wake(name)
            self.client.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0])
            start[0] = self.client.getBasePositionAndOrientation(body)
            for _ in range(STAND_STEPS):
                self.client.stepSimulation()
            end = [self.client.getBasePositionAndOrientation(b) for b in bodies]
        finally:
            self.client.restoreState(saved)
            self.client.removeState(saved)
            self.poses[name] = before
        return all(math.dist(a[0], b[0]) <= STAND_SHIFT
                   and Pose(tuple(a[0]), tuple(a[1])).angle_to(Pose(tuple(b[0]), tuple(b[1]))) <= STAND_SHIFT
                   for a, b in zip(start, end))

    def blocked(self, name: str, pose: Pose) -> set[str]:
        """As in the kinematic world, and `robot` also where the object would
        come within `CLEARANCE` of the robot: a human does not put an object
        against the hand (which would drag it along as it leaves)."""
        before, body = self.poses[name], self.bodies[name]
        self._place_body(name, pose)  # placed once for both questions
        hits = self._hits(body, ignore={name}, robot=False)
        if self.client.getClosestPoints(self.robot, body, CLEARANCE):  # penetrating it, too
            hits.add("robot")
        self._place_body(name, before)
        self.client.resetBaseVelocity(body, [0, 0, 0], [0, 0, 0])
        return hits


def _steady(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A leg of `n` steps at one speed: the fraction of the leg the target
    has gone after each step, and its speed (as a fraction of the leg's)."""
    return np.arange(1, n + 1) / n, np.ones(n)


def _stopping(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A path's last leg, of `n` steps at one speed, slowing to rest at
    its end: the speed falls evenly to 0 over its last `STOP_STEPS` (at
    most 2n) steps, which go half as far as at the leg's speed, so the leg
    takes half as many steps longer.  Fractions and speeds as `_steady`'s."""
    ramp = min(STOP_STEPS, 2 * n)
    cruise = n - ramp / 2  # steps at the leg's speed
    t = np.minimum(np.arange(1, math.ceil(n + ramp / 2) + 1), n + ramp / 2)
    slowed = np.clip(t - cruise, 0.0, None)  # steps into the ramp
    return (t - slowed ** 2 / (2 * ramp)) / n, 1.0 - slowed / ramp


def _rounded(pose: Pose) -> tuple[float, ...]:
    """A pose to 0.1 mm and 1e-4 of a quaternion's components."""
    return tuple(round(v, 4) for v in (*pose.xyz, *pose.quat))
