"""The strategies of semantics §9 followed through every human behaviour
and run against humans: the expected-cost strategy (with its waiting bound
where EX is an infimum) wins every play within B, and its mean cost
against random(P) agrees with EX; the best-effort strategy never lowers the
class by a move of its own, wins against a cooperating human at cost C, and
finishes on scenes/reach.yaml as often as computed by hand."""

from __future__ import annotations

import dataclasses
import math
import random
from fractions import Fraction
from pathlib import Path

import pytest

from symsynth.game.human_model import RandomModel, parse_model
from symsynth.scene import load_scene
from symsynth.solvers.objectives import solve_objective
from symsynth.solvers.objectives.play import (ExpectedStrategy, check_best_effort, check_expected, replies, run,
                                              still_to_pay)
from symsynth.testing.gamegen import random_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def _small(scene):
    return len(scene.objects) <= 2 and len(scene.locations) <= 3


@pytest.mark.parametrize("solver", ["explicit", "compiled"])
def test_every_play_of_the_expected_strategy_wins_within_B(solver):
    waited = 0
    for seed in range(60):
        scene = random_scene(seed, contacts=seed % 3 == 0, zeros=0.3 if seed % 2 else 0.0)
        if not _small(scene):
            continue
        got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(1, 2)), solver=solver,
                              budget=None)
        if got.expected_cost is None or got.arena is None:
            continue
        B = got.budget_units
        assert check_expected(got.strategy(), B) <= B, seed
        if not got.attained:  # the unbounded waiting strategy is not B-safe: a human who passes wins
            waited += 1
            s = got.strategy()
            assert isinstance(s, ExpectedStrategy)
            with pytest.raises(RuntimeError, match="circles"):
                check_expected(dataclasses.replace(s, waiting=None), B)
    assert waited >= 1


def _worst_by_recursion(strategy, budget):
    """The most the strategy may still pay from each turn it reaches, by the
    recursion of the definition (play.py's walk is a machine-code stack):
    {(node, budget left, count): (move, worst)}; None where a play circles."""
    arena = strategy.arena
    found, path = {}, set()

    def robot(turn):
        if turn in found:
            return found[turn][1]
        if turn in path:
            raise RecursionError
        path.add(turn)
        i, b, w = turn
        e = strategy.move(turn)
        c, t = int(arena.r_units[e]), int(arena.r_tgt[e])
        after = strategy.count(w + 1)
        cost = c if t < 0 else c + max(robot((j, b - c, after)) if j >= 0 else 0 for j in replies(arena, t))
        path.discard(turn)
        found[turn] = (e, cost)
        return cost

    try:
        for j in replies(arena, 0):
            if j >= 0:
                robot((j, budget, 0))
    except RecursionError:
        return None
    return found


def test_the_walk_pays_what_the_recursion_does():
    """Every turn the walk reaches, its move and its worst cost, against the
    definition's recursion on generated scenes (zero-cost moves in half of
    them); with the waiting bound off, a strategy that circles is caught by
    both."""
    compared = circled = 0
    for seed in range(100):
        scene = random_scene(seed, contacts=seed % 3 == 0, zeros=0.3 if seed % 2 else 0.0)
        if not _small(scene):
            continue
        got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(1, 2)),
                              solver="explicit", budget=None)
        if got.expected_cost is None or got.arena is None:
            continue
        strategy = got.strategy()
        variants = [strategy] + ([] if got.attained else [dataclasses.replace(strategy, waiting=None)])
        for s in variants:
            expected = _worst_by_recursion(s, got.budget_units)
            if expected is None:
                with pytest.raises(RuntimeError, match="circles"):
                    still_to_pay(s, got.budget_units)
                circled += 1
                continue
            turns = still_to_pay(s, got.budget_units)
            walked = {(i, b, w): (e, c) for i, b, w, e, c in zip(turns.node.tolist(), turns.budget.tolist(),
                                                                  turns.count.tolist(), turns.move.tolist(),
                                                                  turns.worst.tolist())}
            assert walked == expected, seed
            compared += 1
    assert compared >= 12 and circled >= 1


def _mean_and_error(costs):
    n = len(costs)
    mean = sum(costs) / n
    sd = math.sqrt(sum((c - mean) ** 2 for c in costs) / (n - 1))
    return mean, sd / math.sqrt(n)


@pytest.mark.parametrize("P", ["0.3", "0.5"])
def test_monte_carlo_agrees_with_EX_on_the_wait_scene(P):
    scene = load_scene(SCENES / "wait.yaml")
    got = solve_objective(scene, objective="expected", model=parse_model(f"random:{P}"), solver="explicit")
    strategy, rng = got.strategy(), random.Random(11)
    plays = [run(strategy, got.budget_units, "model", rng) for _ in range(20000)]
    assert all(won and cost <= got.budget_units for cost, won in plays)
    mean, error = _mean_and_error([cost for cost, _ in plays])
    assert abs(mean - got.expected_cost) <= 4 * error + got.epsilon, (mean, error, got.expected_cost)
    assert abs(got.expected_cost - (12.5 - 4 * float(P))) < 1e-9


def test_monte_carlo_agrees_with_EX_on_random_scenes():
    checked = 0
    for seed in range(30):
        scene = random_scene(seed)
        if not _small(scene):
            continue
        got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(3, 10)), solver="compiled")
        if got.expected_cost is None or got.arena is None:
            continue
        rng = random.Random(seed)
        plays = [run(got.strategy(), got.budget_units, "model", rng) for _ in range(3000)]
        assert all(won and cost <= got.budget_units for cost, won in plays), seed
        mean, error = _mean_and_error([cost for cost, _ in plays])
        assert abs(mean - got.expected_cost) <= 4.5 * error + 1e-9 + (got.epsilon or 0), (seed, mean, error)
        checked += 1
    assert checked >= 5


@pytest.mark.parametrize("solver", ["explicit", "compiled"])
def test_best_effort_keeps_the_class_and_wins_with_a_cooperating_human(solver):
    cooperative = 0
    for seed in range(60):
        scene = random_scene(seed, contacts=seed % 3 == 0)
        if not _small(scene):
            continue
        got = solve_objective(scene, objective="best-effort", solver=solver)
        if got.arena is None:
            continue
        strategy = got.strategy()
        assert check_best_effort(strategy, got.classes()) >= 1
        if got.position_class == "cooperative":
            cooperative += 1
            rc = got.tables[0]
            cost, won = run(strategy, 0, "cooperative", random.Random(0), coop=rc)
            assert won and cost == got.cooperative_cost, seed
    assert cooperative >= 3


def test_best_effort_finishes_on_reach_as_computed_by_hand():
    """scenes/reach.yaml: P(finish) = 1 - P + P^2/2 = 0.745 at P = 0.3; the
    cost is 9 (transit, grab), or 13 when the human moved b to l2 after the
    transit (transit again)."""
    scene = load_scene(SCENES / "reach.yaml")
    model = parse_model("random(0.3)")
    got = solve_objective(scene, objective="best-effort", model=model, solver="explicit")
    rng = random.Random(5)
    plays = [run(got.strategy(), 0, "model", rng, coop=got.tables[0]) for _ in range(20000)]
    finished = sum(won for _, won in plays) / len(plays)
    assert abs(finished - 0.745) < 4 * math.sqrt(0.745 * 0.255 / len(plays))
    assert {cost for cost, won in plays if won} == {9, 13}
