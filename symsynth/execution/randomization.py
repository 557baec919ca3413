"""The ranges a physical world is randomized in (`simulate --randomize`,
`execution.physics`): each object's mass and friction, and the obstacles'
friction, scaled by a factor drawn uniformly in [1 - r, 1 + r]; each
object's initial pose shifted on the table by up to `pose` metres in x and y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from symsynth.errors import InputError


@dataclass(frozen=True)
class Randomization:
    """Relative ranges for friction and mass, metres for initial poses."""

    friction: float = 0.0
    mass: float = 0.0
    pose: float = 0.0

    KEYS = ("friction", "mass", "pose")

    @staticmethod
    def parse(text: str) -> Randomization:
        """`friction=0.2,mass=0.2,pose=0.005` (any of the three)."""
        values: dict[str, float] = {}
        for part in filter(None, (p.strip() for p in text.split(","))):
            key, _, value = part.partition("=")
            key = key.strip()
            if key not in Randomization.KEYS or not value:
                raise InputError(f"--randomize: expected KEY=VALUE with KEY one of {', '.join(Randomization.KEYS)}"
                                 f" (e.g. friction=0.2,mass=0.2,pose=0.005), found {part!r}")
            try:
                number = float(value)
            except ValueError:
                raise InputError(f"--randomize: {key} must be a number, found {value!r}") from None
            if not math.isfinite(number) or number < 0 or (key != "pose" and number >= 1):
                raise InputError(f"--randomize: {key} must be " + ("a distance >= 0 in metres" if key == "pose"
                                 else "a relative range in [0, 1)") + f", found {value}")
            values[key] = number
        return Randomization(**values)

    def __str__(self) -> str:
        return ",".join(f"{key}={getattr(self, key):g}" for key in self.KEYS)
