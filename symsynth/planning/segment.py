"""The straight-segment stepping rule: a straight joint-space motion is
checked at `n + 1` evenly spaced configurations, both ends included, with
`n` the least number of steps (at least one) whose euclidean joint-space
length is at most `step`.  Every planner plugin and the simulator
cut motions this way, so that they check the same configurations."""

from __future__ import annotations

import math

import numpy as np

from symsynth.planning.protocol import Config, PlannerError


def segment(start: Config | np.ndarray, goal: Config | np.ndarray, step: float) -> np.ndarray:
    """(n + 1, d) configurations from `start` to `goal`, at most
    `step` apart (euclidean), both ends included."""
    if not step > 0:
        raise PlannerError(f"the check step must be positive, got {step}")
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    n = max(1, math.ceil(float(np.linalg.norm(goal - start)) / step))
    return start + (goal - start) * (np.arange(n + 1) / n)[:, None]
