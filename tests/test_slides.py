"""Displacement primitives in the game (docs/game-semantics.md §4b):
contacts, the `slide(o,a,l')` action and its conditional slide rules.

- Hand-solved scenes, their values worked out in the docstrings, for every
  solver: a box the robot cannot grasp where it stands, pushed onto its
  target; a slide rule that asks for a location to be cleared first.
- On 200 generated scenes with contacts and slide rules, k = 0..3, the
  explicit and symbolic solvers agree (the BDD relation is built from the
  costmap independently of `game.abstraction`'s moves), the forward solver
  agrees on one k per scene, and every strategy pays no more than E_p
  against every human behaviour.
- The symbolic relations, read back state by state, are the abstraction's
  moves and costs, slides included (tests/test_game_symbolic.py).
- Scenes without contacts keep their v1 value: the rest of the suite's
  generated scenes are unchanged (gamegen draws contacts from a second
  generator), and so is every test of them.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from symsynth.testing.gamegen import random_scene
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.game.abstraction import State, human_moves, initial_state, robot_moves
from symsynth.solvers.bound import LowerBound
from symsynth.game.graph import GameGraph
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers import SOLVERS
from symsynth.solvers.symbolic import solve_symbolic
from symsynth.logic import parse_ltlf
from symsynth.game.strategy import certify, read_strategy
from symsynth.scene import load_scene, scene_from_data
from support.games import bound_holds_everywhere, worst_case_of


@pytest.fixture(params=sorted(SOLVERS))
def solve(request):
    return SOLVERS[request.param]


def anchors(places, preimages):
    return ["home"] + [f"{x}/{a}" for x in places for a in preimages]


def box_scene(k, *, contacts=True):
    """A box at l1 that the top grasp cannot reach there (no motion to
    l1/top), a contact `push` behind it, target l2; one Else sample e1,
    from which the box can be grasped.

    - every anchor -> l1/push and -> l3/push: 6; every anchor -> e1/top: 20;
      holding it (box/top) e1/top -> l2/top: 10; grab and drop 5;
    - slides: push l1 -> l2 costs 4, push l3 -> l2 costs 5.

    k = 0: transit(box,push) 6 (from home: the only action), slide 4:
    E_p = 10.
    k = 1: the human waits for the robot to stand behind the box, then
    takes the box to Else (ee falls back to Else; a box at Else cannot be
    slid: e1/push is reached by no motion).  The robot grasps it from
    there: transit(box,top) to e1/top, max over the 9 anchors it may stand
    at = 20, grab 5, transfer e1/top -> l2/top 10, drop 5: 6 + 40 = 46.
    Moving it to l3 instead costs the robot only 6 + 6 + 5 = 17 in all;
    moving it at once, 40.  E_p = 46.
    k = 2: the second move shifts the box within Else once the robot stands
    at e1/top (a real move: ee falls back to Else), and the robot transits
    there again: 6 + 20 + 20 + 5 + 10 + 5 = 66.
    Without the contact (and its motions and slide): the box cannot be
    grasped at l1, so with k = 0 the task is unrealizable."""
    places = ["l1", "l2", "l3", "e1"]
    preimages = ["top", "push"] if contacts else ["top"]
    every = anchors(places, preimages)
    motions = [{"mode": "empty", "from": s, "to": "e1/top", "rules": [{"cost": 20}]} for s in every if s != "e1/top"]
    motions.append({"mode": "box/top", "from": "e1/top", "to": "l2/top", "rules": [{"cost": 10}]})
    data = {"name": "box", "objects": {"box": {"at": "l1"}}, "locations": ["l1", "l2", "l3"],
            "else_samples": ["e1"], "grasps": ["top"], "human": {"k": k}, "task": "F(at(box, l2))",
            "costmap": {"format": "symsynth.costmap/1", "motions": motions}}
    if contacts:
        motions += [{"mode": "empty", "from": s, "to": t, "rules": [{"cost": 6}]}
                    for t in ("l1/push", "l3/push") for s in every if s != t]
        data["contacts"] = ["push"]
        data["costmap"]["slides"] = [
            {"contact": "push", "from": "l1", "to": "l2", "rules": [{"free": [], "cost": 4}]},
            {"contact": "push", "from": "l3", "to": "l2", "rules": [{"cost": 5}]}]
    return scene_from_data(data)


@pytest.mark.parametrize("k, value", [(0, 10), (1, 46), (2, 66)])
def test_a_box_too_wide_to_grasp_is_pushed_onto_its_target(solve, k, value):
    solution = solve(box_scene(k))
    assert solution.cost_bound == value
    if k == 0:
        assert [s.action for s in solution.principal_play] == ["transit(box,push)", "slide(box,push,l2)"]
        assert solution.principal_play[-1].state == State(("l2",), None, ("box", "push"))
    assert worst_case_of(box_scene(k), solution, parse_ltlf("F(at(box, l2))")) == solution.units


def test_without_the_contact_the_box_task_is_unrealizable(solve):
    assert solve(box_scene(0, contacts=False)).cost_bound is None


def cleared_scene():
    """The slide push l1 -> l2 costs 4 if l3 is free, 30 otherwise; a can
    stands at l3 and can be moved to l4.

    - every anchor -> l1/push: 6; every anchor -> l3/top: 3;
      can/top l3/top -> l4/top: 2; grab and drop 5.
    - Push at once: 6 + 30 = 36.
    - Clear l3 first: transit(can,top) 3, grab 5, transfer(l4) 2,
      drop 5, transit(box,push) from l4/top 6, slide 4 (l3 now free): 25.
    E_p = 25 (k = 0)."""
    places = ["l1", "l2", "l3", "l4"]
    every = anchors(places, ["top", "push"])
    motions = ([{"mode": "empty", "from": s, "to": "l1/push", "rules": [{"cost": 6}]} for s in every if s != "l1/push"]
               + [{"mode": "empty", "from": s, "to": "l3/top", "rules": [{"cost": 3}]} for s in every if s != "l3/top"]
               + [{"mode": "can/top", "from": "l3/top", "to": "l4/top", "rules": [{"cost": 2}]}])
    return scene_from_data({
        "name": "cleared", "objects": {"box": {"at": "l1"}, "can": {"at": "l3"}}, "locations": places,
        "grasps": ["top"], "contacts": ["push"], "task": "F(at(box, l2))",
        "costmap": {"format": "symsynth.costmap/1", "motions": motions, "slides": [
            {"contact": "push", "from": "l1", "to": "l2",
             "rules": [{"free": ["l3"], "cost": 4}, {"free": [], "cost": 30}]}]}})


def test_a_conditional_slide_rule_makes_the_robot_clear_a_location(solve):
    solution = solve(cleared_scene())
    assert solution.cost_bound == 25
    assert [s.action for s in solution.principal_play] == [
        "transit(can,top)", "grab(can)", "transfer(l4)", "drop(can,l4)", "transit(box,push)", "slide(box,push,l2)"]
    assert [s.cost for s in solution.principal_play] == [3, 5, 2, 5, 6, 4]


def test_a_slide_needs_its_target_free_and_the_object_at_a_location():
    """`slide` only from a location of interest, to a free one; the hand
    stays at the contact, relative to the moved object."""
    scene = cleared_scene()
    at_box = State(("l1", "l3"), None, ("box", "push"))
    assert ("slide(box,push,l2)", State(("l2", "l3"), None, ("box", "push")), 30.0) in robot_moves(scene, at_box)
    assert not [a for a, _, _ in robot_moves(scene, State(("l1", "l2"), None, ("box", "push"))) if "slide" in a]
    assert not [a for a, _, _ in robot_moves(scene, State(("Else", "l3"), None, ("box", "push"))) if "slide" in a]
    assert "grab(box)" not in [a for a, _, _ in robot_moves(scene, at_box)]  # a contact never closes the hand
    # a human move of the object drops the aim at its contact
    assert State(("l4", "l3"), None, "Else") in [w for _, w in human_moves(scene, at_box)]


# -- generated scenes ------------------------------------------------------------------

@pytest.mark.parametrize("chunk", range(4))
def test_solvers_agree_on_scenes_with_contacts(chunk):
    """50 scenes per chunk, 200 in all: explicit and symbolic at k = 0..3,
    forward at one k; the explicit strategy checked against every human
    behaviour where the value is finite."""
    kinds = {"finite": 0, "infinite": 0, "slides": 0}
    for seed in range(2000 + 50 * chunk, 2000 + 50 * (chunk + 1)):
        scene = random_scene(seed, contacts=True)
        for k in range(4):
            explicit = solve_explicit(scene, k=k)
            assert solve_symbolic(scene, k=k).units == explicit.units, (seed, k)
            if k == seed % 4:
                assert SOLVERS["forward"](scene, k=k).units == explicit.units, (seed, k)
            if explicit.units is None:
                kinds["infinite"] += 1
                continue
            kinds["finite"] += 1
            kinds["slides"] += any(s.action.startswith("slide(") for s in explicit.principal_play)
            if k == seed % 4:
                assert worst_case_of(scene, explicit, parse_ltlf(scene.task)) == explicit.units
    assert kinds["finite"] >= 20 and kinds["infinite"] >= 20 and kinds["slides"] >= 2, kinds


# -- scene and costmap errors -------------------------------------------------------------

def base(**extra):
    return {"name": "t", "objects": {"b": {"at": "l1"}}, "locations": ["l1", "l2"], "grasps": ["top"]} | extra


@pytest.mark.parametrize("data, message", [
    (base(contacts=["top"]), "contacts.0: 'top' is already a grasp"),
    (base(contacts=["push", "push"]), "contacts: ['push', 'push'] has non-unique elements"),
    (base(contacts=["push"], costmap={"format": "symsynth.costmap/1", "motions": [], "slides": [
        {"contact": "pull", "from": "l1", "to": "l2", "rules": [{"cost": 1}]}]}),
     "slide pull l1 -> l2: unknown contact 'pull'; expected one of push"),
    (base(contacts=["push"], costmap={"format": "symsynth.costmap/1", "motions": [], "slides": [
        {"contact": "push", "from": "l1", "to": "Else", "rules": [{"cost": 1}]}]}),
     "slide push l1 -> Else: 'Else' is not a location of interest"),
    (base(contacts=["push"], costmap={"format": "symsynth.costmap/1", "motions": [], "slides": [
        {"contact": "push", "from": "l1", "to": "l2", "rules": [{"free": ["l9"], "cost": 1}]}]}),
     "slide push l1 -> l2: rule names unknown locations l9"),
    (base(costmap={"format": "symsynth.costmap/1", "motions": [], "slides": [
        {"contact": "push", "from": "l1", "to": "l2", "rules": [{"cost": -1}]}]}),
     "slides[0].rules[0].cost: must be >= 0"),
    (base(costmap={"format": "symsynth.costmap/1", "motions": [], "slides": [{"contact": "push"}]}),
     "slides[0]: missing from, to, rules"),
])
def test_contact_errors_are_named(data, message):
    with pytest.raises(InputError) as error:
        scene_from_data(data)
    assert message in str(error.value)


def test_a_costmap_with_slides_is_written_as_it_is_read(tmp_path):
    from symsynth.scene.costmap import load_costmap, write_costmap

    costmap = box_scene(0).costmap
    write_costmap(costmap, tmp_path / "c.json")
    again = load_costmap(tmp_path / "c.json")
    assert again == costmap and again.slide_rules("push", "l3", "l2")[0].cost == 5


# -- the bundled scene, the command line and strategy files -----------------------------------

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def test_the_bundled_push_scene_is_the_hand_solved_one(capsys):
    """scenes/push-abstract.yaml is `box_scene(1)` (its comments solve it in
    the same words), solved through the command line."""
    scene = load_scene(SCENES / "push-abstract.yaml")
    assert scene.costmap == box_scene(1).costmap and scene.contacts == ("push",) and scene.k == 1
    for k, value in ((1, 46), (0, 10)):
        assert main(["solve", str(SCENES / "push-abstract.yaml"), "--k", str(k), "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["cost_bound"] == value


def test_a_strategy_file_with_slides_is_certified_and_a_forged_one_refused(tmp_path, capsys):
    path = tmp_path / "strategy.json"
    scene = load_scene(SCENES / "push-abstract.yaml")
    assert main(["solve", str(SCENES / "push-abstract.yaml"), "--k", "0", "-o", str(path)]) == 0
    certify(scene, read_strategy(path))  # raises if anything is off
    data = json.loads(path.read_text())
    data["positions"][1]["action"] = "slide(box,push,l3)"  # no slide rule from l1 to l3
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match=r"slide\(box,push,l3\)"):
        certify(scene, read_strategy(path))
    capsys.readouterr()


def test_a_stuck_robot_at_a_contact_is_told_why(capsys):
    """k = 1 and no grasp from Else either: the human takes the box to Else,
    where it cannot be slid; the counter play ends with the reasons."""
    data = yaml.safe_load((SCENES / "push-abstract.yaml").read_text())
    data["costmap"] = box_scene(1).costmap.to_json()
    data["costmap"]["motions"] = [m for m in data["costmap"]["motions"] if m["to"] != "e1/top"]
    scene = scene_from_data(data)
    from symsynth.game.stuck import stuck_reasons
    reasons = stuck_reasons(scene, State(("Else",), None, ("box", "push")))
    assert "slide(box,push,...): box is at Else, and only an object at a location of interest is slid" in reasons
    reasons = stuck_reasons(scene, State(("l3",), None, ("box", "push")))
    assert "slide(box,push,...): the costmap has no slide rule for push from l3 to l1" in reasons  # not l2: it has one
    reasons = stuck_reasons(scene, State(("l2",), None, ("box", "push")))
    assert "slide(box,push,...): the costmap has no slide rule for push from l2 to l1, l3" in reasons


# -- the forward solver's lower bound with slides ---------------------------------------------

def test_the_lower_bound_with_slides_is_admissible_everywhere():
    """At every reachable position of generated scenes with contacts (any
    turn, any h), the bound is at most the explicit solver's value; it is
    on (and not zero everywhere) for the pattern-like tasks."""
    enabled = informative = 0
    for seed in range(3000, 3060):
        scene = random_scene(seed, contacts=True)
        bound, checked = bound_holds_everywhere(scene, 2)
        enabled += bound.enabled
        informative += bound.enabled and bound(initial_state(scene), 0, False) > 0
    assert enabled >= 10 and informative >= 5, (enabled, informative)


def test_the_lower_bound_counts_the_cheaper_of_carrying_and_sliding():
    """box_scene(0): the box cannot be grasped at l1 (no motion to l1/top),
    so the only way to l2 is the slide (4) after a transit to its contact
    (6 from anywhere): the bound at the start is the value, 10."""
    scene = box_scene(0)
    formula = parse_ltlf(scene.task)
    bound = LowerBound(GameGraph(scene, formula, 1.0), formula)
    assert bound.enabled and bound.strike == 0
    assert bound(initial_state(scene), 0, False) == 10 == solve_explicit(scene).units
