"""The benchmark's scene family `bench/gamefamily.py` (put n blocks into a pattern).

Scenes validate, are deterministic in the seed, have every motion the game
can ask for, carry conditional rules, and the pattern is achievable: the
explicit solver finds a finite E_p, equal to hand-derived values on tiny
instances.
"""

from __future__ import annotations


import pytest


from bench.gamefamily import pattern_data, pattern_scene
from symsynth.game.abstraction import initial_state, robot_moves  # noqa: E402
from symsynth.solvers.explicit import solve_explicit  # noqa: E402
from symsynth.scene.costmap import Rule  # noqa: E402
from symsynth.scene.model import ELSE  # noqa: E402

SIZES = [(1, 2), (2, 3), (2, 4), (3, 4), (3, 5), (4, 6), (5, 7), (6, 8), (7, 10), (8, 12)]


@pytest.mark.parametrize("n,m", SIZES)
def test_scenes_validate_and_have_the_intended_shape(n, m):
    scene = pattern_scene(n, m, k=3, seed=0)
    assert len(scene.objects) == n and len(scene.locations) == m
    assert scene.else_samples == ("e1", "e2") and scene.grasps == ("top",) and scene.k == 3
    assert all("block" in o.tags for o in scene.objects)
    at = [o.at for o in scene.objects]
    if n >= 2:
        assert ELSE in at and any(a != ELSE for a in at)
    placed = [a for a in at if a != ELSE]
    assert len(placed) == len(set(placed))
    # one F of a conjunction of n distinct targets, none holding at the start
    data = pattern_data(n, m, k=3, seed=0)
    assert data["task"].startswith("F(") and data["task"].count("at(") == n
    targets = [part.split(", ")[1].rstrip(")") for part in data["task"][2:-1].split(" & ")]
    assert len(set(targets)) == n and set(targets) <= set(scene.locations)
    assert all(o.at != t for o, t in zip(scene.objects, targets))


def test_deterministic_in_the_seed():
    assert pattern_data(4, 6, seed=3) == pattern_data(4, 6, seed=3)
    assert pattern_data(4, 6, seed=3) != pattern_data(4, 6, seed=4)


def test_m_must_leave_a_free_location():
    with pytest.raises(ValueError, match="m must be >= n \\+ 1"):
        pattern_data(3, 3)


@pytest.mark.parametrize("grasps", [("top",), ("top", "side")])
def test_costmap_has_every_motion_the_game_asks_for(grasps):
    """Spec §5: mode empty from every anchor to every x/g; mode o/g from
    every x/g to every l/g.  Costs are integers >= 1, and there are
    conditional rules, each cheaper than its pair's unconditional one."""
    scene = pattern_scene(3, 6, seed=1, grasps=grasps)
    places = scene.locations + scene.else_samples
    anchors = scene.anchors
    wanted = {("empty", s, f"{x}/{g}") for x in places for g in grasps for s in anchors}
    wanted |= {(f"{o}/{g}", f"{x}/{g}", f"{l}/{g}") for o in scene.object_names for g in grasps
               for x in places for l in scene.locations}
    wanted = {key for key in wanted if key[1] != key[2]}
    motions = scene.costmap.motions
    assert set(motions) == wanted
    conditional = 0
    for rules in motions.values():
        assert all(r.cost >= 1 and r.cost == int(r.cost) for r in rules)
        plain = [r.cost for r in rules if not r.free]
        assert len(plain) == 1
        for r in rules:
            if r.free:
                conditional += 1
                assert r.cost < plain[0] and r.free <= set(places)
    assert conditional > 0


def test_conditional_rule_in_a_row():
    """Three locations in a row, l1 (0,0), l2 (1,0), l3 (2,0): l1 -> l3 passes
    over l2, so it costs 20 when l2 is free and 20 + 6 otherwise."""
    scene = pattern_scene(1, 3, k=0)
    rules = scene.costmap.rules("o1/top", "l1/top", "l3/top")
    assert sorted((sorted(r.free), r.cost) for r in rules) == [([], 26.0), (["l2"], 20.0)]


def test_hand_solved_single_block():
    """n = 1, m = 3, k = 0; red block o1 at l1, pattern F(at(red, l3)).

    Layout: l1 (0,0), l2 (1,0), l3 (2,0); e1 (-1,-1), e2 (3,-1); home (1,-1.5).
    The robot starts with ee = Else, so transit(o1,top) costs the largest
    motion from any anchor to l1/top: home 18 (d = 1.80), l2 10, l3 20 (over
    l2, which is free), e1 14 (d = 1.41), e2 32 (d = 3.16; l2 and l3 are
    0.32 and 0.63 off the segment, so not in between) -> 32.  Grab 5;
    transfer(l3) from l1/top with l2 free 20 (via l2 also 10 + 10 = 20);
    drop 5.  E_p = 32 + 5 + 20 + 5 = 62."""
    scene = pattern_scene(1, 3, k=0, initial={"o1": "l1"}, target={"o1": "l3"})
    assert scene.task == "F(at(red, l3))"
    solution = solve_explicit(scene)
    assert solution.cost_bound == 62.0


def test_hand_solved_blocked_row():
    """As above with a green block o2 standing at l2 (its own target:
    F(at(red, l3) & at(green, l2))).  Now l2 is not free for a motion serving
    o1: transit's l3 -> l1 costs 26, still below e2's 32; transfer(l3)
    costs 26 (around l2), and nowhere else is free to go through.  Moving
    o2 out of the way first would cost more than the 6 saved (its transit
    alone is 22).  E_p = 32 + 5 + 26 + 5 = 68."""
    scene = pattern_scene(2, 3, k=0, initial={"o1": "l1", "o2": "l2"},
                          target={"o1": "l3", "o2": "l2"})
    v0 = initial_state(scene)
    costs = dict((a, c) for a, _, c in robot_moves(scene, v0))
    assert costs["transit(o1,top)"] == 32.0
    solution = solve_explicit(scene)
    assert solution.cost_bound == 68.0
    assert [(s.action, s.cost) for s in solution.principal_play] == [
        ("transit(o1,top)", 32.0), ("grab(o1)", 5.0), ("transfer(l3)", 26.0), ("drop(o1,l3)", 5.0)]


@pytest.mark.parametrize("n,m", [(1, 2), (2, 3), (2, 4), (3, 4)])
def test_pattern_is_achievable_against_the_human(n, m):
    """Finite E_p for every k, not decreasing in k (more human moves cannot help the robot)."""
    values = [solve_explicit(pattern_scene(n, m, k=k)).cost_bound for k in range(3)]
    assert all(v is not None and v > 0 for v in values)
    assert values == sorted(values)


def test_costs_are_rounded_distances_with_a_detour_per_place_crossed():
    """e1 at (-1, -1) to l1 at (0, 0): 10 * sqrt(2) = 14.14, rounded to 14.
    l1 to l4 in a row of four passes over l2 and l3: base 30, around 30 + 2 * 6."""
    scene = pattern_scene(1, 3, k=0)
    assert scene.costmap.rules("empty", "e1/top", "l1/top") == (Rule(frozenset(), 14.0),)
    rules = pattern_scene(1, 4, k=0).costmap.rules("o1/top", "l1/top", "l4/top")
    assert sorted((sorted(r.free), r.cost) for r in rules) == [([], 42.0), (["l2", "l3"], 30.0)]
