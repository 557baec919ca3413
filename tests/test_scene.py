"""Scene and costmap loading: every problem reported with file, line and key
path, and a valid file read back exactly."""

import json
import textwrap

import pytest

from symsynth.errors import InputError
from symsynth.planning.methods import METHODS as planning_methods
from symsynth.scene import Costmap, Provenance, Rule, load_costmap, load_scene, write_costmap
from symsynth.scene.costmap import METHODS, CostmapError, costmap_from_data
from symsynth.scene.load import SceneError

GOOD = """\
name: toy
objects:
  w1: {tags: [block, white], at: l1}
  b:  {tags: [block, black], at: Else}
locations: [l1, l2, l3]
else_samples: [e1, e2]
grasps: [top]
primitives: {grab: 5, drop: 4}
human: {k: 2}
task: "F(at(black, l2)) & G(occupied(l3) -> at(white, l1))"
costmap: toy.costmap.json
"""

COSTMAP = {"format": "symsynth.costmap/1", "motions": [
    {"mode": "empty", "from": "home", "to": "l1/top",
     "rules": [{"free": [], "cost": 7}, {"free": ["l2"], "cost": 3}]},
    {"mode": "b/top", "from": "e1/top", "to": "l2/top", "rules": [{"free": ["e2"], "cost": 4}]},
]}


def write(tmp_path, text, costmap=COSTMAP):
    (tmp_path / "toy.costmap.json").write_text(json.dumps(costmap))
    path = tmp_path / "toy.yaml"
    path.write_text(textwrap.dedent(text))
    return path


def problems(tmp_path, text, costmap=COSTMAP):
    with pytest.raises(SceneError) as caught:
        load_scene(write(tmp_path, text, costmap))
    return str(caught.value)


def test_valid_scene_is_read_exactly(tmp_path):
    scene = load_scene(write(tmp_path, GOOD))
    assert scene.object_names == ("w1", "b")
    assert scene.objects[0].tags == {"w1", "block", "white"}  # own name is a tag
    assert scene.objects[1].at == "Else"
    assert scene.locations == ("l1", "l2", "l3") and scene.else_samples == ("e1", "e2")
    assert (scene.grab_cost, scene.drop_cost, scene.k) == (5.0, 4.0, 2)
    assert scene.costmap.rules("empty", "home", "l1/top") == (Rule(frozenset(), 7.0),
                                                             Rule(frozenset({"l2"}), 3.0))
    assert scene.costmap.rules("empty", "l1/top", "home") == ()
    assert scene.anchors == ("home", "l1/top", "l2/top", "l3/top", "e1/top", "e2/top")
    assert scene.modes == ("empty", "w1/top", "b/top")


def test_two_objects_at_one_location(tmp_path):
    text = GOOD.replace("b:  {tags: [block, black], at: Else}", "b:  {tags: [block, black], at: l1}")
    message = problems(tmp_path, text)
    assert f"{tmp_path / 'toy.yaml'}:4: objects.b.at: location 'l1' already holds 'w1'" in message


def test_unknown_location_in_at_lists_the_known_ones(tmp_path):
    message = problems(tmp_path, GOOD.replace("at: Else}", "at: l9}"))
    assert ":4: objects.b.at: unknown location 'l9'; expected one of l1, l2, l3, Else" in message


def test_every_problem_is_reported_at_once(tmp_path):
    text = (GOOD.replace("at: Else}", "at: l9}")
            .replace("at(black, l2)", "at(black, l7)")
            .replace("G(occupied(l3)", "G(occupied(l3) & holding(green)"))
    message = problems(tmp_path, text)
    assert message.startswith("2 problems in the scene:")
    assert ":4: objects.b.at:" in message
    assert ":10: task:" in message and "unknown location 'l7'" in message


def test_unknown_tag_in_task_lists_the_known_ones(tmp_path):
    message = problems(tmp_path, GOOD.replace("at(black, l2)", "at(green, l2)"))
    assert "unknown object or tag 'green'; known: b, black, block, w1, white" in message


def test_task_syntax_error_names_the_line(tmp_path):
    message = problems(tmp_path, GOOD.replace('task: "F(at(black, l2))', 'task: "F(at(black, l2)'))
    assert ":10: task: syntax error" in message and "^" in message


def test_schema_problems_name_key_path_and_expectation(tmp_path):
    text = GOOD.replace("primitives: {grab: 5, drop: 4}", "primitives: {grab: -5, drop: 4}")
    assert ":8: primitives.grab: -5 is less than the minimum of 0" in problems(tmp_path, text)
    text = GOOD.replace("human: {k: 2}", "human: {k: two}")
    assert ":9: human.k: expected integer, found 'two'" in problems(tmp_path, text)
    text = GOOD.replace("grasps: [top]", "grasp: [top]")
    assert "'grasp' was unexpected" in problems(tmp_path, text)
    assert "'locations' is required" in problems(tmp_path, GOOD.replace("locations: [l1, l2, l3]\n", ""))


def test_reserved_and_clashing_names(tmp_path):
    text = GOOD.replace("locations: [l1, l2, l3]", "locations: [l1, l2, l3, Else]")
    assert "locations.3: 'Else' is reserved" in problems(tmp_path, text)
    text = GOOD.replace("else_samples: [e1, e2]", "else_samples: [e1, l2]")
    assert "else_samples.1: 'l2' is already a location of interest" in problems(tmp_path, text)


def test_costmap_with_unknown_anchor_mode_location(tmp_path):
    bad = {"format": "symsynth.costmap/1", "motions": [
        {"mode": "x/top", "from": "home", "to": "l9/top", "rules": [{"free": ["l8"], "cost": 1}]}]}
    message = problems(tmp_path, GOOD, bad)
    assert "unknown mode 'x/top'" in message
    assert "unknown anchor 'l9/top'" in message
    assert "rule names unknown locations l8" in message


def test_costmap_negative_cost_and_missing_file(tmp_path):
    bad = {"format": "symsynth.costmap/1", "motions": [
        {"mode": "empty", "from": "home", "to": "l1/top", "rules": [{"free": [], "cost": -3}]}]}
    assert "motions[0].rules[0].cost: must be >= 0, found -3" in problems(tmp_path, GOOD, bad)
    text = GOOD.replace("toy.costmap.json", "missing.json")
    assert "cannot read costmap" in problems(tmp_path, text) and "missing.json" in problems(tmp_path, text)


def test_costmap_not_json_names_line(tmp_path):
    path = tmp_path / "c.json"
    path.write_text('{"format": "symsynth.costmap/1",\n "motions": [,]}')
    with pytest.raises(InputError, match=r"c\.json:2:\d+: not JSON"):
        load_costmap(path)


def test_costmap_write_read_round_trip(tmp_path):
    costmap = Costmap({("empty", "home", "l1/top"): (Rule(frozenset(), 7.0), Rule(frozenset({"l2", "e1"}), 2.5)),
                       ("b/top", "e1/top", "l2/top"): (Rule(frozenset({"e2"}), 4.0, ((0.0, 1.5), (0.5, 1.0))),)})
    write_costmap(costmap, tmp_path / "c.json")
    back = load_costmap(tmp_path / "c.json")
    assert back == costmap
    assert back.rules("b/top", "e1/top", "l2/top")[0].path == ((0.0, 1.5), (0.5, 1.0))
    assert back.provenance is None and "planner" not in json.loads((tmp_path / "c.json").read_text())


@pytest.mark.parametrize("provenance", [
    Provenance("pybullet", "0.1.0", "recursive", 3, 60, None, 0.05),
    Provenance("ompl-fcl", method="sg", seed=0, seconds=2.5, check_step=0.1),
    Provenance("my-planner"),  # only the name is required
])
def test_costmap_provenance_round_trip(tmp_path, provenance):
    costmap = Costmap({("empty", "home", "l1/top"): (Rule(frozenset(), 7.0, ((0.0,), (7.0,))),)}, provenance)
    write_costmap(costmap, tmp_path / "c.json")
    data = json.loads((tmp_path / "c.json").read_text())
    assert list(data) == ["format", "planner", "motions"]  # who built it, before the motions
    assert data["planner"] == {k: v for k, v in vars(provenance).items() if v is not None}
    back = load_costmap(tmp_path / "c.json")
    assert back == costmap and back.provenance == provenance


def test_costmap_provenance_written_before_the_rename_reads_resolution_as_check_step():
    """Costmap files (and cache entries) written while the key was
    `resolution` keep their meaning; new files say `check_step`."""
    old = dict(COSTMAP, planner={"name": "pybullet", "resolution": 0.025})
    assert costmap_from_data(old).provenance == Provenance("pybullet", check_step=0.025)
    assert costmap_from_data(old).provenance.to_json() == {"name": "pybullet", "check_step": 0.025}


def test_costmap_keys_the_loader_does_not_know_are_ignored_in_the_provenance_too():
    data = dict(COSTMAP, comment="by hand", planner={"name": "pybullet", "seed": 2, "colour": "blue"})
    assert costmap_from_data(data).provenance == Provenance("pybullet", seed=2)


def test_costmap_provenance_methods_are_the_planning_methods():
    assert METHODS == tuple(planning_methods)


@pytest.mark.parametrize("planner, expected", [
    ("pybullet", ["planner: expected an object with the name and settings of the planner that built the "
                  "costmap, found 'pybullet'"]),
    (None, ["planner: expected an object"]),
    ({"seed": 0}, ["planner.name: expected the planner's name, found None"]),
    ({"name": "pybullet", "version": 1, "method": "astar", "seed": -1, "roadmap_size": 2.5,
      "check_step": 0, "seconds": float("inf")},
     ["planner.version: expected a non-empty string, found 1",
      "planner.method: expected one of sg, recursive, found 'astar'",
      "planner.seed: expected a whole number >= 0, found -1",
      "planner.roadmap_size: expected a whole number >= 2, found 2.5",
      "planner.seconds: expected a finite number > 0, found inf",
      "planner.check_step: expected a finite number > 0, found 0",
      "planner: a roadmap has either a size (roadmap_size) or a time limit (seconds), not both"]),
    ({"name": "", "seed": True}, ["planner.name: expected the planner's name, found ''",
                                  "planner.seed: expected a whole number >= 0, found True"]),
])
def test_costmap_bad_provenance_is_reported_with_its_key_path(planner, expected):
    """Every problem at once, the motions' among them."""
    data = {"format": "symsynth.costmap/1", "planner": planner, "motions": [
        {"mode": "empty", "from": "home", "to": "l1/top", "rules": [{"free": [], "cost": -3}]}]}
    with pytest.raises(CostmapError) as error:
        costmap_from_data(data, "c.json")
    lines = str(error.value).splitlines()
    assert lines[0] == "c.json: invalid costmap:"
    assert "  motions[0].rules[0].cost: must be >= 0, found -3" in lines
    for problem in expected:
        assert any(line.startswith(f"  {problem}") for line in lines), (problem, lines)
    assert len(lines) == 2 + len(expected)


def test_scene_costmap_with_bad_provenance_names_the_scene_key(tmp_path):
    bad = dict(COSTMAP, planner={"name": "pybullet", "seed": "zero"})
    assert "planner.seed: expected a whole number >= 0, found 'zero'" in problems(tmp_path, GOOD, bad)


def test_yaml_syntax_error_names_the_line(tmp_path):
    path = write(tmp_path, GOOD.replace("grasps: [top]", "grasps: [top"))
    with pytest.raises(SceneError, match=r"toy\.yaml:\d+: not valid YAML"):
        load_scene(path)


def test_missing_scene_file(tmp_path):
    with pytest.raises(SceneError, match="cannot read scene"):
        load_scene(tmp_path / "nope.yaml")


def test_unreadable_text_and_odd_yaml_are_named(tmp_path):
    path = tmp_path / "latin.yaml"
    path.write_bytes(b"name: x\xff\nobjects: {}\nlocations: [l1]\n")
    with pytest.raises(SceneError, match=r"latin.yaml is not UTF-8 text"):
        load_scene(path)
    path = write(tmp_path, "name: x\nobjects:\n  ? [a]\n  : {}\nlocations: [l1]\n")
    with pytest.raises(SceneError, match=r"toy.yaml:3: not valid YAML: a key must be a name"):
        load_scene(path)
    merged = write(tmp_path, GOOD.replace("  b:  {tags: [block, black], at: Else}",
                                          "  b:  {<<: {tags: [block, black]}, at: Else}"))
    assert load_scene(merged) == load_scene(write(tmp_path, GOOD))


def test_costmap_infinite_cost_and_bad_path(tmp_path):
    costmap = json.loads(json.dumps(COSTMAP))
    costmap["motions"][0]["rules"][0]["cost"] = float("inf")
    costmap["motions"][1]["rules"][0]["path"] = [["a"]]
    with pytest.raises(InputError) as error:
        load_scene(write(tmp_path, GOOD, costmap))
    assert "motions[0].rules[0].cost: expected a finite number, found inf" in str(error.value)
    assert "motions[1].rules[0].path: expected a list of waypoints" in str(error.value)


def test_defaults_reserved_names_format_and_the_cap_on_problems(tmp_path):
    bare = load_scene(write(tmp_path, "name: bare\nobjects: {a: {at: l1}}\nlocations: [l1, l2]\n"))
    assert (bare.grab_cost, bare.drop_cost, bare.grasps, bare.k, bare.costmap) == (5.0, 5.0, ("top",), 0, None)
    for name in ("home", "Hand"):
        with pytest.raises(SceneError, match=f"locations.3: '{name}' is reserved"):
            load_scene(write(tmp_path, GOOD.replace("[l1, l2, l3]", f"[l1, l2, l3, {name}]")))
    with pytest.raises(InputError, match="format: expected 'symsynth.costmap/1', found 'symsynth.costmap/0'"):
        load_scene(write(tmp_path, GOOD, dict(COSTMAP, format="symsynth.costmap/0")))
    foreign = {"format": "symsynth.costmap/1", "motions": [
        {"mode": "empty", "from": "home", "to": f"x{i}/top", "rules": [{"free": [], "cost": 1}]}
        for i in range(20)]}
    with pytest.raises(SceneError) as error:
        load_scene(write(tmp_path, GOOD, foreign))
    message = str(error.value)
    assert message.startswith("20 problems in the scene") and "... and 8 more" in message
    assert message.count("unknown anchor") == 12
