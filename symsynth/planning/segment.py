"""The straight-segment stepping rule: a straight joint-space motion is
checked at `n + 1` evenly spaced configurations, both ends included, with
`n` the least number of steps (at least one) whose euclidean joint-space
length is at most `resolution`.  Every planner plugin and the simulator
cut motions this way, so that they check the same configurations."""

from __future__ import annotations

import math

import numpy as np

from symsynth.planning.protocol import Config, PlannerError


def segment(start: Config | np.ndarray, goal: Config | np.ndarray, resolution: float) -> np.ndarray:
    """(n + 1, d) configurations from `start` to `goal`, at most
    `resolution` apart (euclidean), both ends included."""
    if not resolution > 0:
        raise PlannerError(f"resolution must be positive, got {resolution}")
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    n = max(1, math.ceil(float(np.linalg.norm(goal - start)) / resolution))
    return start + (goal - start) * (np.arange(n + 1) / n)[:, None]
