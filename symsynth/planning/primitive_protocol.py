"""Motion primitives as plugins, found through the entry-point group
`symsynth.primitives` (the built-ins register the same way: pyproject.toml).

Two kinds, the two the game knows (docs/game-semantics.md §4, §4b):

* *prehensile*: a grasp closes or opens the hand (`grab`, `drop`); the game
  charges the scene's fixed cost, and the simulator runs the primitive's
  `execute`;
* *displacement*: the hand stands at a *contact* of an object (a pose
  relative to it, like a grasp's, but the hand never closes) and slides the
  object from one location to another (`push`, `pull`).  Such a primitive
  answers which slides are geometrically possible, with the end-effector's
  Cartesian path, the places its swept volume touches and its cost: the
  costmap's slide rules (`SlideRule`).

A plugin is a class with the attributes and methods of `Prehensile` or
`Displacement`; `symsynth.testing.primitive` pins what they mean.  The
registry itself (`symsynth.primitive_registry`) sits below the scene, which checks
the primitive each contact names.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol, runtime_checkable

from symsynth.planning.protocol import Config, Planner
from symsynth.primitive_registry import (KINDS, PREHENSILE_ACTIONS, PrimitiveError, displacement,
                                         prehensile_primitives, primitive, primitive_names)
from symsynth.scene.geometry import Geometry
from symsynth.scene.model import Scene

__all__ = ["KINDS", "PREHENSILE_ACTIONS", "Displacement", "Prehensile", "PrimitiveError", "SlideRule",
           "displacement", "prehensile_primitives", "primitive", "primitive_names"]


@dataclass(frozen=True)
class SlideRule:
    """One slide a displacement primitive can make, as the costmap records
    it: contact `contact` moves `obj` from location `start` to `goal` at
    `cost` (radians along `path` x per_radian, plus the primitive's fixed
    cost) if every place in `free` is free; `path` is the robot's
    configurations along it, from the anchor `start/contact` to the anchor
    `goal/contact`."""

    contact: str
    start: str
    goal: str
    free: frozenset[str]
    cost: float
    path: tuple[Config, ...]


@runtime_checkable
class Prehensile(Protocol):
    """The game's grab and drop (`primitive_registry.PREHENSILE_ACTIONS`) are
    each carried out by the prehensile primitive registered under that
    name.  The costmap asks both where and on what they can act: a holding
    mode `o/g` gets motions only if every one `holds` o with g, and only
    between the anchors `x/g` every one `reaches`."""

    name: ClassVar[str]
    kind: ClassVar[str]  # "prehensile"

    def holds(self, geometry: Geometry, obj: str, grasp: str) -> bool:
        """Whether the hand can hold `obj` with grasp `grasp` (a box wider
        than the gripper opens cannot be grabbed)."""

    def reaches(self, scene: Scene, planner: Planner, place: str, grasp: str, anchor: Config) -> bool:
        """Whether the primitive can act at `place` with `grasp`, the robot
        at the anchor `place/grasp` (configuration `anchor`): e.g. the hand
        comes down to the grasp pose without meeting a static obstacle."""

    def execute(self, world: Any, approaches: Any, move: Any) -> Any:
        """Carry out `move` (the game's `Move`: its object, grasp, location)
        in the simulator's world; `approaches` plans the hand's straight
        approach paths."""


@runtime_checkable
class Displacement(Protocol):
    name: ClassVar[str]
    kind: ClassVar[str]  # "displacement"
    #: Cost of one slide besides the motion (radians x per_radian); a scene
    #: may set it under `costs: {NAME: c}`.
    fixed_cost: ClassVar[float]

    def slides(self, scene: Scene, planner: Planner, contact: str,
               anchors: Mapping[str, Config]) -> list[SlideRule]:
        """Every slide with `contact` between two locations of interest that
        is geometrically possible for some object of `scene` (its shape, its
        size), with its path checked by `planner` against static obstacles,
        starting and ending at the anchors' configurations."""

    def execute(self, world: Any, move: Any, path: tuple[Config, ...]) -> Any:
        """Carry out the slide `move` (the game's `Move`: object, contact,
        target location) in the simulator's world along `path`, the evidence
        of its slide rule: in the kinematic world the object moves with the
        contact; in the physical one (`execution.physics.PhysicsWorld`) it
        must move only as the robot pushes it (`execution.trial` watches).
        Returns what `execution.hand_motions` returns (`path`, `touched`,
        `radians`)."""
