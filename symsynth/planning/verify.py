"""Re-check a costmap's evidence paths (`symsynth costmap verify`).

A rule `(F, c, path)` of a motion from anchor `s` to anchor `t` claims: with
every place outside `F` occupied (except the places the motion's `never` set
says cannot be, as `build.physical_queries` gives them), the robot can
follow `path` from `s`'s configuration to `t`'s, and it costs `c`.  Each
path's end points are compared with the anchors' configurations, the path
is checked again, at a finer check step than the one it was built with,
against the static obstacles and exactly those location obstacles, and its
cost is recomputed.  A failure is a bug in a planner or in the costmap
algorithms.

The anchors' configurations are the verifying planner's inverse kinematics
solutions (`anchor_configs`), so a costmap must be verified with the
planner that built it: another planner's solutions for the same poses
differ, and every rule would fail its end points.  The costmap records
that planner (`Costmap.provenance`), and `building_planner` holds to it.
(Comparing end-effector poses instead would need forward kinematics, which
the `Planner` protocol does not have, and a check that all paths through an
anchor use one configuration there, since the robot's motions chain at
anchors.)

Anchors a scene declares absent (`absent_at`, semantics §5) have no
configuration and no rule: loading the costmap against the scene already
checked that its `absent` list is the scene's and that no rule touches one.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from symsynth.errors import InputError
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.build import mode_anchors, physical_queries
from symsynth.planning.methods import Query
from symsynth.planning.protocol import Mode, Planner
from symsynth.planning.registry import planner_names
from symsynth.planning.slides import swept_places
from symsynth.primitive_registry import displacement
from symsynth.scene.costmap import Costmap
from symsynth.scene.geometry import point_text
from symsynth.scene.model import Scene, geometry_of

#: How far (radians, per joint) a path's end may be from its anchor's configuration.
ANCHOR_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Failure:
    mode: str
    start: str
    goal: str
    rule: int
    reason: str

    def __str__(self) -> str:
        return f"{self.mode} {self.start} -> {self.goal}, rule {self.rule}: {self.reason}"


def path_length(path) -> float:
    q = np.asarray(path, dtype=float)
    return float(np.linalg.norm(np.diff(q, axis=0), axis=1).sum()) if len(q) > 1 else 0.0


def building_planner(costmap: Costmap, given: str | None, source: str) -> str:
    """The planner to verify `costmap` with: the one it records, or, for a
    file without that record, the `given` one.  Another planner than the
    recorded one is refused rather than run: every rule would fail its end
    points, which says nothing about the paths (module doc).  (No override:
    to re-check a file whose record is wrong, remove the record and name
    the planner.)"""
    built = costmap.provenance
    if built is not None:
        installed_planner(built.name, source)
    if built is None:
        if given is None:
            raise InputError(f"{source} does not record the planner that built it (no key 'planner': written "
                             "by hand or by an older symsynth): give it with --planner NAME; its evidence paths "
                             "end at that planner's inverse kinematics solutions for the anchors")
        return given
    if given is not None and given != built.name:
        raise InputError(f"--planner {given}: {source} was built by planner {built.name!r} (its key 'planner'), "
                         f"and its evidence paths start and end at {built.name}'s inverse kinematics solutions "
                         f"for the anchors; {given}'s solutions differ, so every rule would fail its end points. "
                         f"Leave --planner out to verify with {built.name}")
    return built.name


def installed_planner(name: str, source: str) -> str:
    """`name`, recorded in the costmap `source` as its builder, if that
    planner is installed; else an error that names the file and its record
    (the user never typed the name) and the way out."""
    known = planner_names()
    if name not in known:
        raise InputError(f"{source} records planner {name!r} as its builder (its key 'planner'), which is not "
                         f"installed (installed: {', '.join(known) or 'none'}): install that planner's plugin, "
                         "or remove the key from the file and give --planner NAME")
    return name


def verify_costmap(costmap: Costmap, scene: Scene, planner: Planner, step: float,
                   progress: bool = True) -> tuple[int, list[Failure]]:
    """(rules checked, failures).  `step` is the step along each path, in
    radians (the command passes a quarter of the finer of the recorded
    build check step and the scene's);
    `planner` must be the one that built the costmap (module doc)."""
    places = frozenset(scene.locations + scene.else_samples)
    per_radian = geometry_of(scene).per_radian
    failures: list[Failure] = []
    configs = anchor_configs(planner, scene)
    limits = np.asarray(planner.limits, dtype=float)
    queries: dict[str, dict[tuple[str, str], Query]] = {}  # mode -> (start, goal) -> query, as built
    checked = 0
    items = [(key, i, rule) for key, rules in costmap.motions.items() for i, rule in enumerate(rules)]
    shown = None if progress else True  # None: on a terminal only
    for (mode_name, start, goal), i, rule in tqdm(items, desc="verify", unit="rule", disable=shown, leave=False):
        fail: Callable[[str], None] = lambda reason: failures.append(  # noqa: E731
            Failure(mode_name, start, goal, i, reason))
        checked += 1
        if mode_name not in scene.modes:
            fail("not a motion of this scene")
            continue
        mode = Mode.parse(mode_name)
        if mode_name not in queries:
            anchors = mode_anchors(planner, mode, configs)
            queries[mode_name] = {(q.start, q.goal): q for q in physical_queries(
                scene, mode, {name: touched for name, (_, touched) in anchors.items()})}
        query = queries[mode_name].get((start, goal))
        if query is None:
            fail("not a motion of this scene")
            continue
        if rule.path is None or len(rule.path) == 0:
            fail("no evidence path")
            continue
        outside = _outside_limits(rule.path, limits)
        if outside is not None:
            fail(outside)
            continue
        for end, point, anchor in (("starts", rule.path[0], start), ("ends", rule.path[-1], goal)):
            if not _same_config(point, configs[anchor]):
                fail(f"{end} at {point_text(point)}, not at anchor {anchor} {point_text(configs[anchor])}")
        if not math.isclose(rule.cost, per_radian * path_length(rule.path), rel_tol=1e-9, abs_tol=1e-9):
            fail(f"cost {rule.cost} but the path is {path_length(rule.path):.6f} rad "
                 f"x {per_radian} per radian = {per_radian * path_length(rule.path):.6f}")
        allowed = rule.free | query.never
        for a, b in zip(rule.path, rule.path[1:] or rule.path):
            contacts = planner.motion_contacts(mode, tuple(a), tuple(b), step)
            if contacts.static:
                fail("collides with the robot itself or a static obstacle")
                break
            touched = (contacts.locations & places) - allowed
            if touched:
                fail(f"touches {', '.join(sorted(touched))}, which the rule assumes may be occupied")
                break
    for (contact, start, goal), rules in costmap.slides.items():
        for i, rule in enumerate(rules):
            checked += 1
            for reason in _slide_problems(scene, planner, configs, limits, step, contact, start, goal, rule):
                failures.append(Failure(f"slide {contact}", start, goal, i, reason))
    return checked, failures


def _slide_problems(scene: Scene, planner: Planner, configs: dict, limits: np.ndarray, step: float,
                    contact: str, start: str, goal: str, rule) -> list[str]:
    """What is wrong with a slide rule's evidence (`planning.slides`): its
    path must run from anchor `start/contact` to `goal/contact` within the
    joint limits, cost per_radian x its length plus its primitive's fixed
    cost, meet no static obstacle with the hand, and touch (with the hand)
    or sweep (with the object's footprint) no place outside its `free` set
    but the two locations."""
    geometry = geometry_of(scene)
    spec = geometry.contacts.get(contact)
    if spec is None or start not in scene.locations or goal not in scene.locations:
        return ["not a slide of this scene"]
    if rule.path is None or len(rule.path) == 0:
        return ["no evidence path"]
    outside = _outside_limits(rule.path, limits)
    if outside is not None:
        return [outside]
    problems = []
    for end, point, anchor in (("starts", rule.path[0], f"{start}/{contact}"),
                               ("ends", rule.path[-1], f"{goal}/{contact}")):
        if anchor not in configs or not _same_config(point, configs[anchor]):
            problems.append(f"{end} at {point_text(point)}, not at anchor {anchor}")
    plugin = displacement(spec.primitive)
    fixed = geometry.primitive_costs.get(plugin.name, plugin.fixed_cost)
    expected = geometry.per_radian * path_length(rule.path) + fixed
    if not math.isclose(rule.cost, expected, rel_tol=1e-9, abs_tol=1e-9):
        problems.append(f"cost {rule.cost} but the path is {path_length(rule.path):.6f} rad x "
                        f"{geometry.per_radian} per radian + {fixed} ({plugin.name}) = {expected:.6f}")
    allowed = rule.free | {start, goal}
    places = frozenset(scene.locations + scene.else_samples)
    for a, b in zip(rule.path, rule.path[1:] or rule.path):
        contacts = planner.motion_contacts(Mode(), tuple(a), tuple(b), step)
        if contacts.static:
            problems.append("the hand collides with the robot itself or a static obstacle")
            break
        touched = (contacts.locations & places) - allowed
        if touched:
            problems.append(f"the hand touches {', '.join(sorted(touched))}, which the rule assumes may be occupied")
            break
    swept: set[str] = set()
    for obj in scene.object_names:
        swept |= swept_places(scene, obj, start, goal) or set()
    if swept - allowed:
        problems.append(f"the object sweeps {', '.join(sorted(swept - allowed))}, which the rule assumes may be "
                        "occupied")
    return problems


def _outside_limits(path, limits: np.ndarray) -> str | None:
    """Why a path is no path of this robot (waypoints of another length than
    its joints, or outside their limits), None when it is one."""
    joints = len(limits)
    for i, q in enumerate(path):
        if len(q) != joints:
            return f"waypoint {i} has {len(q)} joint values, the robot has {joints} joints"
        if np.any(np.asarray(q) < limits[:, 0] - ANCHOR_TOLERANCE) or \
                np.any(np.asarray(q) > limits[:, 1] + ANCHOR_TOLERANCE):
            return f"waypoint {i} {point_text(q)} is outside the joint limits"
    return None


def _same_config(a, b) -> bool:
    """Equal up to rounding (the path's ends are the roadmap's anchor vertices)."""
    return len(a) == len(b) and bool(np.allclose(a, b, rtol=0.0, atol=ANCHOR_TOLERANCE))
