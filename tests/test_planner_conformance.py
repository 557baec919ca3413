"""The conformance suite (`planner_conformance.py`) once per planner
registered in the entry-point group `symsynth.planners`."""

from __future__ import annotations

from importlib.metadata import entry_points

from planner_conformance import PlannerConformance

REGISTERED = sorted(ep.name for ep in entry_points(group="symsynth.planners"))

for _name in REGISTERED:
    _cls = type(f"Test_{_name.replace('-', '_')}", (PlannerConformance,), {"planner_name": _name})
    globals()[_cls.__name__] = _cls


def test_the_built_in_planners_are_registered():
    """Losing a planner's entry point must not silently drop its tests."""
    assert {"ompl-fcl", "pybullet"} <= set(REGISTERED)
