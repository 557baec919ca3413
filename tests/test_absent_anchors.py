"""Absent anchors (docs/game-semantics.md §5, a **choice**): an anchor with no
robot configuration is listed under the costmap's `absent`; no motion or
slide touches it, and `starts(v)` with the hand empty at Else ranges over
home and the anchors that exist.  Every solver computes that value; the
costmap format, the scene's `absent_at` and the builder carry the list."""

from __future__ import annotations

import dataclasses
import json
import math
import random

import pytest
import yaml

from symsynth.testing.gamegen import random_scene
from support.games import bound_holds_everywhere, worst_case_of
from support.planar import PlanarPlanner, planar_scene
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.game.abstraction import initial_state, starts
from symsynth.game.solution import task_formula
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.build import compute_costmap
from symsynth.planning.protocol import PlannerError
from symsynth.scene import scene_from_data
from symsynth.scene.costmap import Rule, costmap_from_data
from symsynth.scene.load import costmap_problems
from symsynth.solvers import SOLVERS

SOLVER_NAMES = ("explicit", "symbolic", "compiled", "forward")

#: The shelf of scenes/shelf.yaml in the abstract: block b stands at l1 under
#: a low board, where the top grasp has no anchor (l1/top is absent); the
#: contact `pull` draws it out to l2.
SHELF_MOTIONS = [
    ("home", "l1/pull", 4), ("l2/top", "l1/pull", 6), ("l2/pull", "l1/pull", 2),
    ("home", "l2/top", 3), ("l1/pull", "l2/top", 5), ("l2/pull", "l2/top", 1),
    ("home", "l2/pull", 3), ("l2/top", "l2/pull", 2), ("l1/pull", "l2/pull", 3),
]


def shelf(task: str, absent: list[str] | None = ("l1/top",)) -> dict:
    data = {
        "name": "shelf-abstract",
        "objects": {"b": {"tags": ["block"], "at": "l1"}},
        "locations": ["l1", "l2"], "grasps": ["top"], "contacts": ["pull"],
        "primitives": {"grab": 5, "drop": 5}, "human": {"k": 0}, "task": task,
        "costmap": {"format": "symsynth.costmap/1",
                    "motions": [{"mode": "empty", "from": s, "to": t, "rules": [{"free": [], "cost": c}]}
                                for s, t, c in SHELF_MOTIONS],
                    "slides": [{"contact": "pull", "from": "l1", "to": "l2", "rules": [{"free": [], "cost": 3}]}]},
    }
    if absent is not None:
        data["costmap"]["absent"] = list(absent) if isinstance(absent, tuple) else absent
    return data


def values(scene, k=None, strategies=False):
    """Each solver's E_p; with `strategies`, each strategy is also followed
    through every human behaviour in the game and must pay exactly E_p."""
    formula = task_formula(scene, None)
    found = {}
    for name in SOLVER_NAMES:
        solution = SOLVERS[name](scene, formula, k=scene.k if k is None else k)
        if strategies and solution.units is not None:
            assert worst_case_of(scene, solution, formula) == solution.units, name
        found[name] = solution.cost_bound
    return found


@pytest.mark.parametrize("task, expected", [("F(at(b, l2))", 9.0), ("F(holding(b))", 15.0)])
def test_hand_solved_shelf(task, expected):
    """Hand empty at Else, the robot may be at home, l2/top, l1/pull or
    l2/pull (not l1/top: absent).  transit(b,top) aims at l1/top, which has
    no motion: not available.  transit(b,pull) to l1/pull costs the worst of
    home 4, l2/top 6, l1/pull 0 (already there), l2/pull 2: 6.  Then
    slide(b,pull,l2) costs 3: F(at(b,l2)) is won for 6 + 3 = 9.  For
    F(holding(b)): from (b,pull) with b at l2 the robot is at l2/pull, so
    transit(b,top) to l2/top costs 1 and grab 5: 6 + 3 + 1 + 5 = 15 (a
    transit to the top grasp before the slide aims at l1/top again)."""
    scene = scene_from_data(shelf(task))
    assert set(starts(scene, initial_state(scene))) == {"home", "l2/top", "l1/pull", "l2/pull"}
    assert values(scene, strategies=True) == dict.fromkeys(SOLVER_NAMES, expected)


def test_without_the_record_every_transit_from_else_is_infinite():
    """The contract read literally: l1/top is among the starts at Else and
    has no motion to anything, so every transit from the start is infinite."""
    scene = scene_from_data(shelf("F(at(b, l2))", absent=None))
    assert "l1/top" in starts(scene, initial_state(scene))
    assert values(scene) == dict.fromkeys(SOLVER_NAMES, None)


def with_absent(scene, rng: random.Random):
    """`scene` with one or two anchors absent (never home): their motions
    and slides left out and the list recorded."""
    absent = frozenset(rng.sample(scene.anchors[1:], rng.randint(1, 2)))
    costmap = scene.costmap
    motions = {key: rules for key, rules in costmap.motions.items() if key[1] not in absent and key[2] not in absent}
    slides = {key: rules for key, rules in costmap.slides.items()
              if f"{key[1]}/{key[0]}" not in absent and f"{key[2]}/{key[0]}" not in absent}
    result = dataclasses.replace(scene, costmap=dataclasses.replace(costmap, motions=motions, slides=slides,
                                                                    absent=absent))
    assert costmap_problems(result, result.costmap) == []
    return result


def reduced(scene):
    """The same game in the contract's own terms (no `absent` list): every
    absent anchor gets a free motion (cost 0) to every anchor.  A start the
    robot cannot be at then never raises a max (costs are >= 0), while no
    motion leads to it, so the contract's value is the one the choice
    defines: an independent check of every solver's `starts`."""
    costmap = scene.costmap
    motions = dict(costmap.motions)
    for s in costmap.absent:
        for t in scene.anchors[1:]:
            if t != s:
                motions[("empty", s, t)] = (Rule(frozenset(), 0.0),)
    return dataclasses.replace(scene, costmap=dataclasses.replace(costmap, motions=motions, absent=frozenset()))


@pytest.mark.parametrize("chunk", range(3))
def test_random_scenes_with_absent_anchors(chunk):
    """explicit == symbolic == compiled == forward == the contract's value of
    the reduced game, at k = 0..2; the lists change many values (the
    contract read literally makes them infinite)."""
    changed = finite = 0
    for seed in range(25 * chunk, 25 * (chunk + 1)):
        rng = random.Random(f"absent {seed}")
        scene = with_absent(random_scene(7000 + seed, contacts=seed % 2 == 0), rng)
        k = seed % 3
        found = values(scene, k, strategies=seed % 5 == 0)
        expected = SOLVERS["explicit"](reduced(scene), task_formula(scene, None), k=k).cost_bound
        assert found == dict.fromkeys(SOLVER_NAMES, expected), (seed, k)
        literal = dataclasses.replace(scene, costmap=dataclasses.replace(scene.costmap, absent=frozenset()))
        changed += SOLVERS["explicit"](literal, task_formula(scene, None), k=k).cost_bound != expected
        finite += expected is not None
        if seed % 5 == 0:
            bound_holds_everywhere(scene, k)  # the forward solver's lower bound stays admissible
    assert changed >= 3 and finite >= 5, (changed, finite)


def test_scenes_without_absent_anchors_keep_their_value():
    for seed in range(20):
        scene = random_scene(7100 + seed, contacts=seed % 2 == 0)
        assert scene.present_anchors == scene.anchors
        assert reduced(scene) == scene


# -- the format ----------------------------------------------------------------------

def test_costmap_round_trip_and_no_key_without_absences():
    scene = scene_from_data(shelf("F(at(b, l2))"))
    data = scene.costmap.to_json()
    assert data["absent"] == ["l1/top"]
    assert costmap_from_data(data).absent == {"l1/top"}
    assert "absent" not in dataclasses.replace(scene.costmap, absent=frozenset()).to_json()


@pytest.mark.parametrize("absent, expected", [
    ("l1/top", "absent: expected a list of anchors"),
    (["l1"], "absent[0]: expected an anchor PLACE/GRASP"),
    (["l1/top", "l1/top"], "absent[1]: 'l1/top' is listed twice"),
    (["l9/top"], "absent: 'l9/top' is not an anchor of the scene"),
    (["home/top"], "absent: 'home/top' is not an anchor of the scene"),
    (["l2/top"], "motion empty home -> l2/top: 'l2/top' is listed as absent"),
    (["l2/pull"], "slide pull l1 -> l2: its anchor l2/pull is listed as absent"),
])
def test_bad_absent_lists_are_named(absent, expected):
    with pytest.raises(InputError) as caught:
        scene_from_data(shelf("F(at(b, l2))", absent=absent))
    assert expected in str(caught.value)


def test_without_contacts_drops_their_absent_anchors():
    scene = scene_from_data(shelf("F(at(b, l2))", absent=["l1/top", "l2/pull"]) | {"costmap": {
        "format": "symsynth.costmap/1", "absent": ["l1/top", "l2/pull"],
        "motions": [{"mode": "empty", "from": "home", "to": "l1/pull", "rules": [{"free": [], "cost": 1}]}]}})
    assert scene.without_contacts().costmap.absent == {"l1/top"}


# -- physical scenes: absent_at and the builder ----------------------------------------

def planar_with_absent(absent_at=("far", "wall")):
    scene = planar_scene(places={"l1": (0.5, 0.58), "l2": (0.7, 0.58), "far": (1.5, 0.5), "wall": (0.3, 0.38)},
                         objects={"a": "l1"}, obstacles={"w": (0.3, 0.3, 0.05, 0.05)}, task="F(at(a, l2))")
    geometry = scene.geometry
    grasps = {g: dataclasses.replace(frame, absent_at=frozenset(absent_at)) for g, frame in geometry.grasps.items()}
    return dataclasses.replace(scene, geometry=dataclasses.replace(geometry, grasps=grasps))


def test_builder_records_the_declared_absent_anchors():
    """far/top is out of reach and wall/top inside an obstacle: undeclared,
    they are an error that says how to declare them; declared, the costmap
    lists them, has no motion touching them, and solves (a to l2: the
    planar grid's values are test_costmap_build's business)."""
    with pytest.raises(PlannerError, match="absent_at"):
        anchor_configs(PlanarPlanner(planar_with_absent(())), planar_with_absent(()))
    scene = planar_with_absent()
    assert set(anchor_configs(PlanarPlanner(scene), scene)) == {"home", "l1/top", "l2/top"}
    costmap = compute_costmap(scene, "recursive", "planar", progress=False, planner_factory=PlanarPlanner)[0]
    assert costmap.absent == {"far/top", "wall/top"}
    assert not any({s, t} & costmap.absent for _, s, t in costmap.motions)
    assert costmap_problems(scene, costmap) == []
    solved = dataclasses.replace(scene, costmap=costmap)
    assert math.isfinite(SOLVERS["explicit"](solved, task_formula(solved, None)).cost_bound)
    other = dataclasses.replace(costmap, absent=frozenset({"far/top"}))
    assert any("it is another scene's costmap" in p for p in costmap_problems(scene, other))


PHYSICAL = """
name: p
robot: {}
objects: {b: {box: [0.04, 0.04, 0.04], at: l1}}
locations: {l1: {xyz: [0.5, 0, 0]}}
grasps: {top: {xyz: [0, 0, 0.1], absent_at: [%s]}}
"""


def test_absent_at_names_places():
    import yaml
    scene = scene_from_data(yaml.safe_load(PHYSICAL % "l1"))
    assert scene.geometry.absent == {"l1/top"}
    with pytest.raises(InputError, match=r"grasps\.top\.absent_at\.0.*'l7' is no place of the scene"):
        scene_from_data(yaml.safe_load(PHYSICAL % "l7"))


def test_solve_reports_the_absent_anchors(tmp_path, capsys):
    """`symsynth solve` names the anchors the costmap declares absent, in
    text and JSON, so a reader of E_p knows which motions do not exist;
    a scene without any prints no such line."""
    for absent, expected in ((["l1/top"], ["l1/top"]), (None, None)):
        path = tmp_path / "shelf.yaml"
        path.write_text(yaml.safe_dump(shelf("F(at(b, l2))", absent=absent)))
        assert main(["solve", str(path)]) == 0
        lines = [line for line in capsys.readouterr().out.splitlines() if line.startswith("absent")]
        assert lines == ([] if expected is None else [lines[0]])
        if expected is not None:
            assert lines[0].split()[1].rstrip(":") == "l1/top"
        assert main(["solve", "--json", str(path)]) == 0
        assert json.loads(capsys.readouterr().out).get("absent") == expected
