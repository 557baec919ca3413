"""The straight-segment stepping rule shared by the planners and the simulator."""

from __future__ import annotations

import numpy as np
import pytest

from symsynth.execution.motion import steps
from symsynth.planning.protocol import PlannerError
from symsynth.planning.segment import segment


def test_segment_steps_at_most_the_check_step_ends_included():
    start, goal = np.zeros(3), np.array([0.3, 0.4, 0.0])  # 0.5 long
    points = segment(start, goal, 0.1)
    assert len(points) == 6 and np.allclose(points[0], start) and np.allclose(points[-1], goal)
    assert np.allclose(np.linalg.norm(np.diff(points, axis=0), axis=1), 0.1)
    # 0.5 / 0.12 = 4.2: five steps of 0.1, as four of 0.125 would be too long
    assert len(segment(start, goal, 0.12)) == 6 and len(segment(start, start, 0.1)) == 2


def test_a_check_step_that_is_not_positive_is_a_planner_error():
    for step in (0.0, -0.1, float("nan")):
        with pytest.raises(PlannerError, match="check step must be positive"):
            segment((0.0, 0.0), (1.0, 0.0), step)


def test_a_path_steps_through_every_waypoint_each_leg_by_the_rule():
    path = [(0.0, 0.0), (0.75, 1.0), (0.75, 1.0), (0.75, 0.5)]  # legs 1.25, 0, 0.5 long
    found = list(steps(path, 0.25))
    assert len(found) == 1 + 5 + 1 + 2
    assert [found[i] for i in (0, 5, 6, 8)] == path
    assert np.allclose(found[1], (0.15, 0.2)) and np.allclose(found[7], (0.75, 0.75))
    assert list(steps([], 0.1)) == [] and list(steps([(1.0, 2.0)], 0.1)) == [(1.0, 2.0)]
