"""The line task with 1-4 obstacles between the locations (the paper's
Fig. 4): `scenes/line-obstacles-N.yaml`, whose N = 0 case is
`scenes/line.yaml` (its findings are in `test_paper_scenarios.py`).

Expectations come from the files' text read as plain YAML (not through the
scene loader), from the straight motions between neighbouring arms in the
scene without posts, and from both game solvers.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import math
from pathlib import Path

import pytest
import yaml

from symsynth.game.solution import task_formula
from symsynth.solvers import SOLVERS
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.build import compute_costmaps
from symsynth.planning.protocol import Mode
from symsynth.planning.registry import planner_class
from symsynth.scene import load_scene
from symsynth.scene.load import scene_from_data

SCENES = Path(__file__).resolve().parents[1] / "scenes"
COUNTS = (1, 2, 3, 4)
ROADMAP = 60  # vertices per mode, as in test_paper_scenarios.py
CLEARANCE = 0.03  # metres between a post and any object standing at a place


def path(n: int) -> Path:
    return SCENES / ("line.yaml" if n == 0 else f"line-obstacles-{n}.yaml")


@functools.cache
def raw(n: int) -> dict:
    return yaml.safe_load(path(n).read_text())


def posts(n: int) -> dict[str, dict]:
    """The obstacles of variant n that line.yaml does not have."""
    return {name: spec for name, spec in raw(n)["obstacles"].items() if name not in raw(0)["obstacles"]}


@functools.cache
def scene(n: int):
    return load_scene(path(n))


def box_gap(centre_a, half_a, centre_b, half_b) -> float:
    """Distance between two axis-aligned rectangles (0 if they overlap)."""
    apart = [max(0.0, abs(a - b) - (ha + hb)) for a, b, ha, hb in zip(centre_a, centre_b, half_a, half_b)]
    return math.hypot(*apart)


@pytest.mark.parametrize("n", COUNTS)
def test_variant_is_line_plus_n_posts(n):
    """Same robot, objects, locations, grasps, costs, task and planner as
    line.yaml; n more obstacles, the table kept."""
    variant, line = raw(n), raw(0)
    assert {k: v for k, v in variant.items() if k not in ("name", "obstacles")} == \
        {k: v for k, v in line.items() if k not in ("name", "obstacles")}
    assert variant["name"] == f"line-obstacles-{n}"
    assert set(line["obstacles"]) < set(variant["obstacles"])
    assert all(variant["obstacles"][name] == spec for name, spec in line["obstacles"].items())
    assert len(posts(n)) == n
    if n > 1:  # each variant adds one post to the previous one
        assert posts(n - 1).items() < posts(n).items()
    loaded = scene(n)
    assert {b.name for b in loaded.geometry.obstacles} == set(variant["obstacles"])
    assert loaded.geometry.places == scene(0).geometry.places  # Else samples drawn the same


@pytest.mark.parametrize("n", COUNTS)
def test_posts_stand_between_the_locations_clear_of_every_place(n):
    """Each post's footprint lies inside the cross's bounding box, at least
    CLEARANCE from the footprint of any object standing at any place (the
    locations and the Else samples), and rises above the objects."""
    xy = [spec["xyz"][:2] for spec in raw(n)["locations"].values()]
    low = [min(p[i] for p in xy) for i in range(2)]
    high = [max(p[i] for p in xy) for i in range(2)]
    objects = raw(n)["objects"].values()
    object_half = [max(o["box"][i] for o in objects) / 2 for i in range(2)]
    tallest = max(o["box"][2] for o in objects)
    places = [pose.xyz[:2] for pose in scene(n).geometry.places.values()]
    assert len(places) == len(xy) + raw(n)["else"]["samples"]
    for name, spec in posts(n).items():
        centre, size = spec["xyz"][:2], spec["box"]
        half = [size[0] / 2, size[1] / 2]
        assert all(low[i] <= centre[i] - half[i] and centre[i] + half[i] <= high[i] for i in range(2)), name
        gaps = [box_gap(centre, half, place, object_half) for place in places]
        assert min(gaps) >= CLEARANCE, (name, min(gaps))
        assert spec["xyz"][2] == 0.0 and size[2] > tallest, name


def anchors(n: int, planner: str):
    built = planner_class(planner)(scene(n))
    return built, anchor_configs(built, scene(n))  # raises, naming them, if any anchor cannot be used


@functools.cache
def fcl_anchors(n: int):
    return anchors(n, "ompl-fcl")  # (pybullet clients are not cached: they must close before exit)


@pytest.mark.parametrize("planner", ["ompl-fcl", "pybullet"])
@pytest.mark.parametrize("n", COUNTS)
def test_every_anchor_is_reachable(n, planner):
    _, found = fcl_anchors(n) if planner == "ompl-fcl" else anchors(n, planner)
    line = scene(0)
    assert set(found) == {"home"} | {f"{x}/{g}" for x in line.locations + line.else_samples for g in line.grasps}


@pytest.mark.parametrize("n", COUNTS)
def test_each_post_blocks_the_straight_move_between_its_arms(n):
    """For each post, the two arm locations nearest to it: the straight
    joint-space motion between their anchors is free in line.yaml and hits
    the post in line.yaml plus that post alone: the hand must go around or
    over it."""
    step = scene(0).geometry.planner.check_step / 4
    empty, free = fcl_anchors(0)
    arms = {name: spec["xyz"][:2] for name, spec in raw(0)["locations"].items() if name != "center"}
    for name, spec in posts(n).items():
        a, b = sorted(arms, key=lambda arm: math.dist(arms[arm], spec["xyz"][:2]))[:2]
        start, goal = free[f"{a}/top"], free[f"{b}/top"]
        assert not empty.motion_contacts(Mode(), start, goal, step).static, (a, b)
        data = copy.deepcopy(raw(0))
        data["obstacles"][name] = spec
        alone = planner_class("ompl-fcl")(scene_from_data(data, source=path(0)))
        assert alone.motion_contacts(Mode(), start, goal, step).static, (name, a, b)


def small(n: int):
    settings = dataclasses.replace(scene(n).geometry.planner, roadmap_size=ROADMAP)
    return dataclasses.replace(scene(n), geometry=dataclasses.replace(scene(n).geometry, planner=settings))


def value(loaded, costmap) -> float | None:
    solved = dataclasses.replace(loaded, costmap=costmap)
    found = {name: solver(solved, task_formula(solved, None), k=solved.k).cost_bound
             for name, solver in SOLVERS.items()}
    assert len(set(found.values())) == 1, found  # the solvers agree
    return found["symbolic"]


@pytest.mark.parametrize("n", COUNTS)
def test_both_methods_win_and_recursive_is_no_dearer(n):
    loaded = small(n)
    costmaps, _ = compute_costmaps(loaded, ("sg", "recursive"), "ompl-fcl", progress=False)
    sg, rec = value(loaded, costmaps["sg"]), value(loaded, costmaps["recursive"])
    assert sg is not None and rec is not None
    assert rec <= sg, (n, rec, sg)


def test_the_benchmark_derives_its_time_verdict_from_the_numbers():
    """bench/line_obstacles.py calls the gap between the methods' times noise
    only when no run's graph searches (the only work that differs) could explain it."""
    from bench.line_obstacles import time_verdict
    noisy = time_verdict({"sg": [3.0, 4.0], "recursive": [3.5, 4.1]}, [0.01, 0.03])
    assert "differ by 0.10-0.50 s, more than the searches took in any run" in noisy and "noise" in noisy
    close = time_verdict({"sg": [3.0, 4.0], "recursive": [3.02, 4.01]}, [0.01, 0.03])
    assert "differ by 0.01-0.02 s, no more than the searches took" in close and "noise" not in close
    assert "searches, which took 0.01-0.03 s per run" in close
    assert "faster than recursive on average for 2 of 2" in close
