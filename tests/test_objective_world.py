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

from symsynth.execution.human import RandomHuman
from symsynth.execution.objective_policy import BudgetPolicy
from symsynth.execution.simulate import SLACK, Simulator
from symsynth.game.graph import GameGraph
from symsynth.game.human_model import RandomModel
from symsynth.game.solution import task_formula
from symsynth.planning.registry import planner_class
from symsynth.solvers.objectives import solve_objective
from symsynth.solvers.objectives.files import objective_table


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
    return s, table, sim


@pytest.mark.parametrize("seed", [3])
def test_the_expected_strategy_runs_in_the_world_within_B(line, seed):
    s, table, sim = line
    run = sim.run(RandomHuman(seed, 0.5, sim.scene), seed)
    assert run.completed, run.reason
    assert run.sound and run.bound == pytest.approx(s.budget)
    robot = sum(step.who == "robot" for step in run.steps)
    assert robot >= 1 and sim.policy.turns == robot
    # what the counter took is what the game charged (units, rounded up from the run's abstract costs)
    assert 0 <= sim.policy.left and (s.budget_units - sim.policy.left) * s.resolution >= run.abstract_cost - SLACK
    assert run.abstract_cost <= s.budget + SLACK and run.cost <= run.abstract_cost + SLACK
