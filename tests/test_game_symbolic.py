"""The symbolic solver against the explicit one and against the abstraction.

- The BDD relations, read back state by state, give exactly the moves and
  quantized costs of `game.abstraction` (the spec written as code) on every
  well-formed state of generated scenes.
- On 240 generated scenes and costmaps (k = 0..3, with zero-cost actions,
  realizable and unrealizable), both solvers return the same E_p.
- The strategy's reachable positions are closed under the human's moves
  and each has a legal action.
"""

from __future__ import annotations

import functools

import pytest

from symsynth.testing.gamegen import random_scene
from symsynth.game.abstraction import State, human_moves, initial_state, quantize, robot_moves
from symsynth.solvers.explicit import solve_explicit
from symsynth.game.strategy import reachable_positions, worst_units
from symsynth.solvers.symbolic import solve_symbolic
from support.games import PICK, pick, queries, well_formed_states


@pytest.mark.parametrize("seed, contacts", [(seed, False) for seed in range(12)]
                         + [(seed + 200, True) for seed in range(8)])
def test_relations_give_the_abstractions_moves_and_costs(seed, contacts):
    """With contacts (semantics §4b) too: the slides come out of the BDD with
    their costs."""
    scene = random_scene(seed + 500, contacts=contacts)
    resolution = (1.0, 0.5, 2.0)[seed % 3]
    game = queries(scene, resolution=resolution)
    count = slides = 0
    for at, grip, ee in well_formed_states(scene):
        v = State(tuple(at[o] for o in scene.object_names), grip, ee)
        expected = sorted((a, w, quantize(c, resolution)) for a, w, c in robot_moves(scene, v))
        assert game.robot_moves(v) == expected, v
        # states, not names: moves of different objects within Else coincide
        assert {w for _, w in game.human_moves(v)} == {w for _, w in human_moves(scene, v)}, v
        count += 1
        slides += sum(a.startswith("slide(") for a, _, _ in expected)
    assert count > 0 and (slides > 0) == contacts


CROSS_SEEDS = range(240)


def cross_scene(seed):
    return random_scene(1000 + seed, positive=seed % 2 == 0), seed % 4


@functools.cache
def explicit_value(seed):
    """(units, cost_bound) of the explicit solver on the cross-checked scene
    `seed`, solved once for the two tests below."""
    scene, k = cross_scene(seed)
    explicit = solve_explicit(scene, k=k)
    return explicit.units, explicit.cost_bound


@pytest.mark.parametrize("seed", CROSS_SEEDS)
def test_same_value_as_the_explicit_solver(seed):
    scene, k = cross_scene(seed)
    symbolic = solve_symbolic(scene, k=k)
    units, cost_bound = explicit_value(seed)
    assert symbolic.units == units
    assert symbolic.cost_bound == cost_bound
    if symbolic.units is not None:
        robot_costs = sum(s.cost for s in symbolic.principal_play if s.who == "robot")
        assert robot_costs == pytest.approx(symbolic.cost_bound)


def test_cross_check_is_not_vacuous():
    """Realizable and unrealizable scenes, each k, and values above a single
    action's cost all occur among the cross-checked scenes."""
    results = [(seed % 4, explicit_value(seed)[0]) for seed in CROSS_SEEDS]
    assert sum(units is None for _, units in results) >= 40
    assert sum(units is not None and units > 10 for _, units in results) >= 60
    for k in range(4):
        assert any(kk == k and units and units > 0 for kk, units in results)
        assert any(kk == k and units is None for kk, units in results)


@pytest.mark.parametrize("seed", range(20))
def test_strategy_answers_every_reachable_position(seed):
    """Every position reachable under the strategy has a legal action, and
    following it after the human's first pass costs at most E_p (the exact
    worst case is checked in test_game_solvers)."""
    scene = random_scene(2000 + seed)
    solution = solve_symbolic(scene)
    choices = reachable_positions(scene, scene.task, solution)
    if solution.units in (None, 0):
        assert choices == {}
        return
    first = next(iter(choices))
    assert first == (initial_state(scene), first[1], scene.k)
    for (v, q, h), choice in choices.items():
        assert choice.action in [a for a, _, _ in robot_moves(scene, v)]
    assert worst_units(choices)[first] <= solution.units
    assert set(solution.strategy) == set(choices)  # looked up: exactly those


def test_infinite_value_has_no_strategy_and_a_counter_play():
    """b must reach l2 but nothing carries it there: the counter play is the
    robot's circle transit, grab, drop back, after the human's move."""
    motions = {key: c for key, c in PICK.items() if key[0] == "empty"}
    solution = solve_symbolic(pick(k=1, motions=motions), budget=10)
    assert solution.cost_bound is None and solution.realizable is False
    assert dict(solution.strategy) == {}
    assert [s.action for s in solution.counter_play][-3:] == ["transit(b,top)", "grab(b)", "drop(b,l1)"]


def test_reports_iterations_and_peak_nodes():
    solution = solve_symbolic(pick(k=1))
    # five robot actions in the worst case, one more round to see the fixpoint
    assert solution.stats["iterations"] >= 6
    assert solution.stats["peak_nodes"] > 0
    assert 2 ** solution.stats["budget_bits"] > solution.units
    assert set(solution.seconds) == {"encode", "qualitative", "attractor", "plays"}
    assert solution.stats["seconds_image"] <= solution.seconds["attractor"]
