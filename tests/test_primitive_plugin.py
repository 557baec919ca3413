"""A third-party displacement primitive, one module and one entry point
with no change to symsynth: `tests/plugins/symsynth-nudge` (its own
pyproject.toml) is installed with pip into a folder of its own, and
`solve` and `simulate` use it; it passes the conformance suite."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from support.primitive_conformance import check_displacement

HERE = Path(__file__).parent
PLUGIN = HERE / "plugins" / "symsynth-nudge"
SCENE = HERE / "data" / "nudge-small.yaml"


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The plugin, installed as a user would (pip; its build backend comes
    from the package index or pip's cache), into a folder put on the path."""
    target = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                           str(PLUGIN)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return target


def symsynth(installed, tmp_path, *args):
    env = dict(os.environ, PYTHONPATH=str(installed), SYMSYNTH_CACHE=str(tmp_path / "cache"))
    return subprocess.run([sys.executable, "-m", "symsynth.cli", *args], capture_output=True, text=True, env=env)


def test_without_the_plugin_the_scene_names_an_unknown_primitive(tmp_path):
    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(SCENE)], capture_output=True,
                          text=True, env=dict(os.environ, SYMSYNTH_CACHE=str(tmp_path)))
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "contacts.behind.primitive: unknown primitive 'nudge'" in done.stderr


def test_solve_and_simulate_use_the_installed_plugin(installed, tmp_path):
    solved = symsynth(installed, tmp_path, "solve", str(SCENE), "--json")
    assert solved.returncode == 0, solved.stderr
    play = [s["action"] for s in json.loads(solved.stdout)["principal_play"]]
    assert play == ["transit(box,behind)", "slide(box,behind,l3)"]  # sideways: the nudge
    run = symsynth(installed, tmp_path, "simulate", str(SCENE), "--human", "none", "--json")
    assert run.returncode == 0, run.stderr
    (result,) = json.loads(run.stdout)["runs"]
    assert result["completed"] and result["divergences"] == []
    assert result["trace"][-1]["state"]["at"] == {"box": "l3"}


def test_the_plugin_conforms(installed, monkeypatch):
    monkeypatch.syspath_prepend(str(installed))
    from symsynth.planning.registry import planner_class
    from symsynth.primitive_registry import displacement
    from symsynth.scene import load_scene

    scene = load_scene(SCENE)
    slides = check_displacement(displacement("nudge"), scene, planner_class("ompl-fcl")(scene), "behind")
    assert {(r.start, r.goal) for r in slides} == {("l1", "l3")}
