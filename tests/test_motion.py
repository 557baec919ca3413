"""Run-time planning (`execution.motion.runtime_motion`) around an object in
the way, with a point robot in the unit square: the world and the planner
are stand-ins small enough to check by hand.  The lazy search (search the
roadmap, check the path's edges, remove the colliding ones, search again)
is compared with the eager way it replaced: check every edge while the
roadmap grows, then search."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from symsynth.execution.motion import (CHECK, RUNTIME_SIZE, LazyEdges, MotionFailed, _shortcut, _unchecked,
                                       lazy_shortest, runtime_motion, steps, world_checks)
from symsynth.planning.methods import RoadmapSearch
from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import Contacts, Mode, PlannerError

START, GOAL = (0.2, 0.2), (0.8, 0.2)
CHECK_STEP = 0.05  # radians between collision checks (the planner's check_step)


class WallWorld:
    """The robot touches `wall` when 0.45 < x < 0.55 and y < 0.7."""

    def __init__(self) -> None:
        self.config = START

    def set_config(self, config) -> None:
        self.config = tuple(float(v) for v in config)

    def touching(self, obstacles: bool = True) -> set[str]:  # the wall is an object: always checked
        x, y = self.config
        return {"wall"} if 0.45 < x < 0.55 and y < 0.7 else set()


class BoxesWorld:
    """The robot touches box `k` when it is strictly inside `boxes[k]`,
    given as (x0, x1, y0, y1)."""

    def __init__(self, start, boxes) -> None:
        self.config, self.boxes = tuple(start), boxes

    def set_config(self, config) -> None:
        self.config = tuple(float(v) for v in config)

    def touching(self, obstacles: bool = True) -> set[str]:
        x, y = self.config
        return {f"box{k}" for k, (x0, x1, y0, y1) in enumerate(self.boxes) if x0 < x < x1 and y0 < y < y1}


WALL = (0.45, 0.55, -1.0, 0.7)  # WallWorld's wall
# start, goal, boxes: around the wall; above it (the roadmap's direct
# start-goal edge is free); a zigzag between two walls; through a gap in a bar
CASES = {
    "wall": (START, GOAL, [WALL]),
    "open": ((0.2, 0.8), (0.8, 0.8), [WALL]),
    "zigzag": ((0.1, 0.1), (0.9, 0.9), [(0.3, 0.4, -1.0, 0.7), (0.6, 0.7, 0.3, 2.0)]),
    "gap": ((0.5, 0.1), (0.5, 0.9), [(-1.0, 0.6, 0.45, 0.55), (0.75, 2.0, 0.45, 0.55)]),
}


def free_in(world):
    """The world's own answer for a segment, counting the segments asked."""
    asked = []

    def free(a, b) -> bool:
        asked.append((tuple(a), tuple(b)))
        for q in steps((a, b), CHECK_STEP / CHECK):
            world.set_config(q)
            if world.touching():
                return False
        return True

    return free, asked


def valid_in(world):
    def valid(q) -> bool:
        world.set_config(q)
        return not world.touching()

    return valid


def eager_shortest(roadmap, free) -> float:
    """Every edge checked, then Dijkstra (scipy's, on the free edges)."""
    keep = np.array([free(roadmap.configs[i], roadmap.configs[j]) for i, j in roadmap.edges], dtype=bool)
    n = len(roadmap.configs)
    graph = coo_matrix((roadmap.lengths[keep], (roadmap.edges[keep, 0], roadmap.edges[keep, 1])), shape=(n, n))
    return float(dijkstra(graph.tocsr(), directed=False, indices=roadmap.anchors["start"])[roadmap.anchors["goal"]])


def eager_motion(world, planner, goal, seed):
    """The way run-time planning went before the lazy search: a roadmap
    whose edges are all checked as it grows, its shortest path, shortcut."""
    valid, free = world_checks(world, planner, Mode(), CHECK_STEP)
    start = world.config
    roadmap = build_roadmap(planner.limits, valid, free, {"start": start, "goal": goal}, RUNTIME_SIZE, seed,
                            CHECK_STEP)
    search = RoadmapSearch(roadmap, [frozenset()] * len(roadmap.edges), ())
    path = search.best_path(search.vertex("start"), search.vertex("goal"), frozenset())
    world.set_config(start)
    return roadmap, _shortcut([search.config(v) for v in path.vertices], free)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("case", sorted(CASES))
def test_the_lazy_search_finds_the_eager_shortest_path_checking_only_some_edges(case, seed):
    """On one roadmap of every candidate edge: the lazy path's segments are
    all free, it is exactly as long as the shortest path over the edges an
    eager check keeps, and fewer edges were checked than the roadmap has."""
    start, goal, boxes = CASES[case]
    world = BoxesWorld(start, boxes)
    free, asked = free_in(world)
    roadmap = build_roadmap(FreePlanner.limits, valid_in(world), _unchecked, {"start": start, "goal": goal},
                            RUNTIME_SIZE, seed, CHECK_STEP)
    path = lazy_shortest(roadmap, free)
    checked = len(asked)
    assert len(set(asked)) == checked < len(roadmap.edges)  # each edge at most once, and not all
    assert np.allclose(path[0], start) and np.allclose(path[-1], goal)
    for q in steps(path, CHECK_STEP / CHECK):
        world.set_config(q)
        assert world.touching() == set(), q
    length = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    assert length == pytest.approx(eager_shortest(roadmap, free), abs=1e-12)
    if case != "open":
        assert length > math.dist(start, goal) + 0.01  # a detour was needed


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("case", sorted(CASES))
def test_run_time_planning_gives_the_eager_roadmaps_path(case, seed):
    """The eager builder's roadmap is the lazy roadmap's free part (same
    vertices, and the free candidate edges are its edges), and here both
    stop at the same size: the shortcut paths are identical."""
    start, goal, boxes = CASES[case]
    world = BoxesWorld(start, boxes)
    motion = runtime_motion(world, FreePlanner(), Mode(), goal, CHECK_STEP, seed)
    assert world.config == start
    eager_roadmap, eager_path = eager_motion(BoxesWorld(start, boxes), FreePlanner(), goal, seed)
    free, _ = free_in(BoxesWorld(start, boxes))
    if free(start, goal):
        assert motion.path == (start, goal)
        return
    lazy_roadmap = build_roadmap(FreePlanner.limits, valid_in(world), _unchecked, {"start": start, "goal": goal},
                                 len(eager_roadmap.configs) - 2, seed, CHECK_STEP)
    assert np.array_equal(lazy_roadmap.configs, eager_roadmap.configs)
    keep = [free(lazy_roadmap.configs[i], lazy_roadmap.configs[j]) for i, j in lazy_roadmap.edges]
    assert np.array_equal(lazy_roadmap.edges[keep], eager_roadmap.edges)
    assert motion.path == eager_path


@pytest.mark.parametrize("size, seed", [(6, 1), (6, 2), (20, 3)])
def test_a_path_found_only_after_the_roadmap_grew_is_the_grown_roadmaps_shortest(size, seed):
    """A narrow gap (x in 0.47..0.53) the first roadmap does not pass: the
    edges checked before a growth step keep their verdicts after it (by
    vertex number), each edge is checked once, and the path is free and as
    short as the grown roadmap's free edges allow."""
    start, goal = (0.1, 0.1), (0.9, 0.9)
    world = BoxesWorld(start, [(-1.0, 0.47, 0.45, 0.55), (0.53, 2.0, 0.45, 0.55)])
    free, asked = free_in(world)
    lazy = LazyEdges(free)
    roadmap = build_roadmap(FreePlanner.limits, valid_in(world), _unchecked, {"start": start, "goal": goal},
                            size, seed, CHECK_STEP, outside=lazy.outside)
    assert len(roadmap.configs) > size + 2  # it grew
    assert len(set(asked)) == len(asked)
    path = lazy.path
    assert np.allclose(path[0], start) and np.allclose(path[-1], goal)
    for q in steps(path, CHECK_STEP / CHECK):
        world.set_config(q)
        assert world.touching() == set(), q
    length = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    assert length == pytest.approx(eager_shortest(roadmap, free_in(BoxesWorld(start, world.boxes))[0]), abs=1e-12)


def test_a_goal_walled_in_fails_with_the_eager_message():
    """Start and goal never joined: every edge ends up checked, the roadmap
    grows to three times its size, and the message names the goal as the
    eager builder did."""
    ring = [(0.6, 0.9, 0.6, 0.65), (0.6, 0.9, 0.85, 0.9), (0.6, 0.65, 0.6, 0.9), (0.85, 0.9, 0.6, 0.9)]
    start, goal = (0.2, 0.2), (0.75, 0.75)
    with pytest.raises(MotionFailed) as lazy:
        runtime_motion(BoxesWorld(start, ring), FreePlanner(), Mode(), goal, CHECK_STEP, seed=0)
    with pytest.raises(PlannerError) as eager:
        eager_motion(BoxesWorld(start, ring), FreePlanner(), goal, seed=0)
    assert str(lazy.value) == f"no path in mode {Mode()}: {eager.value}"
    assert f"after {3 * RUNTIME_SIZE} samples" in str(lazy.value) and str(lazy.value).endswith(": goal")


class FreePlanner:
    """Nothing static anywhere in the unit square."""

    limits = np.array([[0.0, 1.0], [0.0, 1.0]])

    def contacts(self, mode: Mode, config) -> Contacts:
        return Contacts()

    def motion_contacts(self, mode: Mode, start, goal, step: float) -> Contacts:
        return Contacts()


def test_a_blocked_straight_motion_goes_around_the_wall_on_the_roadmaps_shortest_path():
    world = WallWorld()
    motion = runtime_motion(world, FreePlanner(), Mode(), GOAL, CHECK_STEP, seed=0)
    assert motion.source == "runtime" and world.config == START
    assert motion.path[0] == START and np.allclose(motion.path[-1], GOAL)
    hits = []
    for q in steps(motion.path, CHECK_STEP / CHECK):
        world.set_config(q)
        hits += world.touching()
    assert hits == []
    # over the wall's top corners at best: 2 * |(0.25, 0.5)| + 0.1
    assert motion.radians >= 2 * math.hypot(0.25, 0.5) + 0.1 - 1e-9
    assert motion.radians < 2.5  # the greedy shortcut leaves no long detour
    again = runtime_motion(WallWorld(), FreePlanner(), Mode(), GOAL, CHECK_STEP, seed=0)
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
        for q in steps((a, b), CHECK_STEP / CHECK):
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
