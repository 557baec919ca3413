"""Push and pull: the hand at a contact slides an object along the table.

Both follow `planning.slides`' three segments (approach, slide, retreat),
and in both the hand leads: the slide goes the way the hand faces at the
contact (its z axis, projected on the table, within `TOLERANCE`), the
object ahead of it.  They differ in where that takes the object:

* `push` (a contact behind the object, on the robot's side): away from
  the robot's base;
* `pull` (a contact on the far side): toward the robot's base, drawing the
  object out, e.g. from under a shelf.

Any object can be slid: no grasp is needed, so a box wider than the
gripper opens can still be pushed.  In the kinematic simulator the object
keeps its pose relative to the hand while it slides; in the physical one
(`simulate --world physics`) the fingers close and the hand pushes it,
slowing near it, and it moves only by contact (`execution.primitives`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from symsynth.execution import hand_motions
from symsynth.planning.primitive_protocol import SlideRule
from symsynth.planning.protocol import Config, Planner
from symsynth.planning.slides import direction, slide_rule
from symsynth.scene.model import Scene, geometry_of

TOLERANCE = math.radians(20)


class _Slide:
    kind: ClassVar[str] = "displacement"
    fixed_cost: ClassVar[float] = 2.0
    name: ClassVar[str]
    outward: ClassVar[bool]  # the slide takes the object away from the robot's base

    def slides(self, scene: Scene, planner: Planner, contact: str,
               anchors: Mapping[str, Config]) -> list[SlideRule]:
        geometry = geometry_of(scene)
        fixed = geometry.primitive_costs.get(self.name, self.fixed_cost)
        found = []
        for start in scene.locations:
            for goal in scene.locations:
                if start == goal or not self.possible(scene, contact, start, goal):
                    continue
                # one slide rule serves every object (semantics §4b keys it by contact and
                # locations): it must hold for each shape, so it needs all their places free and
                # costs the dearest; a shape that cannot make the slide rules it out
                per_shape: dict[str, SlideRule | None] = {}
                for obj in scene.object_names:
                    shape = repr(geometry.shapes[obj])
                    if shape not in per_shape:
                        per_shape[shape] = slide_rule(scene, planner, obj, contact, start, goal, anchors, fixed)
                rules = [rule for rule in per_shape.values() if rule is not None]
                if rules and len(rules) == len(per_shape):
                    dearest = max(rules, key=lambda rule: rule.cost)
                    free = frozenset[str]().union(*(rule.free for rule in rules))
                    found.append(dataclasses.replace(dearest, free=free))
        return found

    def possible_pairs(self, scene: Scene, contact: str) -> list[tuple[str, str]]:
        """The (from, to) pairs of locations whose direction suits the primitive."""
        return [(a, b) for a in scene.locations for b in scene.locations
                if a != b and self.possible(scene, contact, a, b)]

    def possible(self, scene: Scene, contact: str, start: str, goal: str) -> bool:
        """The hand leads (the slide within TOLERANCE of its facing), and the
        slide goes away from the robot's base (push) or toward it (pull)."""
        if direction(scene, contact, start, goal) > TOLERANCE:
            return False
        geometry = geometry_of(scene)
        places, base = geometry.places, np.asarray(geometry.robot.base.xyz[:2])
        farther = (np.linalg.norm(np.asarray(places[goal].xyz[:2]) - base)
                   > np.linalg.norm(np.asarray(places[start].xyz[:2]) - base))
        return farther == self.outward

    def execute(self, world: Any, move: Any, path: tuple[Config, ...]) -> Any:
        return hand_motions.slide(world, move, path)


class Push(_Slide):
    name: ClassVar[str] = "push"
    outward: ClassVar[bool] = True


class Pull(_Slide):
    name: ClassVar[str] = "pull"
    outward: ClassVar[bool] = False

