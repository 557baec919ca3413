"""A third-party displacement primitive, one module and one entry point
with no change to symsynth: `tests/plugins/symsynth-nudge` (its own
pyproject.toml) is installed with pip into a folder of its own, and
`solve` and `simulate` use it; its own tests, symsynth's conformance suite
in one line, pass."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from support.plugin_repos import PLUGINS, environment, install, run_own_tests

SCENE = PLUGINS / "symsynth-nudge" / "tests" / "nudge-small.yaml"


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    return install("symsynth-nudge", tmp_path_factory.mktemp("site"))


def symsynth(installed, tmp_path, *args):
    return subprocess.run([sys.executable, "-m", "symsynth.cli", *args], capture_output=True, text=True,
                          env=environment(installed, SYMSYNTH_CACHE=str(tmp_path / "cache")))


def test_without_the_plugin_the_scene_names_an_unknown_primitive(tmp_path):
    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(SCENE)], capture_output=True,
                          text=True, env=environment(tmp_path, SYMSYNTH_CACHE=str(tmp_path)))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "contacts.behind.primitive: unknown primitive 'nudge'" in done.stderr


def test_solve_and_simulate_use_the_installed_plugin(installed, tmp_path):
    solved = symsynth(installed, tmp_path, "solve", str(SCENE), "--json")
    assert solved.returncode == 0, solved.stderr
    play = [s["action"] for s in json.loads(solved.stdout)["principal_play"]]
    assert play == ["transit(box,behind)", "slide(box,behind,l3)"]  # sideways: the nudge
    run = symsynth(installed, tmp_path, "simulate", "--world", "kinematic", str(SCENE), "--human", "none", "--json")
    assert run.returncode == 0, run.stderr
    (result,) = json.loads(run.stdout)["runs"]
    assert result["completed"] and result["divergences"] == []
    assert result["trace"][-1]["state"]["at"] == {"box": "l3"}


def test_the_plugins_own_tests_pass(installed, tmp_path):
    """Its tests/test_conformance.py is the one line of docs/plugins.md."""
    done = run_own_tests("symsynth-nudge", installed, tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "2 passed" in done.stdout
