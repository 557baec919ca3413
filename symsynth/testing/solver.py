"""The solver suite: hand-solved scenes and properties every solution must
have (docs/game-semantics.md §6): the same value, and a strategy that pays
no more than E_p against any human (followed through every human behaviour
by `testing.games.worst_case_of`, independently of the solver), on
hand-made games (`testing.games`) and generated ones (`testing.gamegen`).
`conformance("solver", NAME)` (`symsynth.testing`) runs it on a registered
solver.
"""

from __future__ import annotations

import math

import pytest

from symsynth.automata import compile_ltlf
from symsynth.errors import InputError
from symsynth.game.abstraction import State, human_moves, initial_state, letter, quantize, robot_moves
from symsynth.logic import parse_ltlf
from symsynth.scene import scene_from_data
from symsynth.scene.propositions import interpret_all
from symsynth.solvers import SOLVERS
from symsynth.testing import Conformance
from symsynth.testing.gamegen import random_scene
from symsynth.testing.games import CLEAR, PICK, actions, make_scene, pick, worst_case_of


class SolverConformance(Conformance):
    """The solver suite; `solve` is the registered solver under test."""

    @pytest.fixture
    def solve(self, plugin_name):
        return SOLVERS.get_or_fail(plugin_name)

    def test_counter_play_takes_the_cheapest_action(self, solve):
        """b at l1 must reach l3, but there is no transfer at all.  The robot's
        cheapest action from the start is transit(c,top) (3, against 7 for b);
        it grabs c and can only put it back: a circle, and the counter play."""
        motions = {("empty", s, "l1/top"): 7 for s in ("home", "l2/top", "l3/top")}
        motions |= {("empty", s, "l2/top"): 3 for s in ("home", "l1/top", "l3/top")}
        scene = make_scene({"b": "l1", "c": "l2"}, ["l1", "l2", "l3"], motions, task="F(at(b, l3))")
        solution = solve(scene)
        assert solution.cost_bound is None
        assert actions(solution.counter_play) == ["transit(c,top)", "grab(c)", "drop(c,l2)"]




    def test_task_true_at_start_costs_nothing(self, solve):
        """b already stands at l1 and the task is F(at(b, l1)): the first letter
        ρ(v0) is accepted, so the robot has won before anyone moves.  E_p = 0,
        no position is explored, the play is empty; a budget of 0 suffices."""
        scene = make_scene({"b": "l1"}, ["l1", "l2"], {}, k=2, task="F(at(b, l1))")
        solution = solve(scene, budget=0)
        assert (solution.cost_bound, solution.units, solution.realizable) == (0.0, 0, True)
        assert solution.principal_play == () and solution.counter_play is None


    def test_pick_and_place_without_human(self, solve):
        """k = 0.  The robot starts at home with ee = Else, so transit(b,top) is
        measured from every anchor it may stand at to l1/top:
        max(home 7, l1/top 0 (s = t), l2/top 3, e1/top 2) = 7.  Then grab 5,
        transfer(l2) from {l1/top} to {l2/top} = 4, drop 5:
        E_p = 7 + 5 + 4 + 5 = 21."""
        solution = solve(pick(k=0), budget=21)
        assert solution.cost_bound == 21 and solution.realizable is True
        assert actions(solution.principal_play) == ["transit(b,top)", "grab(b)", "transfer(l2)", "drop(b,l2)"]
        assert [s.cost for s in solution.principal_play] == [7, 5, 4, 5]
        assert solution.principal_play[-1].state == State(("l2",), None, ("b", "top"))
        over = solve(pick(k=0), budget=20)
        assert over.realizable is False and over.counter_play == over.principal_play
        assert solution.to_json()["cost_bound"] == 21


    def test_pick_and_place_with_one_human_move(self, solve):
        """k = 1.  The human's moves that matter take b to Else (moving it to l2
        would complete the task).  Once b is in the hand the human can do nothing.
        - Move at once: transit to Else from ee = Else is
          max(home 6, l1/top 8, l2/top 4, e1/top 0) = 8; grab 5; transfer
          e1/top -> l2/top 9; drop 5: 27.
        - Pass, let the robot transit (7), then move b to Else: ee falls back to
          Else and the robot pays 8 + 5 + 9 + 5 again: 7 + 27 = 34.
        - Pass throughout: 21.
        The robot has no choice anywhere (one object, one grasp), so E_p = 34.
        With k = 2 the human repeats the trick once b is in Else (a move within
        Else is a real move): 7 + 8 + 27 = 42."""
        solution = solve(pick(k=1))
        assert solution.cost_bound == 34 and solution.realizable is None
        assert actions(solution.principal_play) == [
            "transit(b,top)", "move(b,Else)", "transit(b,top)", "grab(b)", "transfer(l2)", "drop(b,l2)"]
        assert [s.cost for s in solution.principal_play] == [7, 0, 8, 5, 9, 5]
        assert solve(pick(k=1), k=2).cost_bound == 42


    def test_missing_costmap_entry_is_unrealizable(self, solve):
        """Without b/top l1/top -> l2/top (nor e1/top -> l2/top) b can never
        reach l2.  The robot can still transit (7), grab (5) and drop b back at
        l1 (5), which returns to a position already seen: that circle is the
        counter play.  Without any transit entry the robot has no action at all
        and the counter play is empty."""
        motions = {key: c for key, c in PICK.items() if key[0] == "empty"}
        solution = solve(pick(k=0, motions=motions), budget=100)
        assert solution.cost_bound is None and solution.units is None and solution.realizable is False
        assert solution.strategy == {} and solution.principal_play == ()
        assert actions(solution.counter_play) == ["transit(b,top)", "grab(b)", "drop(b,l1)"]
        assert solution.to_json()["cost_bound"] is None

        stuck = solve(pick(k=0, motions={}))
        assert stuck.cost_bound is None and stuck.counter_play == ()


    def test_conditional_rule_makes_the_robot_clear_a_location(self, solve):
        """b at l1 must go to l3; a at l2 blocks the cheap transfer
        (b/top l1/top -> l3/top: 2 if l2 is free, else 40); k = 0, no Else.
        - Clear first: transit(a,top) from Else max(home 6, l1 2, l3 2, l4 2) = 6,
          grab 5, transfer(l4) 2 (l4 is a's only way out), drop 5,
          transit(b,top) l4/top -> l1/top 3, grab 5, transfer(l3) 2, drop 5: 33.
        - Straight: transit(b,top) max(home 5, l2 3, l3 2, l4 3) = 5, grab 5,
          transfer(l3) 40 (l2 occupied), drop 5: 55.
        - b first, then a: 5 + (l1/top -> l2/top 2) + 27 = 34.
        E_p = 33, starting with a."""
        motions = CLEAR
        scene = make_scene({"a": "l2", "b": "l1"}, ["l1", "l2", "l3", "l4"], motions,
                           task="F(at(b, l3))")
        solution = solve(scene)
        assert solution.cost_bound == 33
        assert actions(solution.principal_play) == [
            "transit(a,top)", "grab(a)", "transfer(l4)", "drop(a,l4)",
            "transit(b,top)", "grab(b)", "transfer(l3)", "drop(b,l3)"]
        # With a at l4 instead, the cheap rule applies at once: 5 + 5 + 2 + 5.
        clear = make_scene({"a": "l4", "b": "l1"}, ["l1", "l2", "l3", "l4"], motions, task="F(at(b, l3))")
        assert solve(clear).cost_bound == 17


    def test_costs_are_rounded_up_to_the_resolution(self, solve):
        """transit 7.2, grab 5, transfer 4.1, drop 5 (exact sum 21.3).
        r = 0.5: 15 + 10 + 9 + 10 = 44 units = 22.0;  r = 1: 8 + 5 + 5 + 5 = 23;
        r = 2: 4 + 3 + 3 + 3 = 13 units = 26."""
        motions = dict(PICK) | {("empty", "home", "l1/top"): 7.2, ("b/top", "l1/top", "l2/top"): 4.1}
        scene = pick(k=0, motions=motions)
        half = solve(scene, resolution=0.5, budget=22)
        assert (half.units, half.cost_bound, half.realizable) == (44, 22.0, True)
        assert solve(scene).cost_bound == 23
        assert solve(scene, resolution=2).cost_bound == 26
        assert [quantize(c, 0.1) for c in (0.3, 0.7, 0.0)] == [3, 7, 0]  # float noise costs no unit
        with pytest.raises(InputError):
            solve(scene, resolution=0)


    def test_bad_input_is_named(self, solve):
        scene = pick(k=0)
        with pytest.raises(InputError, match="unknown object or tag 'zz'"):
            solve(scene, "F(at(zz, l1))")
        with pytest.raises(InputError, match="no costmap"):
            solve(scene_from_data({"name": "bare", "objects": {"b": {"at": "l1"}},
                                            "locations": ["l1", "l2"], "task": "F(at(b, l2))"}))
        with pytest.raises(InputError, match="k must be"):
            solve(scene, k=-1)

    # -- properties on generated scenes

    @pytest.mark.parametrize("seed", range(40))
    def test_solution_properties(self, seed, solve):
        scene = random_scene(seed + 200)
        assert scene.task is not None  # generated scenes have one
        formula = parse_ltlf(scene.task)
        solutions = [solve(scene, k=k) for k in range(3)]
        # More human moves never make it cheaper (inf counts as largest).
        values = [math.inf if s.units is None else s.units for s in solutions]
        assert values == sorted(values)

        solution = solutions[scene.k]
        for budget in (0, 5, 20, 60):
            verdict = solve(scene, budget=budget).realizable
            assert verdict == (solution.cost_bound is not None and solution.cost_bound <= budget)
            assert verdict is not None
        if solution.units is None:
            assert solution.counter_play is not None and solution.principal_play == ()
            return

        assert worst_case_of(scene, solution, formula) == solution.units
        # The principal play is legal, costs E_p, and is accepted exactly at its end.
        assert sum(s.cost for s in solution.principal_play if s.who == "robot") == pytest.approx(solution.cost_bound)
        dfa = compile_ltlf(formula)
        props = interpret_all(formula, scene)
        v = initial_state(scene)
        q = dfa.step(dfa.initial, letter(scene, props, v))
        for step in solution.principal_play:
            assert not dfa.is_accepting(q)
            moves = robot_moves(scene, v) if step.who == "robot" else human_moves(scene, v)
            assert (step.action, step.state) in [m[:2] for m in moves]
            v = step.state
            q = dfa.step(q, letter(scene, props, v))
        assert dfa.is_accepting(q)
