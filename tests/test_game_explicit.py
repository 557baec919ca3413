"""The explicit game solver and the abstraction it runs on (docs/game-semantics.md).

The abstraction's moves and costs on single states, then cross-checks of
the explicit solver on generated scenes (`gamegen`) against two naive
solvers -- a recursive min-max bounded by the budget left (positive costs)
and the min-max equations iterated down from infinity (any costs).  The
hand-solved scenes, run on every solver, are in test_game_solvers.py.
"""

from __future__ import annotations

import functools
import math

import pytest

from symsynth.testing.gamegen import random_scene
from symsynth.automata import compile_ltlf
from symsynth.game.abstraction import (State, human_moves, initial_state, letter, quantize,
                                       robot_moves)
from symsynth.solvers.explicit import solve_explicit
from symsynth.scene.propositions import interpret_all
from symsynth.logic import parse_ltlf
from support.games import game_graph, horizon_value, make_scene, pick


# -- scenes shared with test_game_solvers ------------------------------------------


# -- the abstraction on single states -----------------------------------------------

def test_free_for_the_served_object_and_else_samples():
    """A rule's location counts as free when no *other* object is there; an
    Else sample when no other object is at Else."""
    motions = {("empty", "l2/top", "l1/top"): [(["l1", "l3"], 1), ([], 9)],
               ("empty", "l2/top", "e1/top"): [(["e1"], 2), ([], 6)],
               ("empty", "l2/top", "e2/top"): 3}
    scene = make_scene({"o": "l1", "p": "l2", "q": "Else"}, ["l1", "l2", "l3"], motions,
                       else_samples=["e1", "e2"])
    at_p = State(("l1", "l2", "Else"), None, ("p", "top"))
    costs = {a: c for a, _, c in robot_moves(scene, at_p)}
    assert costs["transit(o,top)"] == 1  # o itself at l1 does not block its own l1
    # Else anchors: e1 costs 2 (only q, the served object, is at Else), e2 costs 3.
    assert costs["transit(q,top)"] == max(2, 3)
    o_at_else = State(("Else", "l2", "Else"), None, ("p", "top"))
    costs = {a: c for a, _, c in robot_moves(scene, o_at_else)}
    assert costs["transit(q,top)"] == max(6, 3)  # o at Else takes e1's cheap rule away
    q_at_l3 = State(("l1", "l2", "l3"), None, ("p", "top"))
    costs = {a: c for a, _, c in robot_moves(scene, q_at_l3)}
    assert costs["transit(o,top)"] == 9  # q at l3 takes the cheap rule away


def test_robot_moves_follow_the_table():
    motions = {("empty", "home", "l1/top"): 1, ("empty", "l2/top", "l1/top"): 1,
               ("b/top", "l1/top", "l2/top"): 1}
    scene = make_scene({"b": "l1", "c": "Else"}, ["l1", "l2"], motions)
    v0 = initial_state(scene)
    assert v0 == State(("l1", "Else"), None, "Else")
    # c is at Else and there are no Else samples: no transit to it.
    assert [a for a, _, _ in robot_moves(scene, v0)] == ["transit(b,top)"]
    (_, at_b, _), = robot_moves(scene, v0)
    assert [(a, w) for a, w, _ in robot_moves(scene, at_b)] == [
        ("grab(b)", State(("Hand", "Else"), "top", "l1"))]
    holding = State(("Hand", "Else"), "top", "l1")
    assert {a: w for a, w, _ in robot_moves(scene, holding)} == {
        "transfer(l2)": State(("Hand", "Else"), "top", "l2"),
        "drop(b,l1)": State(("l1", "Else"), None, ("b", "top"))}


def test_human_moves():
    scene = make_scene({"b": "l1", "c": "Else"}, ["l1", "l2", "l3"], {})
    # b is held, aligned with l2: c may go anywhere but l2; b cannot be moved.
    held = State(("Hand", "Else"), "top", "l2")
    assert [a for a, _ in human_moves(scene, held)] == ["move(c,l1)", "move(c,l3)", "move(c,Else)"]
    # Moving the object the hand is at sends the hand back to Else; within Else counts.
    at_c = State(("l1", "Else"), None, ("c", "top"))
    moves = dict(human_moves(scene, at_c))
    assert moves["move(c,Else)"] == State(("l1", "Else"), None, "Else")
    assert moves["move(b,l2)"] == State(("l2", "Else"), None, ("c", "top"))
    assert "move(b,l1)" not in moves and "move(c,l1)" not in moves


def test_letter():
    scene = make_scene({"b": "l1", "c": "Else"}, ["l1", "l2"], {})
    formula = parse_ltlf("at(block, Else) & holding(b) & occupied(l1) & free(l2) & at(c, l1)")
    props = interpret_all(formula, scene)
    assert letter(scene, props, initial_state(scene)) == {"at(block, Else)", "occupied(l1)", "free(l2)"}
    held = State(("Hand", "l1"), "top", "Else")
    assert letter(scene, props, held) == {"holding(b)", "occupied(l1)", "free(l2)", "at(c, l1)"}


# -- cross-checks on generated scenes ------------------------------------------------

CAP = 60  # the brute force decides values up to this many units


def brute_force(scene, formula, k, cap=CAP):
    """Naive recursive min-max with memo on (v, q, h, turn, budget left).

    `robot(v, q, h, b)` is the least cost <= b the robot can guarantee to win
    with, inf if none.  Every action costs >= 1 unit (checked), so a play that
    stays within b has at most b robot actions and the recursion is finite;
    with cap >= E_p it yields E_p exactly, else inf.
    """
    props = interpret_all(formula, scene)
    dfa = compile_ltlf(formula)

    @functools.cache
    def read(q, v):
        return dfa.step(q, letter(scene, props, v))

    # The moves from v depend on v alone: generated once per state, not
    # once per (v, q, h, b) (about 10 of the 17 s of the slowest seeds).
    @functools.cache
    def robot_options(v):
        options = []
        for _, w, c in robot_moves(scene, v):
            units = quantize(c, 1.0)
            assert units >= 1, "brute force needs positive costs"
            options.append((units, w))
        return options

    @functools.cache
    def human_options(v):
        return [w for _, w in human_moves(scene, v)]

    @functools.cache
    def robot(v, q, h, b):
        best = math.inf
        for units, w in robot_options(v):
            if units <= b:
                q2 = read(q, w)
                rest = 0 if dfa.is_accepting(q2) else human(w, q2, h, b - units)
                best = min(best, units + rest)
        return best

    @functools.cache
    def human(v, q, h, b):
        worst = robot(v, q, h, b)  # pass
        for w in (human_options(v) if h > 0 else ()):
            q2 = read(q, w)
            if not dfa.is_accepting(q2):
                worst = max(worst, robot(w, q2, h - 1, b))
        return worst

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    return 0 if dfa.is_accepting(q0) else human(v0, q0, k, cap)


BRUTE_SEEDS = range(80)


@pytest.mark.parametrize("seed", BRUTE_SEEDS)
def test_matches_brute_force(seed):
    scene = random_scene(seed, positive=True)
    formula = parse_ltlf(scene.task)
    solution = solve_explicit(scene)
    expected = brute_force(scene, formula, scene.k)
    if solution.units is not None and solution.units <= CAP:
        assert expected == solution.units
    else:
        assert expected == math.inf


def test_generated_scenes_are_varied():
    """The cross-check is not vacuous: realizable with a positive cost,
    immediately won, and unrealizable scenes all occur."""
    values = [solve_explicit(random_scene(seed, positive=True)).units for seed in BRUTE_SEEDS]
    assert sum(v is None for v in values) >= 10
    assert sum(v is not None and 0 < v <= CAP for v in values) >= 15
    assert 0 in values


@pytest.mark.parametrize("seed", range(100, 160))
def test_matches_horizon_iteration(seed):
    """Generated scenes where actions may cost 0 (the recursion above would not end)."""
    scene = random_scene(seed)
    solution = solve_explicit(scene)
    expected = horizon_value(scene, parse_ltlf(scene.task), scene.k)
    assert expected == (math.inf if solution.units is None else solution.units)


def test_zero_cost_scenes_are_varied():
    """Zero-cost robot actions, and finite and infinite values, occur among them."""
    graphs = [game_graph(s, parse_ltlf(s.task), s.k)[1]
              for s in (random_scene(seed) for seed in range(100, 160))]
    zero = [any(c == 0 for pos, succ in g.items() if pos[3] for c, _ in succ) for g in graphs]
    values = [solve_explicit(random_scene(seed)).units for seed in range(100, 160)]
    assert sum(zero) >= 20 and sum(z and bool(v) for z, v in zip(zero, values)) >= 10
    assert sum(v is None for v in values) >= 10


def test_positions_explored():
    """The explicit solver counts the positions it explored: none when ρ(v0)
    is accepted; the initial human and robot positions when the robot has no
    action at all."""
    won = make_scene({"b": "l1"}, ["l1", "l2"], {}, k=2, task="F(at(b, l1))")
    assert solve_explicit(won).states == 0
    assert solve_explicit(pick(k=0, motions={})).states == 2
