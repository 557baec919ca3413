"""Places resting on places (`planning/support.py`), and the costmap's
transfers from under them (docs/costmaps.md, *Objects resting on objects*).

The expected relation is read off the scene's numbers by hand; the
consequence in the game is checked on the paper's arch (the session's
60-vertex pybullet costmaps, `conftest.paper_arch`): holding an object
lifted from a support while a block stands on `top`, the robot has no
transfer, only the drop back.
"""

from __future__ import annotations

import dataclasses

import yaml

from symsynth.game.abstraction import State, legal_robot_moves
from symsynth.planning.support import resting
from symsynth.scene import scene_from_data
from symsynth.scene.model import HAND

STACK = """
name: stack
robot: {}
objects:
  w: {box: [0.04, 0.04, 0.06], at: a}
  b: {box: [0.04, 0.14, 0.06], at: c}
locations:
  a: {xyz: [0.5, -0.05, 0.0]}
  up: {xyz: [0.5, 0.0, 0.06]}
  high: {xyz: [0.5, 0.0, 0.08]}
  beside: {xyz: [0.5, 0.2, 0.06]}
  c: {xyz: [0.5, 0.12, 0.0]}
grasps:
  top: {xyz: [0.0, 0.0, 0.1434], rpy: [3.14159265, 0.0, 0.0], approach: 0.07}
task: F(at(w, up))
"""


def test_a_place_rests_on_another_where_an_object_there_would_stand_on_another_one_here():
    """Read off the numbers (w 4 x 4 x 6 cm, b 4 x 14 x 6 cm, both lying
    along y): `up` rests on `a` (b at `up`, y -0.07..0.07, on w at `a`,
    -0.07..-0.03); not on `c` (w at c, 0.10..0.14, and b at `up` miss each
    other, as do b at c, 0.05..0.19, and w at `up`, -0.02..0.02: only b
    itself would overlap at both, and it stands at one place); `beside`
    rests on `c` (w at `beside`, 0.18..0.22, on b at c); `high` is 2 cm
    above every top; nothing rests on `up` or `beside`, 6 cm up."""
    scene = scene_from_data(yaml.safe_load(STACK))
    assert resting(scene) == {"a": frozenset({"up"}), "c": frozenset({"beside"})}


def test_holding_a_support_lifted_from_under_a_block_on_top_leaves_only_the_drop_back(paper_arch):
    """The arch's costmaps (both methods): every transfer rule from a
    support's anchor requires `top` free; so with w2 on `top` and the lintel
    just grabbed from `support2` (the hand hovered over it when the human
    put w2 there, semantics §4 lets it grab), no transfer is available and
    the only move is to put it back; with `top` empty the transfers are."""
    scene, costmaps = paper_arch
    for method, costmap in costmaps.items():
        starts = [(key, rules) for key, rules in costmap.motions.items()
                  if key[0] != "empty" and key[1].split("/")[0] in ("support1", "support2")]
        assert starts and all("top" in rule.free for _, rules in starts for rule in rules), method
        game = dataclasses.replace(scene, costmap=costmap)
        at = dict(zip(scene.object_names, ("support1", "top", HAND)))  # w1, w2, b
        lifted = State(tuple(at[o] for o in scene.object_names), "top", "support2")
        assert [m.action for m in legal_robot_moves(game, lifted)] == ["drop(b,support2)"], method
        clear = dataclasses.replace(lifted, at=tuple("table1" if a == "top" else a for a in lifted.at))
        assert any(m.kind == "transfer" for m in legal_robot_moves(game, clear)), method
