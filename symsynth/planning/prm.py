"""Roadmaps grown by OMPL's PRM, shared by every planner plugin.

`build_roadmap` knows nothing of robots or simulators: it takes the joint
limits and two callables (is a configuration free of static collisions, is
the straight joint-space motion between two configurations), grows an OMPL
`PRM` roadmap and reads its graph back into a `Roadmap`.

Conventions, and what OMPL 2.x's Python bindings make us do:

* The anchors are the first milestones, in the order given (anchors with
  identical configurations share one vertex).  A Python `ValidStateSampler`
  hands them out before it draws uniform samples, because `PRM` takes start
  and goal states only inside `solve`, which runs a second thread and stops
  at the first solution.  `Roadmap.configs` lists the milestones in the order
  they were added, so anchor vertices come first.
* Determinism: OMPL's global seed (`ompl.util.RNG.setSeed`) can be set once
  per process, before the first RNG exists, so it cannot give each call its
  own seed.  The sampler therefore draws from `numpy.random.default_rng(seed)`,
  only `growRoadmap` is used (never `expandRoadmap`, whose random walks use
  OMPL's RNG), and growth stops at a milestone count.  Same inputs and
  seed, same roadmap.  The exception is a time limit (`seconds`, the scene's
  `planner: {seconds: S}`): growth then stops when the time is up, so the
  roadmap depends on the machine and its load, and the same seed no longer
  gives the same roadmap (the milestones are still the seed's sequence,
  only where it stops varies).
* `PRM` completes its setup only when it has a problem definition (without
  one it crashes on its first edge); an empty one with the path-length
  objective is given.
* `PlannerData` lists each edge in both directions and leaves isolated
  milestones out; we keep each undirected edge once, as `(i, j)` with
  `i < j`, sorted, and compute the euclidean lengths ourselves.

An anchor is connected when it lies in the roadmap's largest connected
component (`outside_largest_component`; a caller may judge connection
otherwise, see `build_roadmap`'s `outside`).  Growth continues, `size // 2` milestones at a time, up to
`GROWTH * size` sampled milestones (with a time limit: `seconds / 2` at a
time, up to `GROWTH * seconds`); anchors still outside after that raise
`PlannerError` naming them.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from symsynth.planning.protocol import Config, PlannerError, Roadmap

GROWTH = 3  # at most this many times `size` sampled milestones
ATTEMPTS = 1000  # rejected samples in a row before the free space counts as empty
NEIGHBOURS = 10  # PRM's k: each new milestone tries its k nearest

Validity = Callable[[np.ndarray], bool]
MotionValidity = Callable[[np.ndarray, np.ndarray], bool]
Outside = Callable[[Roadmap], list[str]]


def build_roadmap(limits: np.ndarray, valid: Validity, motion_valid: MotionValidity,
                  anchors: Mapping[str, Config], size: int, seed: int, step: float,
                  seconds: float | None = None, outside: Outside | None = None) -> Roadmap:
    """A PRM roadmap of the anchors plus about `size` sampled milestones, or
    (when `seconds` is given, and then `size` is not used) the milestones
    added in `seconds` of growth.

    `limits` is (d, 2), lower and upper bound per joint; `valid(q)` is false
    for a configuration in static collision; `motion_valid(a, b)` checks the
    straight segment (its callers step along it at `step` radians, which is
    also given to OMPL as its state validity checking resolution).

    `outside(roadmap)` names the anchors a grown roadmap leaves unconnected
    (default `outside_largest_component`); growth goes on while it names
    any, and the error names them.  PRM offers each new milestone's k
    nearest earlier milestones to `motion_valid`, whatever it answered
    before, so a caller that checks edges itself later (lazily) passes a
    `motion_valid` that accepts every motion and judges connection in its
    `outside`: it then sees every candidate edge, of which the ones its own
    check accepts are exactly the edges an eager `motion_valid` would have
    kept (same vertices, in the same order)."""
    limits = np.asarray(limits, dtype=float)
    if limits.ndim != 2 or limits.shape[1] != 2 or np.any(limits[:, 0] > limits[:, 1]):
        raise PlannerError(f"joint limits must be (d, 2) with lower <= upper, got {limits.tolist()}")
    if not (size >= 1 and step > 0):  # written so that NaN fails too
        raise PlannerError(f"roadmap size must be >= 1 and check step > 0, got {size} and {step}")
    if seconds is not None and not seconds > 0:
        raise PlannerError(f"a roadmap time limit must be positive, got {seconds} s")
    points, index = _anchor_milestones(limits, valid, anchors)
    draws = _Draws(limits, valid, points, seed)
    prm, space_info, _alive = _prm(limits, valid, motion_valid, draws, step)

    judge = outside_largest_component if outside is None else outside
    budget = _Budget(len(points), size, seconds)
    while True:
        _grow(prm, draws, budget.done(prm))
        roadmap = _read(prm, space_info, draws, index)
        left = judge(roadmap)
        if not left:
            return roadmap
        if budget.spent():
            raise PlannerError(
                f"anchors not connected to the roadmap after {budget.describe(prm)} "
                f"(k = {NEIGHBOURS}, seed {seed}): {', '.join(left)}")
        budget.extend()


class _Budget:
    """When growth stops: at a milestone count (`size` sampled milestones,
    then `size // 2` more at a time, up to `GROWTH * size`), or at a time
    (`seconds` of growth, then `seconds / 2` more at a time, up to
    `GROWTH * seconds`)."""

    def __init__(self, anchors: int, size: int, seconds: float | None):
        self.anchors, self.size, self.seconds = anchors, size, seconds
        self.target = anchors + size  # milestones
        self.halves = 2  # the growth time allowed so far, in halves of `seconds`
        self.used = 0.0  # seconds of growth so far

    def done(self, prm: og.PRM) -> Callable[[], bool]:
        if self.seconds is None:
            return lambda: prm.milestoneCount() >= self.target
        start = time.monotonic()
        deadline = start + self.seconds * self.halves / 2 - self.used

        def over() -> bool:
            now = time.monotonic()
            if now < deadline:
                return False
            self.used += now - start
            return True
        return over

    def spent(self) -> bool:
        if self.seconds is None:
            return self.target >= self.anchors + GROWTH * self.size
        return self.halves >= 2 * GROWTH

    def extend(self) -> None:
        self.target += max(1, self.size // 2)
        self.halves += 1

    def describe(self, prm: og.PRM) -> str:
        if self.seconds is None:
            return f"{self.target - self.anchors} samples"
        return f"{self.seconds * self.halves / 2:g} s of growth ({prm.milestoneCount() - self.anchors} samples)"


def _anchor_milestones(limits: np.ndarray, valid: Validity,
                       anchors: Mapping[str, Config]) -> tuple[list[np.ndarray], dict[str, int]]:
    """The distinct anchor configurations, in order, and each anchor's index."""
    points: list[np.ndarray] = []
    seen: dict[tuple[float, ...], int] = {}
    index: dict[str, int] = {}
    outside, colliding = [], []
    for name, config in anchors.items():
        q = np.asarray(config, dtype=float)
        if q.shape != (len(limits),):
            raise PlannerError(f"anchor {name} has {q.size} joint values, the robot has {len(limits)}")
        if np.any(q < limits[:, 0]) or np.any(q > limits[:, 1]):
            outside.append(name)
        elif not valid(q):
            colliding.append(name)
        key = tuple(q.tolist())
        if key not in seen:
            seen[key] = len(points)
            points.append(q)
        index[name] = seen[key]
    if outside or colliding:
        problems = ([f"outside the joint limits: {', '.join(outside)}"] if outside else []) + \
                   ([f"in static collision: {', '.join(colliding)}"] if colliding else [])
        raise PlannerError("anchors cannot be roadmap vertices: " + "; ".join(problems))
    return points, index


class _Draws:
    """The anchors first, then uniform valid samples from a seeded numpy
    generator; records every configuration handed out, which is exactly
    PRM's milestones in order."""

    def __init__(self, limits: np.ndarray, valid: Validity, anchors: list[np.ndarray], seed: int):
        self.limits, self.valid = limits, valid
        self.pending = list(anchors)
        self.rng = np.random.default_rng(seed)
        self.milestones: list[np.ndarray] = []
        self.exhausted = False
        self.samplers: list[_Sampler] = []  # the bindings do not keep Python samplers alive

    def sampler(self, space_info: ob.SpaceInformation) -> _Sampler:
        """OMPL's allocator callback."""
        self.samplers.append(_Sampler(space_info, self))
        return self.samplers[-1]

    def next(self) -> np.ndarray | None:
        q: np.ndarray | None
        if self.pending:
            q = self.pending.pop(0)
        else:
            q = next((q for q in self._uniform() if self.valid(q)), None)
            self.exhausted = q is None
        if q is not None:
            self.milestones.append(q)
        return q

    def _uniform(self):
        for _ in range(ATTEMPTS):
            yield self.rng.uniform(self.limits[:, 0], self.limits[:, 1])


class _Sampler(ob.ValidStateSampler):
    def __init__(self, space_info: ob.SpaceInformation, draws: _Draws):
        super().__init__(space_info)
        self.draws = draws

    def sample(self, state: ob.State) -> bool:
        q = self.draws.next()
        if q is None:
            return False
        for i, value in enumerate(q.tolist()):
            state[i] = value
        return True

    def sampleNear(self, state: ob.State, near: ob.State, distance: float) -> bool:
        return False  # PRM's growRoadmap never asks


class _MotionValidator(ob.MotionValidator):
    def __init__(self, space_info: ob.SpaceInformation, dimension: int, motion_valid: MotionValidity):
        super().__init__(space_info)
        self.dimension, self.motion_valid = dimension, motion_valid

    def checkMotion(self, a: ob.State, b: ob.State) -> bool:
        return bool(self.motion_valid(_config(a, self.dimension), _config(b, self.dimension)))


def _config(state: ob.State, dimension: int) -> np.ndarray:
    return np.array(state[0:dimension], dtype=float)


def _prm(limits: np.ndarray, valid: Validity, motion_valid: MotionValidity, draws: _Draws,
         step: float) -> tuple[og.PRM, ob.SpaceInformation, tuple]:
    """The PRM, its space information, and the Python objects OMPL holds
    pointers to (the bindings do not keep them alive for us)."""
    ou.setLogLevel(ou.LOG_WARN)
    dimension = len(limits)
    space = ob.RealVectorStateSpace(dimension)
    bounds = ob.RealVectorBounds(dimension)
    for i, (low, high) in enumerate(limits.tolist()):
        bounds.setLow(i, low)
        bounds.setHigh(i, high)
    space.setBounds(bounds)
    space_info = ob.SpaceInformation(space)
    space_info.setStateValidityChecker(lambda state: bool(valid(_config(state, dimension))))
    validator = _MotionValidator(space_info, dimension, motion_valid)
    space_info.setMotionValidator(validator)
    space_info.setValidStateSamplerAllocator(draws.sampler)
    extent = space.getMaximumExtent()
    space_info.setStateValidityCheckingResolution(min(1.0, step / extent) if extent > 0 else 1.0)
    space_info.setup()
    problem = ob.ProblemDefinition(space_info)
    problem.setOptimizationObjective(ob.PathLengthOptimizationObjective(space_info))
    prm = og.PRM(space_info)
    prm.setMaxNearestNeighbors(NEIGHBOURS)
    prm.setProblemDefinition(problem)
    prm.setup()
    return prm, space_info, (space, validator, draws, problem)


def _grow(prm: og.PRM, draws: _Draws, stop: Callable[[], bool]) -> None:
    done = ob.PlannerTerminationCondition(lambda: draws.exhausted or stop())
    prm.growRoadmapPtc(done)
    if draws.exhausted:
        raise PlannerError(f"no configuration free of static collisions in {ATTEMPTS} uniform samples "
                           f"(after {prm.milestoneCount()} milestones)")
    if prm.milestoneCount() != len(draws.milestones):
        raise PlannerError(f"OMPL's PRM holds {prm.milestoneCount()} milestones, the sampler handed out "
                           f"{len(draws.milestones)}: the roadmap cannot be read back")


def _read(prm: og.PRM, space_info: ob.SpaceInformation, draws: _Draws,
          anchors: dict[str, int]) -> Roadmap:
    configs = np.array(draws.milestones, dtype=float)
    order = {tuple(q.tolist()): i for i, q in enumerate(configs)}
    data = ob.PlannerData(space_info)
    prm.getPlannerData(data)
    dimension = configs.shape[1]
    vertex = [order[tuple(_config(data.getVertex(v).getState(), dimension).tolist())]
              for v in range(data.numVertices())]
    pairs = {tuple(sorted((vertex[v], vertex[w])))
             for v in range(data.numVertices()) for w in data.getEdges(v)}
    edges = np.array(sorted(pairs), dtype=np.int64).reshape(-1, 2)
    lengths = np.linalg.norm(configs[edges[:, 0]] - configs[edges[:, 1]], axis=1)
    return Roadmap(configs=configs, edges=edges, lengths=lengths, anchors=dict(anchors))


def outside_largest_component(roadmap: Roadmap) -> list[str]:
    """Anchors outside the largest connected component (ties: the component
    of the lowest vertex)."""
    n = len(roadmap.configs)
    if not roadmap.anchors:
        return []
    edges = roadmap.edges
    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    sizes = np.bincount(label)
    main = label[int(np.argmax(sizes[label]))]
    return [name for name, i in roadmap.anchors.items() if label[i] != main]
