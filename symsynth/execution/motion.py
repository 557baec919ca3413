"""Moving the robot through the world: a rule's evidence path from the
costmap when its assumptions hold, otherwise a path planned at run time.

**Evidence paths.**  For a transit or transfer between two anchors, the
rules of the costmap whose `free` places are all free in the world
(no object other than the served one stands on them) are tried cheapest
first.  Each rule's path is checked in the world -- objects where they
really are -- at `CHECK` times the planner's check step; the first that
touches nothing is followed.  A path that touches something although its
rule's assumptions hold is a *rejected evidence path*: the costmap claimed
a motion the world does not allow, which the simulator reports loudly.

**Run-time planning** (no anchor at one end, no rule holds, or every
evidence path was rejected): first the straight joint-space segment; else
a roadmap grown by the shared OMPL PRM builder (`planning/prm.py`) in the
current world, searched first and checked later (the idea of LazyPRM).
A configuration is valid when the planner finds no self- or static
collision and the world finds no penetration of an object where it really
stands; vertices are checked as the roadmap grows, edges are not: the
roadmap keeps every candidate edge PRM offers (each milestone's k nearest
earlier ones).  Its shortest start-goal path is searched, only that
path's edges are checked -- a segment asks the planner once for all its
steps (`motion_contacts`, which a planner may batch), then the world step
by step -- in path order up to the first that collides, which is removed,
and the search is repeated, each edge checked at most once.  The first
path whose edges are all free is shortened greedily (from each waypoint,
straight to the farthest later one the segment to which is free).

Edge lengths do not depend on collisions, so that path is a shortest path
of the free edges.  The free candidate edges are exactly the edges of the
roadmap the builder grows when it checks every edge as it adds it (the
eager way, as costmap roadmaps are built and run-time planning was before:
same seed, same vertices in the same order, same candidates), so on a roadmap
of the same size the path is the same (up to ties between equally long
paths, which random vertices do not produce).  The sizes can differ: the
eager builder stops growing when start and goal lie in the largest
connected component of the free edges, the lazy one as soon as a free
path joins them; where the eager one grew further (start and goal joined
in a smaller component) it may find a shorter path on its larger roadmap,
or fail where the lazy one succeeds.
When start and goal are not joined by free edges, every remaining edge
is checked (what the eager builder did) to name the anchors outside the
largest component, and the roadmap grows, `RUNTIME_SIZE // 2` vertices at a
time, up to three times `RUNTIME_SIZE`; beyond, the motion fails with the
builder's message.  Everything is seeded, nothing is timed, so the same
run gives the same path.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np

from symsynth.errors import SymsynthError
from symsynth.execution.world import SimWorld
from symsynth.planning.methods import RoadmapSearch
from symsynth.planning.prm import build_roadmap, outside_largest_component
from symsynth.planning.protocol import Config, Mode, Planner, PlannerError, Roadmap
from symsynth.planning.segment import segment
from symsynth.planning.verify import path_length
from symsynth.scene.costmap import Costmap

CHECK = 4  # world checks per step of the planner's check_step (as `costmap verify`)
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


def steps(path: Sequence[Config], step: float) -> Iterator[tuple[float, ...]]:
    """The configurations along `path`, each leg cut by the planners'
    stepping rule (`planning.segment`), every waypoint included."""
    if len(path) == 0:
        return
    yield tuple(path[0])
    for a, b in zip(path, path[1:]):
        yield from (tuple(q) for q in segment(a, b, step)[1:])


def touched(world: SimWorld, path: Sequence[Config], step: float) -> set[str]:
    """What the robot (and the held object) penetrate along `path`, the
    first configuration that touches anything deciding; the robot is back
    at the path's start afterwards."""
    start = world.config
    found: set[str] = set()
    for config in steps(path, step):
        world.set_config(config)
        found = world.touching()
        if found:
            break
    world.set_config(start)
    return found


def evidence_motion(world: SimWorld, costmap: Costmap, mode: Mode, start: str, goal: str,
                    free: frozenset[str], step: float) -> tuple[Motion | None, list[str]]:
    """The cheapest rule for `start -> goal` whose places are all `free` and
    whose evidence path touches nothing in the world (None when there is
    none), and the rules tried before it whose paths touched something."""
    rejected: list[str] = []
    rules = sorted((r for r in costmap.rules(str(mode), start, goal) if r.free <= free), key=lambda r: r.cost)
    for rule in rules:
        if not rule.path:  # no evidence path to follow
            continue
        path = tuple(tuple(q) for q in rule.path)
        if not np.allclose(path[0], world.config, atol=1e-9):
            path = (world.config,) + path  # a robot a hair off the anchor travels the hair too
        hits = touched(world, path, step / CHECK)
        if not hits:
            return Motion(path, "evidence"), rejected
        rejected.append(f"{mode} {start} -> {goal} (free {_names(rule.free)}, cost {rule.cost:g}) "
                        f"touches {', '.join(sorted(hits))}")
    return None, rejected


def runtime_motion(world: SimWorld, planner: Planner, mode: Mode, goal: Config, step: float,
                   seed: int) -> Motion:
    """A path from the robot's configuration to `goal` in the current world."""
    start = world.config
    valid, free = world_checks(world, planner, mode, step)
    try:
        if tuple(start) == tuple(goal):
            return Motion((tuple(start),), "none")
        if free(start, goal):
            return Motion((tuple(start), tuple(goal)), "runtime")
        if not valid(goal):
            raise MotionFailed(f"the goal configuration collides in the world ({_what(world)})")
        lazy = LazyEdges(free)
        build_roadmap(planner.limits, valid, _unchecked, {"start": start, "goal": goal},
                      RUNTIME_SIZE, seed, step, outside=lazy.outside)
        if lazy.path is None:  # build_roadmap returns once `outside` has found a path
            raise MotionFailed(f"no path in mode {mode}: the roadmap joins start and goal by no free path")
        return Motion(_shortcut(lazy.path, free), "runtime")
    except PlannerError as error:
        raise MotionFailed(f"no path in mode {mode}: {error}") from None
    finally:
        world.set_config(start)


def world_checks(world: SimWorld, planner: Planner, mode: Mode, step: float):
    """`valid(q)` and `free(a, b)` in the current world: the world for the
    objects where they stand, the planner for the rest (self and static
    collisions).  Both leave the robot wherever they checked last."""

    def valid(q) -> bool:
        world.set_config(q)
        return not world.touching(obstacles=False) and not planner.contacts(mode, tuple(q)).static

    def free(a, b) -> bool:  # the planner's question for the whole segment at once (batched)
        if planner.motion_contacts(mode, tuple(a), tuple(b), step / CHECK).static:
            return False
        for q in steps((a, b), step / CHECK):
            world.set_config(q)
            if world.touching(obstacles=False):
                return False
        return True

    return valid, free


def _unchecked(a, b) -> bool:
    """The builder's edge check, deferred: every candidate edge is kept."""
    return True


class LazyEdges:
    """Search first, check later: the builder's judge of a grown roadmap
    (`build_roadmap(..., outside=...)`), which looks for a start-goal path
    whose edges `free` accepts and keeps it in `path`.

    `verdicts` remembers each checked edge, as `(i, j)` with `i < j`, checked
    from the older vertex `i` to `j` (the direction PRM checks an edge in);
    vertex numbers do not change as the roadmap grows, so the verdicts
    carry over from one size to the next."""

    def __init__(self, free) -> None:
        self.free = free
        self.verdicts: dict[tuple[int, int], bool] = {}
        self.path: list[tuple[float, ...]] | None = None

    def outside(self, roadmap: Roadmap) -> list[str]:
        self.path = lazy_shortest(roadmap, self.free, self.verdicts)
        if self.path is not None:
            return []
        # Not joined: judged as the eager builder judges it, for its growth and message.
        for i, j in roadmap.edges.tolist():
            _verdict(roadmap, self.free, self.verdicts, i, j)
        return outside_largest_component(_free_part(roadmap, self.verdicts))


def lazy_shortest(roadmap: Roadmap, free, verdicts: dict[tuple[int, int], bool] | None = None
                  ) -> list[tuple[float, ...]] | None:
    """The shortest path from the anchor `start` to `goal` of `roadmap`
    whose edges `free` accepts (configurations, start first), None if its
    free edges do not join them.  A shortest path is searched with the
    edges known to collide removed, its edges not checked yet are checked
    in path order up to the first that collides, and the search starts
    again, until a path's edges are all free.  `verdicts` (updated) holds
    the edges already checked."""
    verdicts = {} if verdicts is None else verdicts
    edges = roadmap.edges.tolist()
    start, goal = int(roadmap.anchors["start"]), int(roadmap.anchors["goal"])
    while True:
        blocked = [_COLLIDES if verdicts.get((min(i, j), max(i, j))) is False else _NOTHING for i, j in edges]
        search = RoadmapSearch(roadmap, blocked, _COLLIDES)
        path = search.best_path(start, goal, _COLLIDES)
        if path is None:
            return None
        if all(_verdict(roadmap, free, verdicts, a, b) for a, b in zip(path.vertices, path.vertices[1:])):
            return [search.config(v) for v in path.vertices]


_COLLIDES: frozenset[str] = frozenset({"collides"})
_NOTHING: frozenset[str] = frozenset()


def _verdict(roadmap: Roadmap, free, verdicts: dict[tuple[int, int], bool], a: int, b: int) -> bool:
    key = (min(a, b), max(a, b))
    if key not in verdicts:
        verdicts[key] = bool(free(roadmap.configs[key[0]], roadmap.configs[key[1]]))
    return verdicts[key]


def _free_part(roadmap: Roadmap, verdicts: dict[tuple[int, int], bool]) -> Roadmap:
    """`roadmap` with only the edges checked free."""
    keep = np.array([verdicts[i, j] for i, j in roadmap.edges.tolist()], dtype=bool).reshape(-1)
    return Roadmap(roadmap.configs, roadmap.edges[keep], roadmap.lengths[keep], roadmap.anchors)


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
