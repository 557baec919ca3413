"""Fixtures shared by test files: the paper's scenes on small roadmaps,
with their costmaps computed once per test session."""

import pytest

from support.paper import PLANNERS, small
from symsynth.planning.build import compute_costmaps


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
