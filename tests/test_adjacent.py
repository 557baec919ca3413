"""The adjacent-link rule shared by the planner plugins."""

from __future__ import annotations

from pathlib import Path

import pybullet_data

from symsynth import bullet
from symsynth.planning.adjacent import adjacent_pairs
from symsynth.scene.geometry import Pose, Robot
from symsynth_planners.bullet.robot import RobotBody

PANDA = Path(pybullet_data.getDataPath()) / "franka_panda" / "panda.urdf"


def test_a_link_is_adjacent_to_its_nearest_ancestor_with_geometry():
    """base -> a -> b -> c, b -> d -> e, a -> f; `a` and `d` have no geometry."""
    parent = {"a": "base", "b": "a", "c": "b", "d": "b", "e": "d", "f": "a"}
    pairs = adjacent_pairs(["base", "b", "c", "e", "f"], parent.get)
    assert pairs == [("base", "b"), ("b", "c"), ("b", "e"), ("base", "f")]
    assert adjacent_pairs(["c", "e"], parent.get) == []  # no ancestor with geometry


def test_the_pybullet_plugin_leaves_out_the_pandas_chain_and_the_fingers_on_the_hand():
    robot = Robot(urdf=PANDA, base=Pose(), home=(0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785),
                  ee_link="panda_hand", joints=tuple(f"panda_joint{i}" for i in range(1, 8)),
                  fixed=(("panda_finger_joint1", 0.04), ("panda_finger_joint2", 0.04)))
    client = bullet.client()
    try:
        body = RobotBody(client, robot)
        names = {-1: client.getBodyInfo(body.id)[0].decode()}
        names.update({j: client.getJointInfo(body.id, j)[12].decode()
                      for j in range(client.getNumJoints(body.id))})
        found = {frozenset((names[a], names[b])) for a, b in body.adjacent}
    finally:
        client.disconnect()
    chain = [f"panda_link{i}" for i in range(8)] + ["panda_hand"]  # link8 has no geometry
    expected = {frozenset(pair) for pair in zip(chain, chain[1:])}
    expected |= {frozenset(("panda_hand", finger)) for finger in ("panda_leftfinger", "panda_rightfinger")}
    assert found == expected
