"""The conformance suite (`symsynth.testing.planner`) once per planner
registered in the entry-point group `symsynth.planners`, by the line a
plugin's own repository uses (`symsynth.testing.conformance`)."""

from __future__ import annotations

from symsynth.planning.registry import planner_names
from symsynth.testing import conformance

TestPlanners = conformance("planner", *planner_names())


def test_the_built_in_planners_are_registered():
    """Losing a planner's entry point must not silently drop its tests."""
    assert {"ompl-fcl", "pybullet"} <= set(planner_names())


def test_the_time_limit_case_of_a_planner_without_one(monkeypatch):
    """The suite's time-limit test on a plugin that does not declare
    `time_limited` (both built-in ones do): it passes because the scene's
    time limit is refused before the planner is built, and fails if it is not."""
    from symsynth.planning import build
    from symsynth.planning.registry import planner_class
    from symsynth.testing import planner as planner_suite

    untimed = type("Untimed", (planner_class("ompl-fcl"),), {"time_limited": False})
    for module in (planner_suite, build):
        monkeypatch.setattr(module, "planner_class", lambda name: untimed)
    case = planner_suite.PlannerConformance()
    case.name = "untimed"
    case.test_a_time_limit_grows_the_roadmap_for_that_long()
    monkeypatch.setattr(build, "_factory", lambda scene, name, factory: untimed)  # the refusal gone
    try:
        case.test_a_time_limit_grows_the_roadmap_for_that_long()
    except BaseException as error:  # pytest.raises' "DID NOT RAISE"
        assert "DID NOT RAISE" in str(error)
    else:
        raise AssertionError("the test passed without the refusal")
