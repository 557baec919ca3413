"""A large `k` is solved with fewer human moves where that provably gives the
same game (symsynth/game/horizon.py), and refused with the reason where it
does not; compared with solving the game with all `k` moves directly."""

from __future__ import annotations

import pytest
import yaml

from symsynth.testing.gamegen import random_scene
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.game import horizon
from symsynth.game.horizon import least_units, solve_game
from symsynth.solvers import SOLVERS
from symsynth.logic import parse_ltlf
from symsynth.scene import load_scene
from support.games import make_scene, worst_case_of

#: b at l1; the robot wins once b has left l1.  Transit 4 + grab 5 = 9; a
#: human move of b (or of c, which is in nobody's way) cannot make it
#: dearer: moving b off l1 wins at once, and moving c changes nothing the
#: robot needs.  So E_p = 9 for every k, and the cheapest action (4) lets a
#: play use at most 9 // 4 = 2 human moves.
LEAVE = dict(objects={"b": "l1", "c": "l2"}, locations=["l1", "l2", "l3"],
             motions={("empty", s, "l1/top"): 4 for s in ("home", "l2/top", "l3/top")},
             task="F(!at(b, l1))")


def leave(k):
    return make_scene(LEAVE["objects"], LEAVE["locations"], LEAVE["motions"], k=k, task=LEAVE["task"])


@pytest.mark.parametrize("solver", sorted(SOLVERS))
def test_a_million_moves_are_solved_with_eight(solver):
    scene = leave(10**6)
    tried = []
    solution = solve_game(SOLVERS[solver], scene, tried=lambda h, s: tried.append(h))
    assert tried == [8]
    assert (solution.units, solution.k) == (9, 10**6)
    assert solution.stats["solved_with_k"] == 8 and solution.stats["moves_usable"] == 2
    assert SOLVERS[solver](leave(3)).units == 9  # solved directly, with few moves
    # The shifted strategy, followed through every behaviour of a human with
    # a million moves, never pays more than E_p.
    assert worst_case_of(scene, solution, parse_ltlf(scene.task)) == 9


def test_least_units():
    assert least_units(leave(0), 1.0) == 4
    assert least_units(leave(0), 3.0) == 2  # 4 and 5 round up to 2 units of 3
    one_sample = make_scene({"b": "l1"}, ["l1"], {("empty", "home", "l1/top"): 4}, else_samples=["e1"])
    assert least_units(one_sample, 1.0) == 0  # e1/top -> e1/top: a transit of cost 0


@pytest.mark.parametrize("seed", range(300, 316))
def test_random_scenes_agree_with_solving_all_moves(seed):
    """k = 40 through solve_game against the explicit solver with k = 40."""
    scene = random_scene(seed)
    ours = solve_game(SOLVERS["explicit"], scene, k=40)
    direct = SOLVERS["explicit"](scene, k=40)
    assert ours.units == direct.units and ours.k == 40


def test_random_scenes_take_the_short_cut():
    """The comparison above is not vacuous: some of its scenes are decided
    with fewer moves (an infinite value), some with all 40."""
    cut = [ "solved_with_k" in solve_game(SOLVERS["explicit"], random_scene(seed), k=40).stats
           for seed in range(300, 316)]
    assert 3 <= sum(cut) <= len(cut) - 3


def test_growing_value_is_refused_with_the_values(monkeypatch, capsys):
    """The toy's value grows by 27 units per human move (k = 8: 239,
    16: 455, 32: 887 -- 50 + 27 (k - 1) for k >= 1, its scene file works out
    k = 1), so no fewer moves give its game with k = 10^6; with the limit
    lowered to 32 layers, the command refuses and names the values seen."""
    monkeypatch.setattr(horizon, "MAX_LAYERS", 32)
    assert main(["solve", "scenes/toy.yaml", "--k", "1000000", "--solver", "explicit"]) == 2
    err = capsys.readouterr().err
    assert "E_p = 239 units with 8, E_p = 455 units with 16, E_p = 887 units with 32" in err
    assert "Traceback" not in err
    with pytest.raises(InputError, match="still grows"):
        solve_game(SOLVERS["symbolic"], load_scene("scenes/toy.yaml"), k=10**6)


def test_cli_reports_the_short_cut(tmp_path, capsys):
    scene = tmp_path / "leave.yaml"
    scene.write_text(yaml.safe_dump({
        "name": "leave", "objects": {o: {"at": at} for o, at in LEAVE["objects"].items()},
        "locations": LEAVE["locations"], "grasps": ["top"], "human": {"k": 10**6},
        "task": LEAVE["task"], "costmap": {"format": "symsynth.costmap/1", "motions": [
            {"mode": m, "from": s, "to": t, "rules": [{"free": [], "cost": c}]}
            for (m, s, t), c in LEAVE["motions"].items()]}}))
    assert main(["solve", str(scene)]) == 0
    out = capsys.readouterr().out
    assert "k = 1000000 moves" in out and "E_p        9\n" in out
    assert "solved with k = 8: against its strategy a play can use at most 2 human moves" in out
