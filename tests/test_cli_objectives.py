"""`symsynth solve --objective` and `symsynth simulate --objective` on the
scenes solved by hand (scenes/wait.yaml, scenes/reach.yaml): the §9 JSON
keys, the runs next to EX, and clear errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def symsynth(*args):
    return subprocess.run([sys.executable, "-m", "symsynth.cli", *map(str, args)], capture_output=True, text=True)


def test_solve_expected_json_has_the_keys_of_semantics_9(tmp_path):
    done = symsynth("solve", SCENES / "wait.yaml", "--objective", "expected", "--json", "-o", tmp_path / "s.json")
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert out["objective"] == "expected" and out["human_model"] == "random(0.3)"
    assert out["cost_bound"] == 21 and out["budget"] == 21
    assert out["expected_cost"] == pytest.approx(11.3, abs=1e-9)
    assert out["attained"] is False and out["waiting"] == 42 and out["strategy"]["entries"] > 0


def test_solve_best_effort_json(tmp_path):
    done = symsynth("solve", SCENES / "reach.yaml", "--objective", "best-effort", "--json")
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert (out["objective"], out["class"], out["cooperative_cost"], out["cost_bound"]) == (
        "best-effort", "cooperative", 9, None)


def test_solve_expected_without_a_model_names_both_places():
    done = symsynth("solve", SCENES / "toy.yaml", "--objective", "expected")
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "--human-model random:P" in done.stderr and "human: {k: K, model: random(P)}" in done.stderr


def test_solve_expected_below_E_p_is_undefined():
    done = symsynth("solve", SCENES / "wait.yaml", "--objective", "expected", "--budget", "20", "--json")
    out = json.loads(done.stdout)
    assert out["expected_cost"] is None and out["realizable"] is False and out["cost_bound"] == 21


def test_simulate_expected_agrees_with_EX_and_stays_within_B():
    done = symsynth("simulate", SCENES / "wait.yaml", "--objective", "expected", "--runs", 4000, "--json")
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    random_runs = out["runs"]["random"]
    assert abs(random_runs["mean_cost"] - 11.3) <= random_runs["ci95"] * 2 + 1e-6  # 4 sigma
    assert random_runs["above_budget"] == 0 and out["runs"]["adversarial"]["max_cost"] <= 21
    assert out["runs"]["every human"]["max_cost"] <= 21
    assert out["runs"]["worst-case strategy"]["expected_cost"] == pytest.approx(13.505)  # by hand


def test_simulate_best_effort_against_three_humans():
    done = symsynth("simulate", SCENES / "reach.yaml", "--objective", "best-effort", "--runs", 4000, "--json")
    assert done.returncode == 0, done.stderr
    runs = json.loads(done.stdout)["runs"]
    assert runs["cooperative"]["finished"] == 1 and runs["cooperative"]["mean_cost"] == 9
    assert runs["adversarial"]["finished"] == 0
    assert runs["random"]["finish_probability"] == pytest.approx(0.745)
    assert abs(runs["random"]["finished"] - 0.745) < 4 * (0.745 * 0.255 / 4000) ** 0.5


def test_simulate_in_world_needs_a_physical_scene():
    done = symsynth("simulate", SCENES / "wait.yaml", "--objective", "expected", "--in-world")
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "abstract scene" in done.stderr and "--in-world" in done.stderr


@pytest.mark.parametrize("world", [[], ["--world", "kinematic"]])
def test_simulate_in_world_chooses_the_world_as_simulate_does(world):
    """--randomize is refused in the kinematic world, asked for or the scene's
    default (the paper's arch: the lintel does not fit the fingers)."""
    done = symsynth("simulate", SCENES / "arch.yaml", "--objective", "expected", "--in-world",
                    "--randomize", "mass=0.1", *world)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "add --world physics" in done.stderr


@pytest.mark.parametrize("options, expected", [
    (["--objective", "best-effort", "--human", "adversarial"], "runs against --human none, random"),
    (["--objective", "expected", "--human-model", "nosuchmodel:1"], "unknown human model"),
])
def test_simulate_in_world_checks_the_humans_before_the_costmap(tmp_path, options, expected):
    """A wrong --human or --human-model with --in-world is refused before any
    planning: the costmap cache stays empty (it held the arch's costmap when
    the check came after it)."""
    env = dict(os.environ, SYMSYNTH_CACHE=str(tmp_path / "cache"))
    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "simulate", str(SCENES / "arch.yaml"),
                           "--in-world", "--world", "kinematic", *options], capture_output=True, text=True, env=env)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert expected in done.stderr
    written = [p.name for p in (tmp_path / "cache").rglob("*") if p.is_file()]
    assert [name for name in written if name.startswith("arch-")] == []  # a costmap is named after its scene
