"""One primitive tried in the physical world, apart from any strategy: the
small API a verifier, a conformance suite or a benchmark calls ("execute
this slide from this start in physics, return where the object ended").

`slide_trial` builds a `PhysicsWorld` holding only the slid object (so no
other object stands on any place, and every rule's `free` set holds), puts
the object on the slide's start (shifted by the randomization's pose), the
robot on the first configuration of the path, lets the world settle, has
the displacement primitive execute the move, lets the world settle again
and reports where the object ended (`Outcome`).  While the primitive runs,
every step is watched: how far the object moved at a step when the robot
touched it, and when it did not (a primitive that sets the object's pose
moves it without touching it: `Outcome.untouched`; an object set from one
place to another jumps farther in one step than anything pushed at a
walking pace: `Outcome.jump`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from symsynth.execution.observe import POSITION, distance
from symsynth.execution.physics import PhysicsWorld, Randomization
from symsynth.game.abstraction import Move, State
from symsynth.primitive_registry import displacement
from symsynth.scene.geometry import Pose
from symsynth.scene.model import Scene

COAST = 24  # steps after the hand last touched the object during which it may still slide (0.1 s)


@dataclass(frozen=True)
class Outcome:
    """Where a tried primitive left its object, and how it got there."""

    end: Pose  # the object's pose once settled
    target: Pose  # where the abstraction says it is
    error: float  # metres between the two
    pushed: float  # metres the object moved at steps while the robot touched it (or just had)
    untouched: float  # metres it moved at steps while nothing of the robot had touched it for COAST steps
    jump: float  # the most it moved in one step (metres)
    tipped: float  # radians between its end orientation and the target's

    @property
    def success(self) -> bool:
        """The object ended within the observation's tolerance of the target."""
        return self.error <= POSITION


def slide_trial(scene: Scene, obj: str, contact: str, start: str, goal: str, path: tuple[tuple[float, ...], ...],
                *, primitive: Any = None, randomization: Randomization | None = None, seed: int = 0) -> Outcome:
    """Slide `obj` with `contact` from location `start` to `goal` along
    `path` (a slide rule's evidence, anchor to anchor) in a physical world
    of its own; `primitive` is the displacement plugin that executes it
    (default: the contact's)."""
    geometry = scene.geometry
    if geometry is None:
        raise ValueError(f"scene {scene.name!r} has no geometry")
    plugin = primitive if primitive is not None else displacement(geometry.contacts[contact].primitive)
    spec = next(o for o in scene.objects if o.name == obj)
    alone = dataclasses.replace(scene, objects=(dataclasses.replace(spec, at=start),), task=None)
    world = PhysicsWorld(alone, randomization=randomization, seed=seed)
    try:
        world.set_config(path[0])
        world.settle()
        watch = _Watch(world, obj)
        world.watch = watch
        after = State((goal,), None, (obj, contact))  # what the abstraction says (semantics §4b)
        move = Move("slide", f"slide({obj},{contact},{goal})", obj, 0, contact, goal, after=after)
        plugin.execute(world, move, path)
        world.settle()
        world.watch = None
        end, target = world.poses[obj], geometry.places[goal]
        return Outcome(end, target, distance(end, target), watch.pushed, watch.untouched, watch.jump,
                       end.angle_to(target))
    finally:
        world.close()


class _Watch:
    """After every step: how far the object moved, and whether the robot touches it."""

    def __init__(self, world: PhysicsWorld, obj: str) -> None:
        self.obj, self.body = obj, world.bodies[obj]
        self.last = self._where(world)
        self.since = COAST + 1  # steps since the robot last touched the object
        self.pushed = self.untouched = self.jump = 0.0

    def _where(self, world: PhysicsWorld) -> tuple[float, ...]:
        return tuple(world.client.getBasePositionAndOrientation(self.body)[0])

    def __call__(self, world: PhysicsWorld) -> None:
        here = self._where(world)
        moved = math.dist(here, self.last)
        self.last = here
        self.since = 0 if world.robot_touches(self.obj) else self.since + 1
        self.jump = max(self.jump, moved)
        if self.since <= COAST:
            self.pushed += moved
        else:
            self.untouched += moved


def slide_trials(scene: Scene, obj: str, contact: str, start: str, goal: str,
                 path: tuple[tuple[float, ...], ...], trials: int, *, primitive: Any = None,
                 randomization: Randomization | None = None, seed: int = 0) -> list[Outcome]:
    """`slide_trial` `trials` times, seeds `seed`, `seed + 1`, ...: the
    success rate of a slide rule in a family of randomized worlds is
    `sum(o.success for o in outcomes) / trials`."""
    return [slide_trial(scene, obj, contact, start, goal, path, primitive=primitive, randomization=randomization,
                        seed=seed + i) for i in range(trials)]
