"""A physical scene's conditional costmap, computed by a planner plugin.

The steps of the paper's Alg. 1 (lines 4-6): anchors by inverse kinematics;
one roadmap per *geometric* mode against static obstacles; the location
obstacles each roadmap edge touches, checked once; then every motion of
every mode is a graph search (`methods`).  Modes that look the same to a
planner (the same grasp on objects of the same shape, among the same other
shapes) share one roadmap and its checks.
"""

from __future__ import annotations

import dataclasses
import os
import time
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

from tqdm import tqdm

from symsynth.errors import InputError, SymsynthWarning
from symsynth.parallel import Executor, LocalPool
from symsynth.planning import cache
from symsynth.planning.methods import METHODS, costmap_for_mode
from symsynth.planning.anchors import anchor_configs, mode_queries
from symsynth.planning.protocol import Config, Mode, Planner, PlannerError, Roadmap
from symsynth.planning.registry import planner_class, planner_version
from symsynth.planning.support import lifted, resting
from symsynth.primitive_registry import displacement, prehensile_primitives
from symsynth.scene.costmap import Costmap, CostmapError, Provenance, Rule, SlideKey, costmap_from_data
from symsynth.scene.load import costmap_problems
from symsynth.scene.model import Scene, geometry_of


@dataclass
class Stats:
    """Where the time went, for reports and the benchmark."""

    seconds: dict[str, float] = field(default_factory=lambda: {
        "anchors": 0.0, "roadmaps": 0.0, "edge checks": 0.0, "searches": 0.0, "slides": 0.0})
    roadmaps: int = 0
    vertices: int = 0
    edges: int = 0
    motions: int = 0
    rules: int = 0
    searches: int = 0
    workers: int = 1  # processes that built roadmaps; their seconds are summed
    wall: float = 0.0  # seconds from start to end, as a clock on the wall measures them

    def add(self, phase: str, since: float) -> float:
        now = time.perf_counter()
        self.seconds[phase] += now - since
        return now


def _geometric_key(scene: Scene, mode: Mode) -> tuple:
    """Modes with equal keys see the same static and location geometry."""
    shapes = geometry_of(scene).shapes
    if mode.object is None:
        return ("empty",)
    others = sorted(repr(shapes[o]) for o in shapes if o != mode.object)
    return (mode.grasp, repr(shapes[mode.object]), tuple(others))


def mode_anchors(planner: Planner, mode: Mode, configs: dict) -> dict[str, tuple[Config, frozenset[str]]]:
    """The anchors a mode's roadmap must connect, each with the places its
    configuration touches in that mode: all anchors in the empty mode; in a
    holding mode the `x/g` of its grasp where the held object is clear of
    static obstacles (elsewhere the object cannot be held).  One contact
    check per anchor serves the whole geometric mode."""
    suffix = None if mode.object is None else f"/{mode.grasp}"
    found = {}
    for name, q in configs.items():
        if suffix is not None and not name.endswith(suffix):
            continue
        contacts = planner.contacts(mode, q)
        if suffix is None or not contacts.static:
            found[name] = (q, contacts.locations)
    return found


def holds(scene: Scene, mode: Mode) -> bool:
    """A holding mode only when every prehensile primitive of the game can
    hold its object with its grasp (`Prehensile.holds`: a box wider than
    the opening cannot be held, and the costmap gets no motion in that
    mode); the empty hand always."""
    return mode.object is None or all(p.holds(geometry_of(scene), mode.object, mode.grasp)
                                      for p in prehensile_primitives())


def graspable(scene: Scene, planner: Planner, configs: dict[str, Config]) -> set[str]:
    """The grasp anchors `x/g` where every prehensile primitive of the game
    can act (`Prehensile.reaches`; each asked only where the ones before it
    said yes)."""
    names = {f"{x}/{g}" for x in scene.locations + scene.else_samples for g in scene.grasps}
    found = {n for n in names if n in configs}
    for plugin in prehensile_primitives():
        found = {n for n in found if plugin.reaches(scene, planner, *n.rsplit("/", 1), configs[n])}
    return found


def compute_costmap(scene: Scene, method: str, planner_name: str | None = None,
                    seed: int | None = None, progress: bool = True,
                    planner_factory: Callable[[Scene], Planner] | None = None,
                    executor: Executor | None = None) -> tuple[Costmap, Stats]:
    """The costmap of a physical scene by `method` (`sg` or `recursive`)."""
    found, stats = compute_costmaps(scene, (method,), planner_name, seed, progress, planner_factory, executor)
    return found[method], stats


def compute_costmaps(scene: Scene, methods: tuple[str, ...], planner_name: str | None = None,
                     seed: int | None = None, progress: bool = True,
                     planner_factory: Callable[[Scene], Planner] | None = None,
                     executor: Executor | None = None) -> tuple[dict[str, Costmap], Stats]:
    """The costmaps of several methods from one set of roadmaps and edge
    checks (the methods differ only in their graph searches).  The roadmaps
    of the modes are built in parallel: on the `executor` given, else on a
    local pool of a process per core.  The graph searches (about 1% of the
    time on the bundled scenes) run here."""
    if scene.geometry is None:
        raise PlannerError(f"scene {scene.name!r} is abstract (no robot): give it a costmap instead")
    for method in methods:
        if method not in METHODS:
            raise PlannerError(f"unknown costmap method {method!r}; known: {', '.join(METHODS)}")
    settings = scene.geometry.planner
    name = planner_name or settings.name
    seed = settings.seed if seed is None else seed
    stats = Stats()
    clock = begin = time.perf_counter()
    planner = _factory(scene, name, planner_factory)(scene)
    configs = anchor_configs(planner, scene)
    clock = stats.add("anchors", clock)

    modes = [m for m in map(Mode.parse, scene.modes) if holds(scene, m)]
    groups: dict[tuple, list[Mode]] = {}
    for mode in modes:
        groups.setdefault(_geometric_key(scene, mode), []).append(mode)
    result: dict[str, dict] = {method: {} for method in methods}
    bar = tqdm(total=len(groups), desc=f"costmap ({', '.join(methods)}, {name})", unit="mode",
               disable=None if progress else True, leave=False)
    jobs = _jobs(scene, planner, configs, groups, bar)
    if planner_factory is not None:  # a factory given in this process: the jobs run here
        executor = None
    workers = 1 if planner_factory is not None else min(len(jobs), os.cpu_count() or 1)
    stats.workers = max(workers if executor is None else executor.workers, 1)
    built = _roadmaps(scene, name, planner, jobs, settings, seed, workers, bar, executor)
    clock = time.perf_counter()
    support = resting(scene)
    for job, done in zip(jobs, built):
        _search(scene, job, done, methods, support, result, stats)
    clock = stats.add("searches", clock)
    slides = slide_rules(scene, planner, configs, support)
    stats.add("slides", clock)
    bar.close()
    stats.rules = sum(len(r) for found in result.values() for r in found.values())
    stats.wall = time.perf_counter() - begin
    return {method: Costmap(dict(sorted(found.items())), provenance(scene, method, name, seed), slides,
                            scene.geometry.absent)
            for method, found in result.items()}, stats


def _jobs(scene: Scene, planner: Planner, configs: dict[str, Config], groups: dict[tuple, list[Mode]],
          bar: tqdm) -> list[tuple[list[Mode], dict]]:
    """One roadmap job per group of geometrically equal modes: the modes and
    their anchors (an object's mode keeps the anchors where it can be
    grasped); a group with no anchor has nothing to build."""
    jobs = []
    reached = graspable(scene, planner, configs)
    for members in groups.values():
        anchors = mode_anchors(planner, members[0], configs)
        if members[0].object is not None:
            anchors = {n: found for n, found in anchors.items() if n in reached}
        if anchors:
            jobs.append((members, anchors))
        else:
            bar.update()
    return jobs


def _search(scene: Scene, job: tuple[list[Mode], dict], done: tuple, methods: tuple[str, ...],
            support: Mapping[str, frozenset[str]], result: dict[str, dict], stats: Stats) -> None:
    """The graph searches of one built roadmap, for every mode of its group
    and every method, added into `result`."""
    assert scene.geometry is not None  # compute_costmaps refuses an abstract scene
    (members, anchors), (roadmap, blocked, seconds) = job, done
    stats.seconds["roadmaps"] += seconds[0]
    stats.seconds["edge checks"] += seconds[1]
    stats.roadmaps += 1
    stats.vertices += len(roadmap.configs)
    stats.edges += len(roadmap.edges)
    places = scene.locations + scene.else_samples
    for member in members:
        queries = physical_queries(scene, member, {n: touched for n, (_, touched) in anchors.items()})
        for method in methods:
            rules = costmap_for_mode(member, roadmap, blocked, queries, method, places, scene.geometry.per_radian)
            if member.object is not None:  # lifting an object from under another (support.py)
                rules = lifted(rules, support)
            result[method].update({key: value for key, value in rules.items() if value})
        stats.motions += len(queries)


def slide_rules(scene: Scene, planner: Planner, configs: dict[str, Config],
                support: Mapping[str, frozenset[str]]) -> dict[SlideKey, tuple[Rule, ...]]:
    """The slide rules of every contact, from its displacement primitive
    (`planning.primitive_protocol`); the same for every costmap method: a slide is
    one Cartesian path, not a roadmap search.  A slide from `x` also requires
    the places resting on `x` free (`support`, from `support.resting`)."""
    found: dict[SlideKey, list[Rule]] = {}
    for contact, spec in sorted(geometry_of(scene).contacts.items()):
        for rule in displacement(spec.primitive).slides(scene, planner, contact, configs):
            found.setdefault((rule.contact, rule.start, rule.goal), []).append(
                Rule(rule.free | support.get(rule.start, frozenset()), rule.cost, rule.path))
    return {key: tuple(sorted(rules, key=lambda r: (r.cost, sorted(r.free)))) for key, rules in sorted(found.items())}


def provenance(scene: Scene, method: str, planner_name: str, seed: int) -> Provenance:
    """What a costmap records of who built it (the file's key `planner`):
    everything `symsynth costmap` and the scene's planner settings chose."""
    settings = geometry_of(scene).planner
    return Provenance(planner_name, planner_version(planner_name), method, seed,
                      settings.roadmap_size if settings.seconds is None else None, settings.seconds,
                      settings.check_step)


def _factory(scene: Scene, name: str, planner_factory: Callable[[Scene], Planner] | None
             ) -> Callable[[Scene], Planner]:
    """The planner's class (or the factory given), checked before it is
    built (the pybullet planner loads its URDF then): an unknown name fails,
    and so does a roadmap time limit for a planner whose class does not
    declare `time_limited` (protocol.Planner.roadmap)."""
    factory = planner_factory or planner_class(name)
    if geometry_of(scene).planner.seconds is not None and not getattr(factory, "time_limited", False):
        raise PlannerError(f"the {name} planner has no roadmap time limit: give the scene's planner a "
                           f"roadmap_size instead of seconds")
    return factory


def _roadmaps(scene: Scene, name: str, planner: Planner, jobs: list, settings, seed: int, workers: int,
              bar, executor: Executor | None = None) -> list:
    """Roadmap and blocked-by sets of each job's mode, in job order; on
    several processes when there are several modes and cores, or on the
    `executor` given (each worker builds its own planner: the results do not
    depend on where they are computed)."""
    args = [(members[0], {name: q for name, (q, _) in anchors.items()}, settings.roadmap_size, seed,
             settings.check_step, settings.seconds) for members, anchors in jobs]
    results: list = []
    if executor is None and workers <= 1:
        for job in args:
            bar.set_postfix_str(f"{job[0]}: roadmap and edge checks")
            results.append(_roadmap_job(planner, *job))
            bar.update()
        return results
    results = [None] * len(args)
    with executor or LocalPool(workers) as running:
        for i, result in running.imap(_worker_job, args, setup=_start_worker, setup_args=(scene, name)):
            results[i] = result
            bar.update()
    return results


_worker_planner: Planner | None = None


def _start_worker(scene: Scene, name: str) -> None:
    """A worker's own planner."""
    global _worker_planner
    _worker_planner = planner_class(name)(scene)


def _worker_job(job):
    if _worker_planner is None:  # set by _start_worker, the pool's setup
        raise RuntimeError("a roadmap job ran in a worker whose planner was not started")
    return _roadmap_job(_worker_planner, *job)


def _roadmap_job(planner: Planner, mode: Mode, anchors: dict, size: int, seed: int, step: float,
                 seconds: float | None):
    start = time.perf_counter()
    if seconds is None:  # planners without a time limit need not take the parameter
        roadmap = planner.roadmap(mode, anchors, size, seed)
    else:
        roadmap = planner.roadmap(mode, anchors, size, seed, seconds=seconds)
    middle = time.perf_counter()
    blocked = edge_blockers(planner, mode, roadmap, step)
    return roadmap, blocked, (middle - start, time.perf_counter() - middle)


def physical_queries(scene: Scene, mode: Mode, touched: dict[str, frozenset[str]]) -> list:
    """The mode's motions between anchors it has, with what the robot's own
    body says about the places: where the start configuration touches the
    obstacle of a place, no object can stand there (the robot is in the way)
    when the motion begins, nor arrive before it ends (human moves happen
    between robot actions).  Such places join `never`.

    A transit whose start touches the place of the object it fetches (its
    `always`) begins in a situation that cannot happen: the object and the
    robot would overlap.  The game still asks for it, when the hand is
    empty at `ee = Else` ("the robot may be anywhere it has been", semantics §5),
    and takes the worst start; leaving the motion out would make it
    infinite and rule out the action for a position the robot cannot be in.
    Such a motion is costed as if the place were free, which is what holds
    whenever the robot really stands at that start.

    One exception follows the queries: a place resting on the start's place
    (`support.resting`) can hold an object when the hand lifts its support
    from under it, and every rule of a transfer from there requires it
    free (`support.lifted`).

    `touched` maps the mode's anchors to the places their configurations
    touch (`mode_anchors`); motions to or from other anchors are left out."""
    queries = []
    for query in mode_queries(scene, mode):
        if query.start not in touched or query.goal not in touched:
            continue
        free_at_start = touched[query.start]
        queries.append(dataclasses.replace(query, always=query.always - free_at_start,
                                           never=query.never | free_at_start))
    return queries


def edge_blockers(planner: Planner, mode: Mode, roadmap: Roadmap, step: float) -> list[frozenset[str]]:
    """The location obstacles each roadmap edge touches (computed once per roadmap)."""
    configs = roadmap.configs
    return [planner.motion_contacts(mode, tuple(configs[i]), tuple(configs[j]), step).locations
            for i, j in roadmap.edges]



@dataclass(frozen=True)
class Obtained:
    """A costmap and where it came from (for the report)."""

    costmap: Costmap
    method: str
    planner: str
    seed: int
    cached: bool
    path: Path | None  # the cache file, or None when caching is off
    stats: Stats | None


def _check_output(scene: Scene, costmap: Costmap, planner: str) -> None:
    """A planner's costmap passes the checks a costmap file does: its numbers
    and paths (`costmap_from_data` on what would be written) and its names
    (`costmap_problems`); a failure is the plugin's, and is named so."""
    try:
        costmap_from_data(costmap.to_json(), f"the costmap planner {planner!r} computed")
    except CostmapError as error:
        raise InputError(f"planner {planner!r} computed a costmap that is not valid: {error}") from None
    problems = costmap_problems(scene, costmap)
    if problems:
        raise InputError(f"planner {planner!r} computed a costmap that does not fit scene {scene.name!r}: "
                         + "; ".join(problems[:3]))


def obtain_costmap(scene: Scene, method: str = "recursive", planner_name: str | None = None,
                   seed: int | None = None, *, use_cache: bool = True, progress: bool = True,
                   planner_factory: Callable[[Scene], Planner] | None = None,
                   executor: Executor | None = None) -> Obtained:
    """The cached costmap of a physical scene, or a new one (then cached);
    its roadmaps built on `executor` (default: a local pool)."""
    settings = geometry_of(scene).planner
    name = planner_name or settings.name
    seed = settings.seed if seed is None else seed
    _factory(scene, name, planner_factory)  # fails before anything is hashed or computed
    path = cache.cache_path(scene, method, name, seed) if use_cache else None
    hit = None if path is None else cache.cached(path, scene)
    built = provenance(scene, method, name, seed)
    # A hit without a record predates it (the key says who built it); one
    # with another record was built by another version of the plugin (the
    # key has symsynth's version, not the plugin's): computed again.
    if hit is not None and path is not None and hit.provenance in (None, built):  # a hit has its path
        if hit.provenance is None:  # written back with its record, so the file says who built it
            hit = dataclasses.replace(hit, provenance=built)
            cache.store(hit, path)
        return Obtained(hit, method, name, seed, True, path, None)
    problem = None if path is None else cache.unwritable(path)
    if path is not None and problem is not None:  # said before the minutes of planning; the result is kept
        warnings.warn(f"the costmap cache {path.parent} cannot be written ({problem}): the costmap is "
                      "computed and used but not cached; set SYMSYNTH_CACHE to a writable folder, or "
                      "give -o FILE (symsynth costmap) to keep it", SymsynthWarning, stacklevel=2)
        path = None
    costmap, stats = compute_costmap(scene, method, name, seed, progress, planner_factory, executor)
    _check_output(scene, costmap, name)
    if path is not None:
        try:
            cache.store(costmap, path)
        except InputError as error:  # a full disk, say: the costmap is still this run's
            warnings.warn(f"{error}; the costmap is used but not cached", SymsynthWarning, stacklevel=2)
            path = None
    return Obtained(costmap, method, name, seed, False, path, stats)
