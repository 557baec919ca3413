"""`symsynth solve` through `symsynth.cli.main`, on scene files in tmp_path.

The scenes are the hand-solved ones of test_strategy_file (values worked
out there): PICK has E_p = 21 with k = 0 and 34 with k = 1.  Every test
that solves runs once per registered solver.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

from symsynth.cli import main
from symsynth import problem as problem_module
from symsynth.solvers import SOLVERS
from symsynth.game.strategy import read_strategy
from symsynth.logic import parse_ltlf
from symsynth.scene import load_scene
from support.paper import SCENES
from support.games import PICK
from support.strategy_files import check_file, costmap_json, scene_data

SOLVER_NAMES = sorted(SOLVERS)

#: PICK without any motion into Else: b is out of reach once at Else.  With
#: k = 0 nothing changes (21); with k = 1 the human moves b to Else after
#: the transit (before the grab, after which b is in the hand) and the robot
#: has no action left: E_p is infinite.
NO_ELSE = {key: cost for key, cost in PICK.items() if "e1/top" not in key[2]}


def write_scene(tmp_path, *, k=0, motions=PICK, task="F(at(b, l2))", costmap=True):
    """pick.yaml with its costmap in pick.costmap.json (semantics §7)."""
    data = scene_data({"b": "l1"}, ["l1", "l2"], else_samples=["e1"], k=k, task=task)
    if task is None:
        del data["task"]
    if costmap:
        (tmp_path / "pick.costmap.json").write_text(json.dumps(costmap_json(motions)))
        data["costmap"] = "pick.costmap.json"
    path = tmp_path / "pick.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def write_costmap(tmp_path, motions, name="other.json"):
    path = tmp_path / name
    path.write_text(json.dumps(costmap_json(motions)))
    return path


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def solve(capsys, solver, *argv):
    code, out, err = run(capsys, "solve", "--solver", solver, *argv)
    assert (code, err) == (0, ""), err
    return out


def play_lines(out):
    """Numbered steps: (who, action, cost or None, running total or None)."""
    steps = []
    for m in re.finditer(r"^\s*\d+\.\s+(robot|human)\s+(\S+)\s+(?:\+(\S+) = (\S+))?", out, re.M):
        who, action, cost, total = m.groups()
        steps.append((who, action, cost and float(cost), total and float(total)))
    return steps


def value_line(out):
    return re.search(r"^E_p\s+(.*)$", out, re.M).group(1)


# -- solving -------------------------------------------------------------------

@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_principal_play_with_costs_and_running_total(capsys, tmp_path, solver):
    out = solve(capsys, solver, write_scene(tmp_path), "--budget", "21")
    assert "realizable within budget 21" in out and "not realizable" not in out
    assert value_line(out) == "21"
    assert re.search(r"^scene\s+pick\b", out, re.M) and re.search(r"^task\s+F\(at\(b, l2\)\)", out, re.M)
    assert re.search(rf"^solver\s+{solver}$" if solver != "auto" else r"^solver\s+auto: compiled, as ", out, re.M)
    assert re.search(r"^human\s+k = 0\b", out, re.M)
    assert play_lines(out) == [("robot", "transit(b,top)", 7, 7), ("robot", "grab(b)", 5, 12),
                               ("robot", "transfer(l2)", 4, 16), ("robot", "drop(b,l2)", 5, 21)]
    assert "at: b=l2 | grip=none | ee=(b,top)" in out.splitlines()[-2]  # after the drop
    assert re.search(r"total cost 21\b", out)


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_human_moves_are_marked_in_the_play(capsys, tmp_path, solver):
    out = solve(capsys, solver, write_scene(tmp_path), "--k", "1")
    assert value_line(out) == "34" and re.search(r"^human\s+k = 1 move\b", out, re.M)
    assert "no --budget" in out
    assert play_lines(out) == [
        ("robot", "transit(b,top)", 7, 7), ("human", "move(b,Else)", None, None),
        ("robot", "transit(b,top)", 8, 15), ("robot", "grab(b)", 5, 20),
        ("robot", "transfer(l2)", 9, 29), ("robot", "drop(b,l2)", 5, 34)]
    assert re.search(r"human\s+move\(b,Else\)\s+at: b=Else \| grip=none \| ee=Else", out)


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_json_has_the_spec_fields(capsys, tmp_path, solver):
    out = solve(capsys, solver, write_scene(tmp_path), "--json", "--budget", "30")
    data = json.loads(out)
    assert {"realizable", "cost_bound", "budget", "k", "states", "seconds",
            "scene", "task", "solver"} <= set(data)
    assert (data["realizable"], data["cost_bound"], data["budget"], data["k"]) == (True, 21, 30, 0)
    assert (data["scene"], data["task"], data["solver"]) == ("pick", "F(at(b, l2))", solver)
    assert data["states"] > 0 and isinstance(data["seconds"], dict)
    high_water = next(int(line.split()[1]) for line in Path("/proc/self/status").read_text().splitlines()
                      if line.startswith("VmHWM:")) / 1024  # this process's peak, read by the kernel's own count
    assert 20 < data["peak_mb"] <= high_water + 1
    assert [s["action"] for s in data["principal_play"]] == [
        "transit(b,top)", "grab(b)", "transfer(l2)", "drop(b,l2)"]
    assert [s["cost"] for s in data["principal_play"]] == [7, 5, 4, 5]
    assert data["principal_play"][-1]["state"] == {"at": {"b": "l2"}, "grip": None, "ee": ["b", "top"]}
    assert (data["units"], data["resolution"], data["counter_play"]) == (21, 1.0, None)
    out = solve(capsys, solver, write_scene(tmp_path), "--json")
    assert json.loads(out)["realizable"] is None
    over = json.loads(solve(capsys, solver, write_scene(tmp_path), "--json", "--budget", "20"))
    assert over["realizable"] is False and over["counter_play"] == over["principal_play"]


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_budget_below_the_value_is_not_realizable(capsys, tmp_path, solver):
    out = solve(capsys, solver, write_scene(tmp_path), "--budget", "20")
    assert "not realizable within budget 20" in out
    assert value_line(out) == "21" and len(play_lines(out)) == 4
    data = json.loads(solve(capsys, solver, write_scene(tmp_path), "--budget", "20", "--json"))
    assert (data["realizable"], data["cost_bound"]) == (False, 21)


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_no_winning_strategy_shows_the_counter_play(capsys, tmp_path, solver):
    scene = write_scene(tmp_path, k=1, motions=NO_ELSE)
    out = solve(capsys, solver, scene, "--budget", "100")
    assert "no winning strategy" in out and value_line(out) == "infinite"
    steps = play_lines(out)
    assert ("human", "move(b,Else)", None, None) in steps
    assert "at: b=Else | grip=none | ee=Else" in out  # where the robot is left
    assert "no action available" in out
    # every motion into Else is missing; the message names some of them
    assert re.search(r"transit\(b,top\): the costmap has no motion for mode empty from .*-> e1/top", out)
    data = json.loads(solve(capsys, solver, scene, "--budget", "100", "--json"))
    assert (data["realizable"], data["cost_bound"]) == (False, None)
    assert {"who": "human", "action": "move(b,Else)"}.items() <= data["counter_play"][-1].items()
    assert value_line(solve(capsys, solver, scene, "--k", "0")) == "21"


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_robot_without_any_motion_is_stuck_at_the_start(capsys, tmp_path, solver):
    out = solve(capsys, solver, write_scene(tmp_path, motions={}))
    assert "no winning strategy" in out and play_lines(out) == []
    assert "at: b=l1 | grip=none | ee=Else" in out and "no action available" in out
    # ee = Else: the robot may stand at any anchor; l1/top -> l1/top costs nothing
    assert ("transit(b,top): the costmap has no motion for mode empty from "
            "home -> l1/top, l2/top -> l1/top, e1/top -> l1/top\n") in out


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_robot_holding_in_else_without_transfers_is_stuck(capsys, tmp_path, solver):
    """b at Else, motions only into e1/top: the robot can fetch b (transit,
    grab) but then holds it at Else with no transfer and nothing to drop on."""
    data = scene_data({"b": "Else"}, ["l1", "l2"], else_samples=["e1"], task="F(at(b, l1))")
    motions = {("empty", s, "e1/top"): 2 for s in ("home", "l1/top", "l2/top")}
    (tmp_path / "c.json").write_text(json.dumps(costmap_json(motions)))
    data["costmap"] = "c.json"
    path = tmp_path / "stuck.yaml"
    path.write_text(yaml.safe_dump(data))
    out = solve(capsys, solver, path)
    assert [step[1] for step in play_lines(out)] == ["transit(b,top)", "grab(b)"]
    assert "drop(b,...): b is held but not aligned with a location" in out
    assert "transfer(l1): the costmap has no motion for mode b/top from e1/top -> l1/top" in out


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_overrides(capsys, tmp_path, solver):
    """--task F(holding(b)): transit 7 + grab 5 = 12.  --costmap with
    home -> l1/top at 3: transit max(3, l2/top 3, e1/top 2) = 3, so 17.
    --resolution 2: 4 + 3 + 2 + 3 = 12 units of 2 = 24."""
    scene = write_scene(tmp_path)
    assert value_line(solve(capsys, solver, scene, "--task", "F(holding(b))")) == "12"
    data = json.loads(solve(capsys, solver, scene, "--task", "F(holding(b))", "--json"))
    assert (data["task"], data["cost_bound"]) == ("F(holding(b))", 12)
    cheaper = write_costmap(tmp_path, PICK | {("empty", "home", "l1/top"): 3})
    assert value_line(solve(capsys, solver, scene, "--costmap", cheaper)) == "17"
    assert value_line(solve(capsys, solver, scene, "--resolution", "2")).startswith(
        "24 (12 units of resolution 2")
    (tmp_path / "bare").mkdir()
    bare = write_scene(tmp_path / "bare", costmap=False)
    pick_costmap = write_costmap(tmp_path, PICK, "pick-saved.json")
    assert value_line(solve(capsys, solver, bare, "--costmap", pick_costmap)) == "21"


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_strategy_file_is_written_and_wins(capsys, tmp_path, solver):
    scene_path = write_scene(tmp_path, k=1)
    target = tmp_path / "out" / "strategy.json"
    target.parent.mkdir()
    out = solve(capsys, solver, scene_path, "-o", target)
    file = read_strategy(target)
    assert f"wrote {target} ({len(file.positions)} positions)" in out
    scene = load_scene(scene_path)
    solution = SOLVERS[solver](scene)
    check_file(scene, parse_ltlf(scene.task), solution, file)
    assert file.cost_bound == 34
    data = json.loads(solve(capsys, solver, scene_path, "-o", target, "--json"))
    assert data["strategy"] == {"file": str(target), "positions": len(file.positions)}


def test_help_explains_the_game_and_lists_every_solver(capsys):
    code, out, _ = run(capsys, "solve", "--help")
    assert code == 0
    text = " ".join(out.split())
    for phrase in ("human moves first", "at most k times", "E_p is the min over robot strategies",
                   "realizable within budget E iff E_p <= E", "principal play", "counter play",
                   "symsynth.strategy/1", "Exit status: 0 when the game is solved"):
        assert phrase in text, phrase
    for name in SOLVERS:
        assert name in out


# -- bad input: one message, exit code 2 -------------------------------------------------

def _bad_costmap(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{"format": "symsynth.costmap/1", "motions": [')
    return path


def _foreign_costmap(tmp_path):
    return write_costmap(tmp_path, {("empty", "home", "x9/top"): 1}, "foreign.json")


@pytest.mark.parametrize("argv, expected", [
    (lambda d, s: [d / "nowhere.yaml"], "nowhere.yaml"),
    (lambda d, s: [s, "--task", "F(at(b, l2)"], r"--task:1:12: syntax error"),
    (lambda d, s: [s, "--task", "F(at(zz, l2))"], r"--task: .*unknown object or tag 'zz'"),
    (lambda d, s: [s, "--costmap", d / "missing.json"], r"cannot read costmap .*missing\.json"),
    (lambda d, s: [s, "--costmap", _bad_costmap(d)], r"bad\.json:1:\d+: not JSON"),
    (lambda d, s: [s, "--costmap", _foreign_costmap(d)], r"foreign\.json: costmap: motion empty home -> x9/top: unknown anchor 'x9/top'"),
    (lambda d, s: [s, "-o", d / "no" / "such" / "dir.json"], r"cannot write strategy file .*dir\.json"),
    (lambda d, s: [write_scene(d, task=None)], r"has no task: give --task"),
    (lambda d, s: [s, "--solver", "explicit", "--time-limit", "5"], r"the explicit solver does not stop at a time limit"),
])
def test_bad_input_is_one_message(capsys, tmp_path, argv, expected):
    code, out, err = run(capsys, "solve", *argv(tmp_path, write_scene(tmp_path)))
    assert code == 2 and out == ""
    assert err.startswith("symsynth solve: ") and re.search(expected, err), err
    assert err.count("symsynth solve:") == 1 and "Traceback" not in err


def test_unwritable_output_is_refused_before_solving(capsys, tmp_path, monkeypatch):
    def no_solve(*args, **kwargs):
        raise AssertionError("solved although the strategy file cannot be written")

    monkeypatch.setattr(problem_module, "SOLVERS", dict(SOLVERS, symbolic=no_solve))
    scene = write_scene(tmp_path)
    code, out, err = run(capsys, "solve", scene, "-o", tmp_path)
    assert code == 2 and "it is a directory" in err
    code, out, err = run(capsys, "solve", scene, "-o", tmp_path / "no" / "x.json")
    assert code == 2 and "is not a writable directory" in err


def test_costmap_option_replaces_the_scenes_and_is_checked_like_it(capsys, tmp_path):
    """--costmap is loaded instead of the scene's own costmap (which need not
    exist), and a name in the wrong place (a location as a mode, a mode as an
    anchor) is an error as it would be in the scene."""
    scene = write_scene(tmp_path)
    (tmp_path / "pick.costmap.json").unlink()
    out = solve(capsys, "explicit", scene, "--costmap", write_costmap(tmp_path, PICK))
    assert value_line(out) == "21"
    wrong = write_costmap(tmp_path, {("l1/top", "home", "l1/top"): 1, ("empty", "empty", "l1/top"): 1},
                          "wrong.json")
    code, out, err = run(capsys, "solve", scene, "--costmap", wrong)
    assert code == 2 and "unknown mode 'l1/top'" in err and "unknown anchor 'empty'" in err


@pytest.mark.parametrize("option, value, expected", [
    ("--k", "-1", "must be >= 0"),
    ("--k", "two", "expected a whole number"),
    ("--budget", "-3", "must be >= 0"),
    ("--budget", "inf", "expected a finite number"),
    ("--resolution", "0", "must be > 0"),
    ("--solver", "no-such-solver", "invalid choice"),
])
def test_bad_options_are_usage_errors(capsys, tmp_path, option, value, expected):
    code, out, err = run(capsys, "solve", write_scene(tmp_path), option, value)
    assert code == 2 and out == ""
    assert "usage:" in err and option in err and expected in err
    assert "Traceback" not in err


@pytest.mark.parametrize("name, reason", [("Else", "a reserved place"), ("Hand", "a reserved place"),
                                          ("l2", "a location"), ("e1", "an Else sample")])
def test_objects_named_like_a_place_are_refused(tmp_path, capsys, name, reason):
    """`at(Else, l2)` would name an object as much as a place: the scene is
    refused up front, at the object's key and line (it was solved)."""
    text = (SCENES / "toy.yaml").read_text().replace("  w: {", f"  {name}: {{")
    (tmp_path / "toy.yaml").write_text(text)
    costmap = (SCENES / "toy.costmap.json").read_text().replace('"w/top"', f'"{name}/top"')
    (tmp_path / "toy.costmap.json").write_text(costmap)
    assert main(["solve", str(tmp_path / "toy.yaml")]) == 2
    err = capsys.readouterr().err
    line = text.splitlines().index(next(l for l in text.splitlines() if l.startswith(f"  {name}:"))) + 1
    assert f"toy.yaml:{line}: objects.{name}: '{name}' is {reason} and cannot name an object" in err


@pytest.mark.parametrize("argv", [["dfa", "-a"], ["solve", str(SCENES / "toy.yaml"), "--task", "-F(at(b,l3))"]])
def test_a_formula_that_starts_with_a_dash_gets_a_hint(capsys, argv):
    assert main(argv) == 2
    assert f"the argument {argv[-1]!r} starts with '-' and is read as an option" in capsys.readouterr().err


def test_time_limit_answers_with_the_exact_value_when_it_is_proven_in_time(capsys, tmp_path):
    out = solve(capsys, "auto", write_scene(tmp_path), "--k", "1", "--time-limit", "60")
    assert value_line(out) == "34"
    assert re.search(r"^solver\s+auto: compiled, as a time limit of 60 s, well above", out, re.M)


def test_the_output_says_what_e_p_is_and_its_unit(capsys):
    """`solve`'s report printed E_p with no word on what it is (only --help had one)."""
    assert main(["solve", str(SCENES / "toy.yaml")]) == 0
    lines = capsys.readouterr().out.splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith("E_p "))
    assert lines[at].split() == ["E_p", "50"]
    assert "least total cost the robot can guarantee against every human with at most 1 move" in lines[at + 1]
    assert "units of the scene's costmap" in lines[at + 1]


def test_a_costmap_computed_in_parallel_reports_wall_time_first():
    """"computed in 17.0 s" was the phases' seconds summed over the worker
    processes, longer than the user waited: the wall time now, the sum
    after it, named as such."""
    from symsynth.cli.solve import elapsed
    from symsynth.planning.build import Stats

    stats = Stats(seconds={"anchors": 1.0, "roadmaps": 25.0, "edge checks": 10.0, "searches": 0.1, "slides": 0.0},
                  workers=2, wall=17.04)
    assert elapsed(stats) == "17.0 s (36.1 s of work on 2 processes)"
    assert elapsed(Stats(seconds={"anchors": 3.0}, workers=1, wall=3.2)) == "3.2 s"
