"""The forward solver (`symsynth.solvers.forward`): the same E_p as the explicit
solver, a strategy that never pays more than E_p against any human, and a
lower bound that never exceeds the value it guides the search to.

Every expected value comes from the explicit solver (or, for the bound, from
the explicit solver's value of every reachable position), never from the
forward solver itself.  The hand-solved scenes of test_game_solvers.py run
on the forward solver too (it is registered in SOLVERS).
"""

from __future__ import annotations

import sys

import pytest

from symsynth.testing.gamegen import random_scene
from symsynth.game.abstraction import initial_state
from symsynth.game.graph import GameGraph, Node
from symsynth.solvers.explicit import _dijkstra, solve_explicit
from symsynth.solvers.bound import LowerBound
from symsynth.solvers.forward import solve_forward
from symsynth.solvers import SOLVERS
from symsynth.game.strategy import reachable_positions, worst_units
from symsynth.logic import parse_ltlf

from bench.gamefamily import pattern_scene
from support.games import bound_holds_everywhere, make_scene, worst_case_of


def test_registered():
    assert SOLVERS["forward"] is solve_forward


def _same(scene, k, **kw):
    """Both solvers on one game; the forward one's answer, checked."""
    expected = solve_explicit(scene, k=k, **kw)
    found = solve_forward(scene, k=k, **kw)
    assert (found.units, found.cost_bound) == (expected.units, expected.cost_bound), (scene.name, k)
    assert found.realizable == expected.realizable
    return expected, found


# -- values against the explicit solver -----------------------------------------------

@pytest.mark.parametrize("chunk", range(6))
def test_random_scenes_match_explicit(chunk):
    """120 generated scenes x k = 0..3: realizable and not, zero-cost
    actions (gamegen draws costs from 0), several grasps, every task
    pattern of gamegen (so the bound is on for some and 0 for others).
    Where E_p is finite the strategy is followed through every human
    behaviour and never pays more than E_p; where it is infinite the
    counter play, walked on the forward search's memo, is the one the
    explicit solver walks on its Dijkstra."""
    kinds = {"finite": 0, "infinite": 0}
    for seed in range(1000 + 20 * chunk, 1000 + 20 * (chunk + 1)):
        scene = random_scene(seed)
        formula = parse_ltlf(scene.task)
        for k in range(4):
            expected, found = _same(scene, k)
            if found.units is None:
                kinds["infinite"] += 1
                assert found.counter_play == expected.counter_play
                assert found.principal_play == () and dict(found.strategy) == {}
            else:
                kinds["finite"] += 1
                assert worst_case_of(scene, found, formula) == found.units
                robot_cost = sum(s.cost for s in found.principal_play if s.who == "robot")
                assert robot_cost == pytest.approx(found.cost_bound)
    # the chunk exercised both kinds of answer (else it tests less than it says)
    assert kinds["finite"] and kinds["infinite"], kinds


@pytest.mark.parametrize("n,m", [(1, 2), (2, 3), (2, 4), (3, 4)])
def test_pattern_family_matches_explicit(n, m):
    """The benchmark's family, where the bound (with its human term) is on."""
    scene = pattern_scene(n, m, k=3)
    formula = parse_ltlf(scene.task)
    for k in range(4):
        _, found = _same(scene, k)
        assert found.units is not None
        assert worst_case_of(scene, found, formula) == found.units
    # found is k = 3's: its principal play costs E_p
    assert sum(s.cost for s in found.principal_play) == found.cost_bound


def test_family_with_two_grasps_and_a_blocked_start():
    """Two grasps (the bound's grasp changes), an object standing on another's
    target (it must be moved away first)."""
    scene = pattern_scene(3, 4, k=2, grasps=("top", "side"),
                          initial={"o1": "l2", "o2": "Else", "o3": "l4"},
                          target={"o1": "l1", "o2": "l2", "o3": "l3"})
    for k in (0, 1, 2):
        _same(scene, k)


def test_resolution_and_budget():
    scene = pattern_scene(2, 3, k=2)
    for r in (0.5, 3.0, 7.0):
        _same(scene, 2, resolution=r)
    expected = solve_explicit(scene)
    for budget in (expected.cost_bound - 1, expected.cost_bound):
        _same(scene, 2, budget=budget)  # realizable compared there
    # over budget, the counter play is a play of the strategy that costs too much
    found = solve_forward(scene, budget=expected.cost_bound - 1)
    assert found.realizable is False
    assert sum(s.cost for s in found.counter_play if s.who == "robot") == expected.cost_bound


# -- special answers ------------------------------------------------------------------

def test_initial_state_accepts():
    """The first letter is accepted: E_p = 0 before anyone moves, whatever k."""
    scene = pattern_scene(2, 3, k=3, initial={"o1": "l1", "o2": "l2"},
                          target={"o1": "l1", "o2": "l2"})
    for k in (0, 3):
        expected, found = _same(scene, k, budget=0)
        assert (found.units, found.realizable, found.principal_play) == (0, True, ())
        assert found.counter_play is None and reachable_positions(scene, scene.task, found) == {}


def test_infinite_by_circling_uses_the_qualitative_check():
    """b at l1 must reach l2; the only transfer into l2 needs l3 free; c
    (at Else) has no transfer at all, so wherever it is put it stays.
    k = 0: transit 2 + grab 5 + transfer 3 + drop 5 = 15.  k = 1: the human
    puts c on l3 (or l2) for good; the robot can still transit, grab and
    drop forever (b can come back from Else and l3 too), so nothing is a dead end
    and the bound keeps growing: only the qualitative check on what the
    search generated shows the trap."""
    anchors = ("home", "l1/top", "l2/top", "l3/top", "e1/top")
    motions = {("empty", s, t): 2 for s in anchors for t in anchors[1:] if s != t}
    motions[("b/top", "l1/top", "l2/top")] = [(["l3"], 3)]
    motions[("b/top", "l2/top", "l1/top")] = 3
    motions[("b/top", "e1/top", "l1/top")] = 3
    motions[("b/top", "l3/top", "l1/top")] = 3
    scene = make_scene({"b": "l1", "c": "Else"}, ["l1", "l2", "l3"], motions, k=1,
                       else_samples=["e1"], task="F(at(b, l2))")
    _, found = _same(scene, 0)
    assert found.units == 15
    expected, found = _same(scene, 1)
    assert found.units is None and found.stats["qualitative"] >= 1
    assert found.counter_play == expected.counter_play


def test_counter_play_does_not_explore_the_game():
    """No object carries both red and green, so the bound is inf at the
    start: the counter play (the explicit solver's, a transit, a grab and
    a drop that comes back to a visited position) is walked on the
    positions it visits, not on the whole reachable game."""
    scene = pattern_scene(3, 4, k=3)
    expected = solve_explicit(scene, "F(at(red, l1) & at(green, l1))")
    found = solve_forward(scene, "F(at(red, l1) & at(green, l1))")
    assert found.units is expected.units is None
    assert found.counter_play == expected.counter_play
    assert [s.who for s in found.counter_play] == ["robot"] * 3
    assert found.states < expected.states / 10


def test_no_action_at_all_is_infinite_without_exploring():
    scene = make_scene({"b": "l1"}, ["l1", "l2"], {}, k=2, task="F(at(b, l2))")
    expected, found = _same(scene, 2)
    assert found.units is None and found.counter_play == expected.counter_play == ()


# -- the strategy --------------------------------------------------------------------

def test_strategy_file_positions_are_bounded_by_e_p():
    """What `solve -o` writes: every position the strategy reaches has an
    action, and the worst cost from the start is E_p."""
    scene = pattern_scene(3, 4, k=2)
    found = solve_forward(scene)
    choices = reachable_positions(scene, scene.task, found)
    worst = worst_units(choices)
    assert choices and all(w is not None for w in worst.values())
    v0 = initial_state(scene)
    game = GameGraph(scene, parse_ltlf(scene.task), 1.0)
    q0 = game.read(game.dfa.initial, v0)
    start = (v0, q0, found.k)
    assert worst[start] <= found.units
    # the human's best reply from the start: max over pass and moves
    replies = [(n.v, n.q, n.h) for _, n, _, _ in game.moves(Node(v0, q0, found.k, False)) if n]
    assert max(worst[p] for p in replies) == found.units


def test_strategy_is_lazy_for_positions_off_the_proof():
    """Looking up a robot position the search never met solves it then."""
    scene = pattern_scene(2, 3, k=1)
    found = solve_forward(scene)
    game = GameGraph(scene, parse_ltlf(scene.task), 1.0)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    nodes, edges = game.explore(Node(v0, q0, 1, False))
    value, choice = _dijkstra(nodes, edges)
    positions = [(n.v, n.q, n.h) for i, n in enumerate(nodes) if i and n.robot and i in value]
    unseen = [p for p in positions if p not in set(found.strategy)]
    assert unseen
    for p in unseen[:25]:
        action = found.strategy[p]
        i = nodes.index(Node(*p, True))
        edge = next(e for e in edges[i] if e.action == action)
        assert edge.units + value[edge.target] == value[i]  # an optimal action


# -- the lower bound ---------------------------------------------------------------------


@pytest.mark.parametrize("n,m,k", [(2, 3, 3), (3, 4, 2), (3, 5, 1)])
def test_bound_is_admissible_on_the_family(n, m, k):
    """At every reachable position, human or robot turn, any h."""
    bound, checked = bound_holds_everywhere(pattern_scene(n, m, k=k), k)
    assert bound.enabled and bound.strike > 0 and checked > 100


@pytest.mark.parametrize("grasps", [("top",), ("top", "side")])
def test_bound_is_exact_for_one_object_without_human(grasps):
    """One block and k = 0: nothing stands in its way and nobody moves it,
    so the value is the bound's own sum (first transit from anywhere, grab,
    the cheapest chain of transfers, drop); a bound that is admissible but
    weak (0, say) fails here, and the search would only get slower."""
    for m in (2, 3, 4, 6):
        for seed in range(3):
            scene = pattern_scene(1, m, k=0, seed=seed, grasps=grasps)
            formula = parse_ltlf(scene.task)
            bound = LowerBound(GameGraph(scene, formula, 1.0), formula)
            assert bound(initial_state(scene), 0, False) == solve_explicit(scene).units, (m, seed)


def test_bound_is_admissible_on_random_scenes():
    enabled = 0
    for seed in range(300, 400):
        scene = random_scene(seed)
        bound, _ = bound_holds_everywhere(scene, 2)
        enabled += bound.enabled
    assert enabled >= 10  # the pattern-like tasks of gamegen switch it on


def test_bound_is_off_for_temporal_conjuncts():
    """F(a & F b): once a has held it need not hold again, so a is no
    obligation of every position; the bound must not count it."""
    scene = random_scene(200)
    assert scene.task == "F(at(block, l2) & F(at(block, l1)))"
    formula = parse_ltlf(scene.task)
    assert not LowerBound(GameGraph(scene, formula, 1.0), formula).enabled


def test_long_plays_do_not_hit_the_recursion_limit():
    """The search recurses once per action along a play: b must walk a
    corridor l1 -> l2 -> ... -> l200 one transfer at a time (transit 1,
    grab 1, 199 transfers of 1, drop 1: 202), with Python's recursion limit
    set far below that depth for the test."""
    corridor = [f"l{i}" for i in range(1, 201)]
    # ee = Else at the start: the first transit is measured from every anchor
    motions = {("empty", s, "l1/top"): 1 for s in ["home"] + [f"{l}/top" for l in corridor[1:]]}
    for a, b in zip(corridor, corridor[1:]):
        motions[("b/top", f"{a}/top", f"{b}/top")] = 1
    scene = make_scene({"b": "l1"}, corridor, motions, task="F(at(b, l200))", grab=1, drop=1)
    limit = sys.getrecursionlimit()
    sys.setrecursionlimit(300)
    try:
        found = solve_forward(scene)
    finally:
        sys.setrecursionlimit(limit)
    assert found.units == solve_explicit(scene).units == 202
