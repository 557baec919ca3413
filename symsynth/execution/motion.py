"""Moving the robot through the world: a rule's evidence path from the
costmap when its assumptions hold, otherwise a path planned at run time.

**Evidence paths.**  For a transit or transfer between two anchors, the
rules of the costmap whose `free` places are all free in the world
(no object other than the served one stands on them) are tried cheapest
first.  Each rule's path is checked in the world -- objects where they
really are -- at `CHECK` times the planner's resolution; the first that
touches nothing is followed.  A path that touches something although its
rule's assumptions hold is a *rejected evidence path*: the costmap claimed
a motion the world does not allow, which the simulator reports loudly.

**Run-time planning** (no anchor at one end, no rule holds, or every
evidence path was rejected): first the straight joint-space segment; else
a roadmap grown by the shared OMPL PRM builder (`planning/prm.py`) in the
current world -- a configuration is valid when the planner finds no
self- or static collision and the world finds no penetration of an object
where it really stands; a segment asks the planner once for all its steps
(`motion_contacts`, which a planner may batch), then the world step by
step -- searched for its shortest start-goal path, which
is then shortened greedily (from each waypoint, straight to the farthest
later one the segment to which is free).  Everything is seeded, nothing is
timed, so the same run gives the same path.  The roadmap grows from
`RUNTIME_SIZE` vertices up to three times that; beyond, the motion fails.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from symsynth.errors import SymsynthError
from symsynth.execution.world import SimWorld
from symsynth.planning.costmaps import RoadmapSearch
from symsynth.planning.prm import build_roadmap
from symsynth.planning.protocol import Config, Mode, Planner, PlannerError
from symsynth.planning.segment import segment
from symsynth.planning.verify import path_length
from symsynth.scene.costmap import Costmap

CHECK = 4  # world checks per planner resolution step (as `costmap verify`)
RUNTIME_SIZE = 60  # roadmap vertices for a motion planned at run time


class MotionFailed(SymsynthError):
    """No collision-free motion was found in the world."""


@dataclass(frozen=True)
class Motion:
    """A path to follow and where it came from: `evidence` (a costmap
    rule's), `runtime` (planned now) or `none` (already there)."""

    path: tuple[Config, ...]
    source: str

    @property
    def radians(self) -> float:
        return path_length(self.path)


def steps(path: Sequence[Config], resolution: float) -> Iterator[tuple[float, ...]]:
    """The configurations along `path`, each leg cut by the planners'
    stepping rule (`planning.segment`), every waypoint included."""
    if len(path) == 0:
        return
    yield tuple(path[0])
    for a, b in zip(path, path[1:]):
        yield from (tuple(q) for q in segment(a, b, resolution)[1:])


def touched(world: SimWorld, path: Sequence[Config], resolution: float) -> set[str]:
    """What the robot (and the held object) penetrate along `path`, the
    first configuration that touches anything deciding; the robot is back
    at the path's start afterwards."""
    start = world.config
    found: set[str] = set()
    for config in steps(path, resolution):
        world.set_config(config)
        found = world.touching()
        if found:
            break
    world.set_config(start)
    return found


def evidence_motion(world: SimWorld, costmap: Costmap, mode: Mode, start: str, goal: str,
                    free: frozenset[str], resolution: float) -> tuple[Motion | None, list[str]]:
    """The cheapest rule for `start -> goal` whose places are all `free` and
    whose evidence path touches nothing in the world (None when there is
    none), and the rules tried before it whose paths touched something."""
    rejected = []
    rules = sorted((r for r in costmap.rules(str(mode), start, goal) if r.free <= free and r.path),
                   key=lambda r: r.cost)
    for rule in rules:
        path = tuple(tuple(q) for q in rule.path)
        if not np.allclose(path[0], world.config, atol=1e-9):
            path = (world.config,) + path  # a robot a hair off the anchor travels the hair too
        hits = touched(world, path, resolution / CHECK)
        if not hits:
            return Motion(path, "evidence"), rejected
        rejected.append(f"{mode} {start} -> {goal} (free {_names(rule.free)}, cost {rule.cost:g}) "
                        f"touches {', '.join(sorted(hits))}")
    return None, rejected


def runtime_motion(world: SimWorld, planner: Planner, mode: Mode, goal: Config, resolution: float,
                   seed: int) -> Motion:
    """A path from the robot's configuration to `goal` in the current world."""
    start = world.config

    def valid(q) -> bool:  # the world for the objects where they stand, the planner for the rest
        world.set_config(q)
        return not world.touching(obstacles=False) and not planner.contacts(mode, tuple(q)).static

    def free(a, b) -> bool:  # the planner's question for the whole segment at once (batched)
        if planner.motion_contacts(mode, tuple(a), tuple(b), resolution / CHECK).static:
            return False
        for q in steps((a, b), resolution / CHECK):
            world.set_config(q)
            if world.touching(obstacles=False):
                return False
        return True

    try:
        if tuple(start) == tuple(goal):
            return Motion((tuple(start),), "none")
        if free(start, goal):
            return Motion((tuple(start), tuple(goal)), "runtime")
        if not valid(goal):
            raise MotionFailed(f"the goal configuration collides in the world ({_what(world)})")
        roadmap = build_roadmap(planner.limits, valid, free, {"start": start, "goal": goal},
                                RUNTIME_SIZE, seed, resolution)
        path = _shortest(roadmap)
        return Motion(_shortcut(path, free), "runtime")
    except PlannerError as error:
        raise MotionFailed(f"no path in mode {mode}: {error}") from None
    finally:
        world.set_config(start)


def _shortest(roadmap) -> list[tuple[float, ...]]:
    """The shortest roadmap path from the anchor `start` to `goal` (the
    costmaps' search, with no edge blocked)."""
    search = RoadmapSearch(roadmap, [frozenset()] * len(roadmap.edges), ())
    path = search.best_path(search.vertex("start"), search.vertex("goal"), frozenset())
    if path is None:
        raise PlannerError("start and goal are not connected")
    return [search.config(v) for v in path.vertices]


def _shortcut(path: list[tuple[float, ...]], free) -> tuple[tuple[float, ...], ...]:
    """Greedy: from each kept waypoint, on to the farthest later waypoint
    that a free straight segment reaches."""
    out, i = [path[0]], 0
    while i < len(path) - 1:
        j = next(j for j in range(len(path) - 1, i, -1) if j == i + 1 or free(path[i], path[j]))
        out.append(path[j])
        i = j
    return tuple(out)


def _what(world: SimWorld) -> str:
    return ", ".join(sorted(world.touching())) or "the robot itself or a static obstacle"


def _names(places: frozenset[str]) -> str:
    return "{" + ", ".join(sorted(places)) + "}"
