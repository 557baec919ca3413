"""`symsynth costmap`, `costmap verify`, `show` and `solve` on a physical
scene, through `symsynth.cli.main`: the arch with a 30-vertex roadmap and
the pybullet planner, in a private cache folder."""

from __future__ import annotations

import json

import pytest
import yaml

from symsynth import __version__
from symsynth.cli import main

ARCH = "scenes/arch.yaml"


@pytest.fixture(scope="module")
def small_arch(tmp_path_factory):
    folder = tmp_path_factory.mktemp("arch")
    data = yaml.safe_load(open(ARCH))
    data["planner"] = {"name": "pybullet", "roadmap_size": 30, "resolution": 0.05, "seed": 0}
    path = folder / "arch.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_compute_verify_and_reuse(capsys, tmp_path, small_arch):
    out_file = tmp_path / "arch.json"
    code, out, err = run(capsys, "costmap", str(small_arch), "-o", str(out_file), "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["cached"] is False and summary["file"] == str(out_file)
    written = json.loads(out_file.read_text())
    assert written["format"] == "symsynth.costmap/1"
    assert written["planner"] == {"name": "pybullet", "version": __version__, "method": "recursive", "seed": 0,
                                  "roadmap_size": 30, "resolution": 0.05}
    assert summary["rules"] == sum(len(m["rules"]) for m in written["motions"]) > 0
    assert all(rule["path"] for m in written["motions"] for rule in m["rules"])

    code, out, _ = run(capsys, "costmap", "verify", str(out_file), "--scene", str(small_arch))
    assert code == 0 and "all evidence paths hold" in out

    again = tmp_path / "again.json"
    code, out, _ = run(capsys, "costmap", str(small_arch), "-o", str(again))
    assert code == 0 and "reused from the cache" in out
    assert again.read_text() == out_file.read_text()  # same seed, same file

    # A rule that claims less than its path costs is caught.
    motion = next(m for m in written["motions"] if m["rules"][0]["cost"] > 0)
    motion["rules"][0]["cost"] /= 2
    out_file.write_text(json.dumps(written))
    code, out, _ = run(capsys, "costmap", "verify", str(out_file), "--scene", str(small_arch))
    assert code == 1 and f"FAIL {motion['mode']} {motion['from']} -> {motion['to']}, rule 0: cost" in out


def test_solve_computes_then_reuses_the_costmap(capsys, small_arch):
    code, out, err = run(capsys, "solve", str(small_arch), "--k", "0", "--json")
    assert code == 0, err
    first = json.loads(out)
    assert first["costmap"]["cached"] is False and first["costmap"]["planner"] == "pybullet"
    code, out, _ = run(capsys, "solve", str(small_arch), "--k", "0", "--json")
    second = json.loads(out)
    assert second["costmap"]["cached"] is True and second["cost_bound"] == first["cost_bound"]


def test_show_writes_a_picture(capsys, tmp_path, small_arch):
    picture = tmp_path / "arch.png"
    code, out, _ = run(capsys, "show", str(small_arch), "-o", str(picture), "--size", "64x48")
    assert code == 0 and picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "5 locations, 2 Else samples" in out


@pytest.mark.parametrize("argv, expected", [
    (["costmap", ARCH, "--seed", "-1"], "--seed: must be >= 0"),
    (["solve", ARCH, "--seed", "x"], "--seed: expected a whole number"),
    (["costmap", ARCH, "-o", "/nonexistent/folder/c.json"], "cannot write costmap file"),
    (["costmap", ARCH, "--planner", "moveit"], "unknown planner 'moveit'; known planners: ompl-fcl, pybullet"),
    (["costmap", "scenes/toy.yaml"], "an abstract scene (no 'robot' key)"),
    (["costmap", "verify", "x.json"], "usage: symsynth costmap verify FILE --scene SCENE"),
    (["costmap", ARCH, "scenes/line.yaml"], "expected one scene file, found 2"),
    (["show", "scenes/toy.yaml"], "an abstract scene (no 'robot' key) has nothing to show"),
    (["show", ARCH, "--size", "big"], "expected WIDTHxHEIGHT"),
])
def test_bad_input_is_one_message(capsys, argv, expected):
    code, out, err = run(capsys, *argv)
    assert code == 2 and expected in err and "Traceback" not in err
