"""Grab and drop: the hand closes on a grasp, or opens over a location.

The game charges the scene's fixed costs (`costs: {grab, drop}`); the
simulator carries them out with `execution.primitives` (approach along the
grasp's axis, close or open, retreat)."""

from __future__ import annotations

from typing import Any, ClassVar

from symsynth.execution import primitives as world_primitives


class Grab:
    name: ClassVar[str] = "grab"
    kind: ClassVar[str] = "prehensile"

    def execute(self, world: Any, approaches: Any, move: Any) -> Any:
        return world_primitives.grab(world, approaches, move.obj, move.grasp)


class Drop:
    name: ClassVar[str] = "drop"
    kind: ClassVar[str] = "prehensile"

    def execute(self, world: Any, approaches: Any, move: Any) -> Any:
        return world_primitives.drop(world, approaches, move.location)
