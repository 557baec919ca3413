"""Re-check a costmap's evidence paths (`symsynth costmap verify`).

A rule `(F, c, path)` of a motion claims: with every place outside `F`
occupied (except the places the motion's `never` set says cannot be), the
robot can follow `path`, and it costs `c`.  Each path is checked again, at
a finer resolution than the one it was built with, against the static
obstacles and exactly those location obstacles; its cost is recomputed.  A
failure is a bug in a planner or in the costmap algorithms.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from symsynth.planning.anchors import anchor_configs, motions
from symsynth.planning.protocol import Mode, Planner
from symsynth.scene.costmap import Costmap
from symsynth.scene.model import Scene


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


def verify_costmap(costmap: Costmap, scene: Scene, planner: Planner, resolution: float,
                   progress: bool = True) -> tuple[int, list[Failure]]:
    """(rules checked, failures).  `resolution` is the step along each path
    (the command passes a quarter of the scene's planner resolution)."""
    queries = {}
    for mode_name in scene.modes:
        for query in motions(scene, Mode.parse(mode_name)):
            queries[(mode_name, query.start, query.goal)] = query
    places = frozenset(scene.locations + scene.else_samples)
    per_radian = scene.geometry.per_radian
    failures: list[Failure] = []
    configs = anchor_configs(planner, scene)
    at_start: dict[tuple[str, str], frozenset[str]] = {}
    checked = 0
    items = [(key, i, rule) for key, rules in costmap.motions.items() for i, rule in enumerate(rules)]
    for (mode_name, start, goal), i, rule in tqdm(items, desc="verify", unit="rule", disable=not progress,
                                                  leave=False):
        fail: Callable[[str], None] = lambda reason: failures.append(  # noqa: E731
            Failure(mode_name, start, goal, i, reason))
        checked += 1
        query = queries.get((mode_name, start, goal))
        if query is None:
            fail("not a motion of this scene")
            continue
        if rule.path is None or len(rule.path) == 0:
            fail("no evidence path")
            continue
        if not math.isclose(rule.cost, per_radian * path_length(rule.path), rel_tol=1e-9, abs_tol=1e-9):
            fail(f"cost {rule.cost} but the path is {path_length(rule.path):.6f} rad "
                 f"x {per_radian} per radian = {per_radian * path_length(rule.path):.6f}")
        mode = Mode.parse(mode_name)
        # what the start anchor's configuration touches cannot be occupied
        # (build.physical_queries); the anchor's, not the path's first point,
        # which the costmap file could put anywhere
        if (mode_name, start) not in at_start:
            at_start[mode_name, start] = planner.contacts(mode, configs[start]).locations
        allowed = rule.free | query.never | at_start[mode_name, start]
        for a, b in zip(rule.path, rule.path[1:] or rule.path):
            contacts = planner.motion_contacts(mode, tuple(a), tuple(b), resolution)
            if contacts.static:
                fail("collides with the robot itself or a static obstacle")
                break
            touched = (contacts.locations & places) - allowed
            if touched:
                fail(f"touches {', '.join(sorted(touched))}, which the rule assumes may be occupied")
                break
    return checked, failures
