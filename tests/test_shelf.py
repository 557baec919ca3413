"""scenes/shelf.yaml end to end: a block under a low shelf board, where the
top grasp's anchor is absent (semantics §5's choice), pulled out by the
built-in `pull`, then carried to its goal.  The costmap is built once (about
25 s) into a cache of this module's own."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from symsynth.cli import main
from symsynth.game.solution import task_formula
from symsynth.planning.build import obtain_costmap
from symsynth.scene import load_scene
from symsynth.solvers import SOLVERS

SHELF = Path(__file__).resolve().parents[1] / "scenes" / "shelf.yaml"


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    with pytest.MonkeyPatch.context() as patch:
        folder = tmp_path_factory.mktemp("shelf-cache")
        patch.setenv("SYMSYNTH_CACHE", str(folder))
        yield folder


def run(capsys, *args):
    assert main(list(args)) == 0
    return json.loads(capsys.readouterr().out)


def test_the_block_is_pulled_out_before_it_is_grasped(cache, capsys):
    """k = 1 (the scene's): the principal play pulls, grasps at `out`, and
    after the human puts the block back under the board, pulls again."""
    solved = run(capsys, "solve", str(SHELF), "--json")
    assert solved["cost_bound"] is not None
    actions = [s["action"] for s in solved["principal_play"]]
    assert actions[:3] == ["transit(b,far)", "slide(b,far,out)", "transit(b,top)"]
    assert actions[-3:] == ["grab(b)", "transfer(goal)", "drop(b,goal)"]
    assert run(capsys, "solve", str(SHELF), "--k", "0", "--json")["cost_bound"] < solved["cost_bound"]


def test_unrealizable_without_the_contact(cache, capsys):
    """The top grasp has no anchor under the board (the costmap says so), so
    without the pull no action reaches the block, with or without a human."""
    assert run(capsys, "costmap", str(SHELF), "--json")["absent"] == ["under/top"]
    scene = load_scene(SHELF)
    costmap = obtain_costmap(scene, "recursive", None, progress=False).costmap
    assert costmap.absent == {"under/top"} and costmap.slide_rules("far", "under", "out")
    scene = dataclasses.replace(scene, costmap=costmap)
    for k in (0, 1):
        assert SOLVERS["explicit"](scene, task_formula(scene, None), k=k).cost_bound is not None
        bare = scene.without_contacts()
        assert SOLVERS["explicit"](bare, task_formula(bare, None), k=k).cost_bound is None


@pytest.mark.parametrize("human", ["adversarial", "random"])
def test_simulated_to_completion(cache, capsys, human):
    """Every run completes within E_p with no divergence; against the
    adversarial human the robot pulls twice, and the transit after each slide
    follows an evidence path from the slide's end anchor `out/far`."""
    extra = ["--runs", "4", "--seed", "1"] if human == "random" else []
    out = run(capsys, "simulate", "--world", "kinematic", str(SHELF), "--human", human, "--json", *extra)
    for record in out["runs"]:
        assert record["completed"] and record["within_bound"] and record["divergences"] == [], record
    if human == "adversarial":
        trace = out["runs"][0]["trace"]
        actions = [s["action"] for s in trace if s["who"] == "robot"]
        assert actions.count("slide(b,far,out)") == 2
        after_slides = [trace[i + 1] for i, s in enumerate(trace) if s["action"] == "slide(b,far,out)"]
        assert all(s["action"] == "transit(b,top)" and s["source"] == "evidence" for s in after_slides)
