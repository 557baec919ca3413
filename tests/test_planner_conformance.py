"""The conformance suite (`planner_conformance.py`) once per planner
registered in the entry-point group `symsynth.planners`."""

from __future__ import annotations

from importlib.metadata import entry_points

from support.planner_conformance import PlannerConformance

REGISTERED = sorted(ep.name for ep in entry_points(group="symsynth.planners"))

for _name in REGISTERED:
    _cls = type(f"Test_{_name.replace('-', '_')}", (PlannerConformance,), {"planner_name": _name})
    globals()[_cls.__name__] = _cls


def test_the_built_in_planners_are_registered():
    """Losing a planner's entry point must not silently drop its tests."""
    assert {"ompl-fcl", "pybullet"} <= set(REGISTERED)


def test_the_time_limit_case_of_a_planner_without_one(monkeypatch):
    """The suite's time-limit test on a plugin that does not declare
    `time_limited` (both built-in ones do): it passes because the scene's
    time limit is refused before the planner is built, and fails if it is not."""
    from support import planner_conformance

    from symsynth.planning import build
    from symsynth.planning.registry import planner_class

    untimed = type("Untimed", (planner_class("ompl-fcl"),), {"time_limited": False})
    for module in (planner_conformance, build):
        monkeypatch.setattr(module, "planner_class", lambda name: untimed)
    case = type("Untimed", (PlannerConformance,), {"planner_name": "untimed"})()
    case.test_a_time_limit_grows_the_roadmap_for_that_long()
    monkeypatch.setattr(build, "_factory", lambda scene, name, factory: untimed)  # the refusal gone
    try:
        case.test_a_time_limit_grows_the_roadmap_for_that_long()
    except BaseException as error:  # pytest.raises' "DID NOT RAISE"
        assert "DID NOT RAISE" in str(error)
    else:
        raise AssertionError("the test passed without the refusal")
