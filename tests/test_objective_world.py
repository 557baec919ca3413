"""The expected-cost strategy (semantics §9) followed in the kinematic
world with its budget counter (`execution.objective_policy`): on the line
with its recursive costmap, against the model's random human, every run
completes along the strategy's own entries (keyed by the budget left, which
the counter must track: a counter that never falls finds no entry once the
robot has paid anything), within B in the abstraction and measured."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest

from symsynth.execution.human import AdversarialHuman, RandomHuman
from symsynth.execution.objective_policy import BudgetPolicy
from symsynth.execution.runs import SLACK
from symsynth.execution.simulate import Simulator
from symsynth.game.graph import GameGraph
from symsynth.game.human_model import RandomModel
from symsynth.game.solution import task_formula
from symsynth.planning.registry import planner_class
from symsynth.solvers.objectives import solve_objective
from symsynth.solvers.objectives.files import objective_table, to_pay_by_position


@pytest.fixture(scope="module")
def line(paper_line):
    scene, costmaps = paper_line
    scene = dataclasses.replace(scene, costmap=costmaps["recursive"], k=1)
    formula = task_formula(scene, None)
    s = solve_objective(scene, formula, objective="expected", model=RandomModel(Fraction(1, 2)), solver="explicit")
    table = objective_table(scene, scene.task, formula, s)
    game = GameGraph(scene, formula, s.resolution)
    policy = BudgetPolicy(table, game)
    sim = Simulator(scene, formula, policy, planner_class(scene.geometry.planner.name)(scene))
    return s, table, sim, formula


@pytest.mark.parametrize("seed", [3])
def test_the_expected_strategy_runs_in_the_world_within_B(line, seed):
    s, table, sim, _ = line
    run = sim.run(RandomHuman(seed, 0.5, sim.scene), seed)
    assert run.completed, run.reason
    assert run.sound and run.bound == pytest.approx(s.budget)
    robot = sum(step.who == "robot" for step in run.steps)
    assert robot >= 1 and sim.policy.turns == robot
    # what the counter took is what the game charged (units, rounded up from the run's abstract costs)
    assert 0 <= sim.policy.left and (s.budget_units - sim.policy.left) * s.resolution >= run.abstract_cost - SLACK
    assert run.abstract_cost <= s.budget + SLACK and run.cost <= run.abstract_cost + SLACK


def _most_any_human_forces(strategy, budget):
    """The largest abstract cost (units) of a play of the expected-cost
    strategy from the start, over every pass and move of every human turn."""
    arena = strategy.arena

    def replies(t):
        return [t] + [int(j) for j in arena.h_tgt[arena.h_off[t]:arena.h_off[t + 1]]]

    def robot(i, b, w):
        e = strategy.move((i, b, w))
        c, t = int(arena.r_units[e]), int(arena.r_tgt[e])
        return c if t < 0 else c + max(0 if j < 0 else robot(j, b - c, strategy.count(w + 1)) for j in replies(t))

    return max(0 if j < 0 else robot(j, budget, 0) for j in replies(0))


def test_the_adversary_drives_the_expected_strategy_to_its_largest_cost_within_B(line):
    """The world's adversary, choosing by what the strategy may still pay
    with the budget it has left, makes the run cost exactly the most any
    human can force in the abstraction (124 units of B = 321): a human
    choosing at random among its replies, or by a counter that does not
    follow the robot, makes it 38 here.  (Choosing by the worst-case values
    V reaches 124 on this scene too: it is the abstraction's `worst` human.)"""
    s, table, sim, formula = line
    policy = BudgetPolicy(table, sim.policy.game, to_pay_by_position(s))
    world = Simulator(sim.scene, formula, policy, sim.planner)
    most = _most_any_human_forces(s.strategy(), s.budget_units)
    for seed in (0, 1):
        run = world.run(AdversarialHuman(seed, policy.still_to_pay), seed)
        assert run.completed and run.sound, run.reason
        assert s.budget_units - policy.left == most <= s.budget_units  # units, as the game charges them
        assert run.abstract_cost <= most * s.resolution + SLACK and run.cost <= run.abstract_cost + SLACK
