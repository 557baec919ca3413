"""One validation for every way a costmap enters (a file, the cache, a
planner), cache files that stay in the cache folder, and `costmap verify`
that checks what `solve` checks (issue 16, rows 2, 4, 10 and 11)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from support.paper import SCENES
from support.planar import PlanarPlanner, planar_scene
from symsynth.cli import main
from symsynth.errors import InputError, SymsynthWarning
from symsynth.planning import cache
from symsynth.planning.build import compute_costmap, obtain_costmap
from symsynth.planning.verify import verify_costmap
from symsynth.scene.costmap import Costmap, write_costmap
from support.planar import gap_scene


def obtain(scene, **kw):
    return obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner, **kw)


def test_another_scenes_costmap_in_the_cache_is_not_used(tmp_path, monkeypatch):
    """A cache file replaced by another scene's valid costmap was reused:
    'no winning strategy' where the value is finite.  The file holds its key;
    one written under another key is computed again, with a warning."""
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    mine = obtain(scene)
    other = planar_scene(places={"l1": (0.5, 0.58), "l2": (0.2, 0.9)}, objects={"a": "l1"}, task="F(at(a, l2))")
    theirs = obtain(other)
    assert theirs.path != mine.path
    mine.path.write_bytes(theirs.path.read_bytes())
    with pytest.warns(SymsynthWarning, match="not written under this key"):
        again = obtain(scene)
    assert not again.cached and again.costmap == mine.costmap
    assert obtain(scene).cached  # written back, valid


def test_a_cache_file_with_the_right_key_but_foreign_names_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    mine = obtain(scene)
    data = json.loads(mine.path.read_text())
    data["motions"][0]["rules"][0]["free"] = ["l99"]
    data[cache.SUM_FIELD] = cache.checksum(data)  # (signed anew: the names are checked, not just the sum)
    mine.path.write_text(json.dumps(data))
    with pytest.warns(SymsynthWarning, match="does not fit the scene: .*unknown locations l99"):
        assert not obtain(scene).cached


@pytest.mark.parametrize("name", ["../../escaped", "/etc/passwd", "x" * 300, "..", "a b/c\\d\0e"])
def test_cache_files_stay_in_the_cache_folder(tmp_path, monkeypatch, name):
    """`name: ../../escaped` wrote the cache file outside $SYMSYNTH_CACHE; a
    300-character name was an OSError traceback."""
    folder = tmp_path / "deep" / "cache"
    monkeypatch.setenv("SYMSYNTH_CACHE", str(folder))
    scene = dataclasses.replace(gap_scene(), name=name)
    got = obtain(scene)
    assert got.path.parent == folder and got.path.is_file() and len(got.path.name) < 160
    assert sorted(p.name for p in tmp_path.rglob("*") if p.is_file()) == [got.path.name]


def test_a_planners_costmap_is_checked_like_a_file(monkeypatch):
    scene = gap_scene()
    costmap, stats = compute_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    key, rules = next(iter(costmap.motions.items()))
    bad = Costmap(dict(costmap.motions) | {key: (dataclasses.replace(rules[0], free=frozenset({"l99"})),)})
    from symsynth.planning import build
    monkeypatch.setattr(build, "compute_costmap", lambda *a, **k: (bad, stats))
    with pytest.raises(InputError, match="planner 'planar' computed a costmap that does not fit scene "
                                         "'planar': .*unknown locations l99"):
        obtain(scene, use_cache=False)


# -- costmap verify and physical scenes ----------------------------------------------

@pytest.fixture(scope="module")
def line_folder(paper_line, tmp_path_factory):
    """The line scene (ompl-fcl, small roadmap) as files, with its sg costmap."""
    scene, costmaps = paper_line
    folder = tmp_path_factory.mktemp("line")
    text = (SCENES / "line.yaml").read_text().replace("roadmap_size: 150", "roadmap_size: 60")
    (folder / "line.yaml").write_text(text)
    write_costmap(costmaps["sg"], folder / "sg.json")
    return folder


def edited_costmap(folder, edit):
    data = json.loads((folder / "sg.json").read_text())
    motion = next(m for m in data["motions"] if m["rules"] and m["rules"][0].get("path"))
    edit(motion["rules"][0])
    path = folder / "edited.json"
    path.write_text(json.dumps(data))
    return path


def test_verify_refuses_a_place_the_scene_does_not_have(line_folder, capsys):
    """`free: [l99]` verified as 'all evidence paths hold' (exit 0) while
    solve --costmap refused the file; both refuse it now."""
    path = edited_costmap(line_folder, lambda rule: rule.update(free=["l99"]))
    for argv in (["costmap", "verify", str(path), "--scene", str(line_folder / "line.yaml")],
                 ["solve", str(line_folder / "line.yaml"), "--costmap", str(path)]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "rule names unknown locations l99" in err and "Traceback" not in err


def test_ragged_waypoints_are_refused_when_read(line_folder, capsys):
    path = edited_costmap(line_folder, lambda rule: rule["path"][1].__delitem__(slice(3, None)))
    assert main(["costmap", "verify", str(path), "--scene", str(line_folder / "line.yaml")]) == 2
    err = capsys.readouterr().err
    assert "expected waypoints of one length (one number per joint), found lengths 3, 7" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("value, reason", [(1e300, "is outside the joint limits"), (3.5, "is outside the joint limits")])
def test_waypoints_beyond_the_joint_limits_fail_verification(line_folder, capsys, value, reason):
    """1e300 rad was an OverflowError traceback; such a path is no path of the robot."""
    path = edited_costmap(line_folder, lambda rule: rule["path"][1].__setitem__(0, value))
    assert main(["costmap", "verify", str(path), "--scene", str(line_folder / "line.yaml")]) == 1
    out, err = capsys.readouterr()
    assert "waypoint 1" in out and reason in out and "1 failed" in out and "Traceback" not in err


def test_waypoints_of_another_robot_fail_verification(paper_line):
    scene, costmaps = paper_line
    key, rules = next((k, r) for k, r in costmaps["sg"].motions.items() if r and r[0].path)
    short = dataclasses.replace(rules[0], path=tuple(q[:5] for q in rules[0].path))
    from symsynth.planning.registry import planner_class
    planner = planner_class("ompl-fcl")(scene)
    _, failures = verify_costmap(Costmap({key: (short,)}), scene, planner, 0.05, progress=False)
    assert [f.reason for f in failures] == ["waypoint 0 has 5 joint values, the robot has 7 joints"]
    assert np.asarray(planner.limits).shape == (7, 2)


def test_an_else_region_with_min_above_max_is_refused(tmp_path, capsys):
    text = (SCENES / "line.yaml").read_text()
    old = "region: {min: [0.25, -0.45], max: [0.65, 0.45]}"
    assert old in text
    path = tmp_path / "line.yaml"
    path.write_text(text.replace(old, "region: {min: [0.65, -0.45], max: [0.25, 0.45]}"))
    assert main(["costmap", str(path)]) == 2
    err = capsys.readouterr().err
    line = next(i for i, l in enumerate(text.splitlines(), 1) if "region:" in l)
    assert f"line.yaml:{line}: else.region: min [0.65, -0.45] must not exceed max [0.25, 0.45]" in err


def test_more_else_samples_than_the_limit_are_refused(tmp_path, capsys):
    text = (SCENES / "line.yaml").read_text()
    path = tmp_path / "line.yaml"
    path.write_text(text.replace("samples: 2", "samples: 1000000"))
    assert main(["costmap", str(path)]) == 2
    assert "else.samples: at most 64 Else samples, found 1000000" in capsys.readouterr().err


def test_a_huge_cost_in_a_cache_file_is_computed_again(tmp_path, monkeypatch):
    """A bad cache file kept solve crashing until it was deleted."""
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    mine = obtain(scene)
    data = json.loads(mine.path.read_text())
    data["motions"][0]["rules"][0]["cost"] = math.inf  # what 400 nines are read as
    data[cache.SUM_FIELD] = cache.checksum(data)  # (signed anew: the number is checked, not just the sum)
    mine.path.write_text(json.dumps(data).replace("Infinity", "9" * 400))
    with pytest.warns(SymsynthWarning, match="cost: expected a finite number"):
        assert not obtain(scene).cached
