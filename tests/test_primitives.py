"""Motion primitives as plugins (entry-point group `symsynth.primitives`):
the built-ins registered through it, physical contacts and their errors,
a push's slide computed on a small geometry and re-checked independently,
and the slide carried out in the simulator."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from symsynth.errors import InputError
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.build import compute_costmap
from symsynth.planning.protocol import Mode
from symsynth.planning.registry import planner_class
from symsynth.planning.slides import MAX_JUMP, slide_path
from symsynth.primitive_registry import PrimitiveError, displacement, primitive, primitive_names
from symsynth.scene import load_scene, scene_from_data

DATA = Path(__file__).parent / "data"


def test_the_built_ins_are_registered_through_the_entry_point_group():
    assert set(primitive_names()) >= {"grab", "drop", "push", "pull"}
    assert {n: primitive(n).kind for n in ("grab", "drop", "push", "pull")} == {
        "grab": "prehensile", "drop": "prehensile", "push": "displacement", "pull": "displacement"}
    assert set(primitive_names("displacement")) >= {"push", "pull"}


def test_unknown_and_prehensile_primitives_are_refused_for_contacts():
    with pytest.raises(PrimitiveError, match="unknown primitive 'shove'; installed primitives: .*push"):
        displacement("shove")
    with pytest.raises(PrimitiveError, match="'grab' is a prehensile primitive; a contact needs a displacement"):
        displacement("grab")


def physical():
    return yaml.safe_load((DATA / "push-small.yaml").read_text())


@pytest.mark.parametrize("change, message", [
    (lambda d: d["contacts"].update(top=d["contacts"]["behind"]), "contacts.top: 'top' is already a grasp"),
    (lambda d: d["contacts"]["behind"].pop("primitive"), "contacts.behind: 'primitive' is required"),
    (lambda d: d["contacts"]["behind"].update(primitive="shove"),
     "contacts.behind.primitive: unknown primitive 'shove'"),
    (lambda d: d["contacts"]["behind"].update(primitive="drop"),
     "contacts.behind.primitive: 'drop' is a prehensile primitive"),
    (lambda d: d["costs"].update(pull=3), "costs.pull: no contact uses a primitive 'pull'"),
])
def test_physical_contact_errors_are_named(change, message):
    data = physical()
    change(data)
    with pytest.raises(InputError) as error:
        scene_from_data(data, source=DATA / "push-small.yaml")
    assert message in str(error.value)


@pytest.fixture(scope="module")
def scene_and_planner():
    scene = load_scene(DATA / "push-small.yaml")
    return scene, planner_class("ompl-fcl")(scene)


@pytest.fixture(scope="module")
def push_sg(scene_and_planner):
    """push-small's start-goal costmap, built once (about 3 s) for the two
    tests that read it."""
    return compute_costmap(scene_and_planner[0], "sg", progress=False)[0]


def anchor(planner, scene, name):
    place, _, contact = name.partition("/")
    pose = scene.geometry.places[place] @ scene.geometry.hand_frame(contact).pre_image()
    return planner.inverse_kinematics(pose, tuple(scene.geometry.robot.home))


def test_a_push_slides_the_way_the_hand_faces_away_from_the_robot(scene_and_planner):
    """The contact `behind` faces +x, away from the robot: push goes l1 -> l2
    only (not back, nor sideways to l3), and pull nowhere (it draws toward
    the robot, with the hand leading); pull-small's contact on the far
    side faces the robot: pull goes l2 -> l1 there, push nowhere."""
    scene, planner = scene_and_planner
    anchors = {a: anchor(planner, scene, a) for a in scene.anchors if a != "home"}
    push = {(r.start, r.goal) for r in displacement("push").slides(scene, planner, "behind", anchors)}
    assert push == {("l1", "l2")}
    assert displacement("pull").possible_pairs(scene, "behind") == []
    far = load_scene(DATA / "pull-small.yaml")
    assert displacement("pull").possible_pairs(far, "far") == [("l2", "l1")]
    assert displacement("push").possible_pairs(far, "far") == []


def test_the_slide_path_is_checked_again_independently(scene_and_planner):
    """The path starts and ends at the anchors, moves in small steps, has
    no static contact anywhere (re-checked configuration by configuration),
    and puts the hand at the contact pose at l1 and at l2 on its way
    (forward kinematics through inverse kinematics' own check)."""
    scene, planner = scene_and_planner
    anchors = {a: anchor(planner, scene, a) for a in ("l1/behind", "l2/behind")}
    path, touched = slide_path(scene, planner, "box", "behind", "l1", "l2", anchors)
    assert path[0] == tuple(anchors["l1/behind"]) and path[-1] == tuple(anchors["l2/behind"])
    steps = np.linalg.norm(np.diff(np.asarray(path), axis=0), axis=1)
    assert steps[:-1].max() <= MAX_JUMP
    assert not any(planner.contacts(Mode(), q).static for q in path)
    assert touched == frozenset()  # nothing stands near the way (l3 is 0.25 m aside, e1 behind)
    # a place on the way is swept: move l3 between l1 and l2, beside the line by less than the box
    data = physical()
    data["locations"]["l3"] = {"xyz": [0.59, 0.08, 0.0]}
    near = scene_from_data(data, source=DATA / "push-small.yaml")
    _, touched = slide_path(near, planner_class("ompl-fcl")(near), "box", "behind", "l1", "l2", anchors)
    assert "l3" in touched


def test_a_slide_ends_on_its_anchor_without_turning_the_arm(scene_and_planner):
    """A contact's anchors lie on one branch of the arm's solutions
    (`anchors.py`), the one the slide's small inverse kinematics steps stay
    on: the slide's last leg, from where the hand's path ends to the anchor
    at l2, turns no joint by more than MAX_JUMP.  (Each anchor seeded at
    home, the two were on different branches, and the leg turned joints 1
    and 3 by 2.7 rad against each other, the hand ending where it was.)"""
    scene, planner = scene_and_planner
    path, _ = slide_path(scene, planner, "box", "behind", "l1", "l2", anchor_configs(planner, scene))
    assert np.abs(np.subtract(path[-1], path[-2])).max() <= MAX_JUMP


def test_the_push_scene_is_solved_and_simulated_with_the_slide(push_sg, tmp_path, monkeypatch, capsys):
    """Costmap built with the push's slide rule; the strategy pushes (the
    grab costs 100); the simulator carries the slide out and measures it
    at its abstract cost."""
    from symsynth.cli import main

    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    (rule,) = push_sg.slide_rules("behind", "l1", "l2")
    length = float(np.linalg.norm(np.diff(np.asarray(rule.path), axis=0), axis=1).sum())
    assert rule.cost == pytest.approx(length * 10 + 2)  # per_radian 10, the scene's push cost 2
    assert main(["simulate", "--world", "kinematic", str(DATA / "push-small.yaml"), "--human", "none", "--json"]) == 0
    import json
    runs = json.loads(capsys.readouterr().out)["runs"]
    steps = runs[0]["trace"]
    assert runs[0]["completed"] and runs[0]["divergences"] == []
    assert [s["action"] for s in steps] == ["transit(box,behind)", "slide(box,behind,l2)"]
    assert steps[1]["source"] == "slide" and steps[1]["state"]["at"] == {"box": "l2"}
    assert steps[1]["measured_cost"] == pytest.approx(steps[1]["abstract_cost"])


SCENES = Path(__file__).resolve().parents[1] / "scenes"


def test_the_bundled_push_scene_needs_its_contact(tmp_path, monkeypatch, capsys):
    """scenes/push.yaml: the box is wider than the opening, so only the push
    moves it, after the block beside its way is carried off; unrealizable
    without the contact, and with one human move (the box taken to Else,
    where it cannot be slid, nor grasped)."""
    import json
    from symsynth.cli import main

    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    assert main(["solve", str(SCENES / "push.yaml"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["cost_bound"] is not None
    actions = [s["action"] for s in out["principal_play"]]
    assert actions[-2:] == ["transit(box,behind)", "slide(box,behind,l2)"] and "drop(b,park)" in actions
    assert main(["solve", str(SCENES / "push.yaml"), "--k", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cost_bound"] is None
    data = yaml.safe_load((SCENES / "push.yaml").read_text())
    del data["contacts"]
    data["costs"].pop("push")
    (tmp_path / "nopush.yaml").write_text(yaml.safe_dump(data))
    assert main(["solve", str(tmp_path / "nopush.yaml"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cost_bound"] is None


def test_costmap_verify_rechecks_slide_evidence(scene_and_planner, push_sg):
    """The built slide rule verifies; a forged cost, a path that does not end
    at the goal's anchor and a `free` set that leaves out a swept place are
    each caught."""
    import dataclasses
    from symsynth.planning.verify import verify_costmap
    from symsynth.scene.costmap import Costmap

    scene, planner = scene_and_planner
    costmap = push_sg
    checked, failures = verify_costmap(costmap, scene, planner, 0.01, progress=False)
    assert failures == [] and checked == sum(1 for _ in costmap.all_rules())
    key = ("behind", "l1", "l2")
    (rule,) = costmap.slides[key]
    for forged, reason in [(dataclasses.replace(rule, cost=rule.cost - 1), "cost"),
                           (dataclasses.replace(rule, path=rule.path[:-1]), "ends at"),
                           (dataclasses.replace(rule, free=frozenset()), None)]:
        _, failures = verify_costmap(Costmap({}, None, {key: (forged,)}), scene, planner, 0.01, progress=False)
        if reason is None:  # push-small sweeps nothing: an empty free set is still right
            assert failures == []
        else:
            assert failures and {f.mode for f in failures} == {"slide behind"}
            assert any(reason in f.reason for f in failures)
    # a place beside the way: the rule must name it
    data = physical()
    data["locations"]["l3"] = {"xyz": [0.59, 0.08, 0.0]}
    near = scene_from_data(data, source=DATA / "push-small.yaml")
    near_planner = planner_class("ompl-fcl")(near)
    _, failures = verify_costmap(Costmap({}, None, {key: (rule,)}), near, near_planner, 0.01, progress=False)
    assert any("sweeps l3" in f.reason for f in failures)


class Says:
    """A prehensile primitive that says what it is told (holds the objects
    in `held`, reaches the places in `reached`) and counts the questions."""

    kind = "prehensile"

    def __init__(self, name, held, reached):
        self.name, self.held, self.reached, self.asked = name, held, reached, []

    def holds(self, geometry, obj, grasp):
        return obj in self.held

    def reaches(self, scene, planner, place, grasp, anchor):
        self.asked.append(place)
        return place in self.reached

    def execute(self, world, approaches, move):
        raise AssertionError("not carried out here")


def test_the_costmap_asks_grab_and_drop_where_and_on_what_they_act(monkeypatch):
    """`holds` and `reaches` are protocol (planning/primitive_protocol.py),
    asked of both primitives of the game's prehensile actions, not looked
    for on the one named grab: a holding mode needs both to hold its object,
    a grasp anchor both to reach it."""
    from symsynth.planning import build

    scene = load_scene(DATA / "push-small.yaml")
    configs = {f"{x}/top": (0.0,) * 7 for x in scene.locations + scene.else_samples}
    grab, drop = Says("grab", {"box"}, {"l1", "l2"}), Says("drop", set(), {"l2"})
    monkeypatch.setattr(build, "prehensile_primitives", lambda: (grab, drop))
    assert build.holds(scene, Mode()) and not build.holds(scene, Mode("box", "top"))
    drop.held = {"box"}
    assert build.holds(scene, Mode("box", "top"))
    assert build.graspable(scene, None, configs) == {"l2/top"}
    assert sorted(grab.asked) == sorted(scene.locations + scene.else_samples)
    assert sorted(drop.asked) == ["l1", "l2"]  # where grab said yes


def test_a_prehensile_plugin_without_the_protocol_is_refused_by_name(tmp_path, monkeypatch):
    (tmp_path / "halfhand.py").write_text("class Hand:\n    name = 'halfhand'\n    kind = 'prehensile'\n"
                                          "    def execute(self, world, approaches, move):\n        pass\n")
    info = tmp_path / "halfhand-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: halfhand\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[symsynth.primitives]\nhalfhand = halfhand:Hand\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(PrimitiveError, match=r"'halfhand' \(halfhand:Hand\) is a prehensile primitive without "
                                             r"holds, reaches"):
        primitive("halfhand")
