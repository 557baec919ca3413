"""Run-time planning (`execution.motion.runtime_motion`) around an object in
the way, with a point robot in the unit square: the world and the planner
are stand-ins small enough to check by hand."""

from __future__ import annotations

import math

import numpy as np

from symsynth.execution.motion import CHECK, runtime_motion, steps
from symsynth.planning.protocol import Contacts, Mode

START, GOAL = (0.2, 0.2), (0.8, 0.2)
RESOLUTION = 0.05


class WallWorld:
    """The robot touches `wall` when 0.45 < x < 0.55 and y < 0.7."""

    def __init__(self) -> None:
        self.config = START

    def set_config(self, config) -> None:
        self.config = tuple(float(v) for v in config)

    def touching(self) -> set[str]:
        x, y = self.config
        return {"wall"} if 0.45 < x < 0.55 and y < 0.7 else set()


class FreePlanner:
    """Nothing static anywhere in the unit square."""

    limits = np.array([[0.0, 1.0], [0.0, 1.0]])

    def contacts(self, mode: Mode, config) -> Contacts:
        return Contacts()


def test_a_blocked_straight_motion_goes_around_the_wall_on_the_roadmaps_shortest_path():
    world = WallWorld()
    motion = runtime_motion(world, FreePlanner(), Mode(), GOAL, RESOLUTION, seed=0)
    assert motion.source == "runtime" and world.config == START
    assert motion.path[0] == START and np.allclose(motion.path[-1], GOAL)
    hits = []
    for q in steps(motion.path, RESOLUTION / CHECK):
        world.set_config(q)
        hits += world.touching()
    assert hits == []
    # over the wall's top corners at best: 2 * |(0.25, 0.5)| + 0.1
    assert motion.radians >= 2 * math.hypot(0.25, 0.5) + 0.1 - 1e-9
    assert motion.radians < 2.5  # the greedy shortcut leaves no long detour
    again = runtime_motion(WallWorld(), FreePlanner(), Mode(), GOAL, RESOLUTION, seed=0)
    assert again.path == motion.path
