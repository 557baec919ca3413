"""`symsynth costmap`, `costmap verify`, `show` and `solve` on a physical
scene, through `symsynth.cli.main`: the arch with a 30-vertex roadmap and
the pybullet planner, in a private cache folder."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from symsynth import __version__
from symsynth.cli import main
from symsynth.planning import cache
from symsynth.scene import load_scene, write_costmap

ARCH = "scenes/arch.yaml"


@pytest.fixture(scope="module")
def small_arch(tmp_path_factory):
    folder = tmp_path_factory.mktemp("arch")
    data = yaml.safe_load(Path(ARCH).read_text())
    data["planner"] = {"name": "pybullet", "roadmap_size": 30, "check_step": 0.05, "seed": 0}
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
                                  "roadmap_size": 30, "check_step": 0.05}
    assert summary["rules"] == sum(len(m["rules"]) for m in written["motions"]) > 0
    assert all(rule["path"] for m in written["motions"] for rule in m["rules"])
    assert "mode/s" not in err  # progress bars only on a terminal (stderr is captured here)

    code, out, err = run(capsys, "costmap", "verify", str(out_file), "--scene", str(small_arch))
    assert code == 0 and "all evidence paths hold" in out
    assert "rule/s" not in err

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


@pytest.fixture(scope="module")
def pybullet_file(paper_arch, tmp_path_factory):
    """The session's arch start-goal costmap, built by pybullet, as a file;
    scenes/arch.yaml names ompl-fcl (and the same check step)."""
    path = tmp_path_factory.mktemp("built") / "arch.json"
    write_costmap(paper_arch[1]["sg"], path)
    assert load_scene(ARCH).geometry.planner.name == "ompl-fcl"
    return path


def test_verify_uses_the_planner_the_costmap_records(capsys, pybullet_file):
    """With the scene's planner, ompl-fcl, every rule would miss its anchors."""
    code, out, err = run(capsys, "costmap", "verify", str(pybullet_file), "--scene", ARCH)
    assert code == 0, out + err
    assert "with planner pybullet at check step 0.0125 rad: all evidence paths hold" in out


def test_verify_refuses_another_planner_than_the_recorded_one(capsys, pybullet_file):
    code, out, err = run(capsys, "costmap", "verify", str(pybullet_file), "--scene", ARCH, "--planner", "ompl-fcl")
    assert code == 2 and not out and "Traceback" not in err
    assert (f"--planner ompl-fcl: {pybullet_file} was built by planner 'pybullet' (its key 'planner'), and its "
            "evidence paths start and end at pybullet's inverse kinematics solutions for the anchors; ompl-fcl's "
            "solutions differ, so every rule would fail its end points. Leave --planner out to verify with "
            "pybullet") in err


def test_verify_without_a_record_needs_the_planner(capsys, pybullet_file, tmp_path):
    data = json.loads(pybullet_file.read_text())
    del data["planner"]
    older = tmp_path / "older.json"
    older.write_text(json.dumps(data))
    code, out, err = run(capsys, "costmap", "verify", str(older), "--scene", ARCH)
    assert code == 2 and "Traceback" not in err
    assert f"{older} does not record the planner that built it" in err and "--planner NAME" in err
    code, out, err = run(capsys, "costmap", "verify", str(older), "--scene", ARCH, "--planner", "pybullet")
    assert code == 0 and "with planner pybullet" in out and "all evidence paths hold" in out


def test_verify_notes_a_costmap_built_by_another_version_of_the_planner(capsys, pybullet_file, tmp_path):
    data = json.loads(pybullet_file.read_text())
    data["planner"]["version"] = "0.0.1"
    older = tmp_path / "older.json"
    older.write_text(json.dumps(data))
    code, out, err = run(capsys, "costmap", "verify", str(older), "--scene", ARCH)
    assert code == 0 and "all evidence paths hold" in out
    assert f"note       {older} was built by pybullet 0.0.1, pybullet {__version__} is installed" in out


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
    (["costmap", ARCH, "--planner", "moveit"], "unknown planner 'moveit'; installed planners: ompl-fcl, pybullet"),
    (["costmap", "scenes/toy.yaml"], "an abstract scene (no 'robot' key)"),
    (["costmap", "verify", "x.json"], "usage: symsynth costmap verify FILE --scene SCENE"),
    (["costmap", ARCH, "scenes/line.yaml"], "expected one scene file, found 2"),
    (["show", "scenes/toy.yaml"], "an abstract scene (no 'robot' key) has nothing to show"),
    (["show", ARCH, "--size", "big"], "expected WIDTHxHEIGHT"),
])
def test_bad_input_is_one_message(capsys, argv, expected):
    code, out, err = run(capsys, *argv)
    assert code == 2 and expected in err and "Traceback" not in err

def test_verify_never_checks_coarser_than_the_scene_asks(capsys, pybullet_file, tmp_path):
    """A record claiming a coarse build check step (stale or edited) must not
    weaken the check: the step is a quarter of the finer of the two, here
    the scene's 0.05 rad."""
    assert load_scene(ARCH).geometry.planner.check_step == 0.05
    data = json.loads(pybullet_file.read_text())
    data["planner"]["check_step"] = 100.0
    coarse = tmp_path / "coarse.json"
    coarse.write_text(json.dumps(data))
    code, out, err = run(capsys, "costmap", "verify", str(coarse), "--scene", ARCH)
    assert code == 0, out + err
    assert "at check step 0.0125 rad" in out


def test_verify_names_a_recorded_planner_that_is_not_installed(capsys, pybullet_file, tmp_path):
    data = json.loads(pybullet_file.read_text())
    data["planner"]["name"] = "moveit"
    foreign = tmp_path / "foreign.json"
    foreign.write_text(json.dumps(data))
    for extra in ((), ("--planner", "pybullet")):
        code, out, err = run(capsys, "costmap", "verify", str(foreign), "--scene", ARCH, *extra)
        assert code == 2 and not out and "Traceback" not in err
        assert (f"{foreign} records planner 'moveit' as its builder (its key 'planner'), which is not installed "
                "(installed: ompl-fcl, pybullet)") in err
        assert "remove the key from the file and give --planner NAME" in err


def test_a_cached_costmap_without_a_record_gets_it_written_back(capsys, tmp_path, small_arch):
    """A cache file from before the record existed is reused, and written back
    with the record its key implies, so the file `costmap` names verifies
    without --planner."""
    code, out, err = run(capsys, "costmap", str(small_arch), "--json")
    assert code == 0, err
    cached = json.loads(out)["file"]
    data = json.loads(Path(cached).read_text())
    recorded = data.pop("planner")
    data[cache.SUM_FIELD] = cache.checksum(data)  # as that older symsynth wrote it, content and sum agreeing
    with open(cached, "w") as f:
        json.dump(data, f)
    code, out, err = run(capsys, "costmap", str(small_arch), "--json")
    assert code == 0 and json.loads(out)["cached"] is True, err
    assert json.loads(Path(cached).read_text())["planner"] == recorded
    code, out, err = run(capsys, "costmap", "verify", cached, "--scene", str(small_arch))
    assert code == 0 and "with planner pybullet" in out and "all evidence paths hold" in out, out + err
