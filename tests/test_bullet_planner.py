"""The pybullet planner's own behaviour beyond the conformance suite."""

from __future__ import annotations

import numpy as np

from symsynth.testing.planner import HOME, INTO_TABLE, CHECK_STEP, scene
from symsynth.planning.protocol import Contacts, Mode
from symsynth.planning.segment import segment
from symsynth_planners.bullet import BulletPlanner


def counted(planner: BulletPlanner) -> list:
    """The configurations the planner's world is set to, from now on."""
    seen = []
    set_config = planner.world.set_config

    def record(config) -> None:
        seen.append(tuple(config))
        set_config(config)

    planner.world.set_config = record
    return seen


def test_motion_contacts_stop_at_the_first_static_configuration():
    """Into the table and back: a segment of many steps whose first (or
    last) configuration is in the table is checked up to it, no further."""
    planner = BulletPlanner(scene("table"))
    steps = segment(INTO_TABLE, HOME, CHECK_STEP)
    assert len(steps) > 10
    assert planner.contacts(Mode(), INTO_TABLE).static and planner.contacts(Mode(), HOME) == Contacts()
    seen = counted(planner)
    assert planner.motion_contacts(Mode(), INTO_TABLE, HOME, CHECK_STEP) == Contacts(static=True)
    assert seen == [tuple(steps[0])]
    del seen[:]
    assert planner.motion_contacts(Mode(), HOME, INTO_TABLE, CHECK_STEP).static
    checked = list(seen)
    assert 1 < len(checked) < len(steps)  # some way in, the hand meets the table
    assert np.allclose(checked, segment(HOME, INTO_TABLE, CHECK_STEP)[:len(checked)])
    assert planner.contacts(Mode(), checked[-1]).static and not planner.contacts(Mode(), checked[-2]).static
