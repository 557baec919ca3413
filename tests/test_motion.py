"""Run-time planning (`execution.motion.runtime_motion`) around an object in
the way, with a point robot in the unit square: the world and the planner
are stand-ins small enough to check by hand."""

from __future__ import annotations

import math

import numpy as np

from symsynth.execution.motion import CHECK, _shortcut, runtime_motion, steps
from symsynth.planning.protocol import Contacts, Mode

START, GOAL = (0.2, 0.2), (0.8, 0.2)
RESOLUTION = 0.05


class WallWorld:
    """The robot touches `wall` when 0.45 < x < 0.55 and y < 0.7."""

    def __init__(self) -> None:
        self.config = START

    def set_config(self, config) -> None:
        self.config = tuple(float(v) for v in config)

    def touching(self, obstacles: bool = True) -> set[str]:  # the wall is an object: always checked
        x, y = self.config
        return {"wall"} if 0.45 < x < 0.55 and y < 0.7 else set()


class FreePlanner:
    """Nothing static anywhere in the unit square."""

    limits = np.array([[0.0, 1.0], [0.0, 1.0]])

    def contacts(self, mode: Mode, config) -> Contacts:
        return Contacts()

    def motion_contacts(self, mode: Mode, start, goal, resolution: float) -> Contacts:
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


def test_the_shortcut_keeps_the_farthest_free_waypoint_from_each_kept_one():
    """A hand-made path up the wall's left side, over it and down: from
    each kept waypoint the next is the farthest one a free straight segment
    reaches, so every kept segment is free and no kept waypoint reaches
    any but its successor in a straight line."""
    path = [(0.2, 0.2), (0.25, 0.4), (0.3, 0.6), (0.35, 0.75), (0.45, 0.8), (0.5, 0.85), (0.55, 0.8),
            (0.65, 0.75), (0.7, 0.6), (0.75, 0.4), (0.8, 0.2)]
    world = WallWorld()

    def free(a, b) -> bool:
        for q in steps((a, b), RESOLUTION / CHECK):
            world.set_config(q)
            if world.touching():
                return False
        return True

    kept = _shortcut(path, free)
    assert kept[0] == path[0] and kept[-1] == path[-1]
    assert [path.index(q) for q in kept] == sorted(path.index(q) for q in kept)  # waypoints, in order
    assert all(free(a, b) for a, b in zip(kept, kept[1:]))
    assert not any(free(kept[i], kept[j]) for i in range(len(kept)) for j in range(i + 2, len(kept)))
    assert len(kept) < len(path)
