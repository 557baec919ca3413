"""Fixtures shared by test files: the paper's scenes on small roadmaps,
with their costmaps computed once per test session."""

import dataclasses
from pathlib import Path

import pytest

from symsynth.planning.build import compute_costmaps
from symsynth.scene import load_scene

ROADMAP = 60  # vertices per mode: the paper's findings hold from here on (measured up to 150)
PLANNERS = {"arch": "pybullet", "line": "ompl-fcl"}  # one scene per built-in planner
SCENES = Path(__file__).resolve().parents[1] / "scenes"


def small(name):
    """`scenes/NAME.yaml` with roadmaps of `ROADMAP` vertices."""
    scene = load_scene(SCENES / f"{name}.yaml")
    settings = dataclasses.replace(scene.geometry.planner, roadmap_size=ROADMAP, name=PLANNERS[name])
    return dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))


def _paper(name):
    scene = small(name)
    costmaps, _ = compute_costmaps(scene, ("sg", "recursive"), PLANNERS[name], progress=False)
    return scene, costmaps


@pytest.fixture(scope="session")
def paper_arch():
    """(arch scene, {"sg": costmap, "recursive": costmap}) by the pybullet planner."""
    return _paper("arch")


@pytest.fixture(scope="session")
def paper_line():
    """(line scene, {"sg": costmap, "recursive": costmap}) by the ompl-fcl planner."""
    return _paper("line")
