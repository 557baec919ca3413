"""The explicit game solver and the abstraction it runs on (spec/game-semantics.md).

Hand-solved scenes first (each value worked out in the docstring), then the
abstraction's moves and costs on single states, then cross-checks on
generated scenes (`gamegen`) against two naive solvers -- a recursive
min-max bounded by the budget left (positive costs) and the min-max
equations iterated down from infinity (any costs) -- and properties every
solution must have.
"""

from __future__ import annotations

import functools
import math

import pytest

from gamegen import random_scene
from symsynth.automata import compile_ltlf
from symsynth.errors import InputError
from symsynth.game.abstraction import (State, human_moves, initial_state, letter, quantize,
                                       robot_moves)
from symsynth.game.explicit import solve_explicit
from symsynth.game.propositions import interpret_all
from symsynth.logic import parse_ltlf
from symsynth.scene import scene_from_data


def make_scene(objects, locations, motions, *, else_samples=(), k=0, task="true",
               grasps=("top",), grab=5, drop=5):
    """`objects`: name -> location; `motions`: (mode, from, to) -> cost, or a
    list of (free, cost) rules."""
    entries = []
    for (mode, start, goal), rules in motions.items():
        rules = [([], rules)] if isinstance(rules, (int, float)) else rules
        entries.append({"mode": mode, "from": start, "to": goal,
                        "rules": [{"free": list(free), "cost": cost} for free, cost in rules]})
    return scene_from_data({
        "name": "hand", "objects": {o: {"at": at, "tags": ["block"]} for o, at in objects.items()},
        "locations": list(locations), "else_samples": list(else_samples), "grasps": list(grasps),
        "primitives": {"grab": grab, "drop": drop}, "human": {"k": k}, "task": task,
        "costmap": {"format": "symsynth.costmap/1", "motions": entries}})


def actions(play):
    return [step.action for step in play]


# -- hand-solved scenes ------------------------------------------------------------

#: One block `b` at l1 to be put at l2; Else sample e1; grab = drop = 5.
PICK = {
    ("empty", "home", "l1/top"): 7, ("empty", "l2/top", "l1/top"): 3,
    ("empty", "e1/top", "l1/top"): 2,
    ("empty", "home", "e1/top"): 6, ("empty", "l1/top", "e1/top"): 8,
    ("empty", "l2/top", "e1/top"): 4,
    ("b/top", "l1/top", "l2/top"): 4, ("b/top", "e1/top", "l2/top"): 9,
}


def pick(k, motions=PICK):
    return make_scene({"b": "l1"}, ["l1", "l2"], motions, else_samples=["e1"], k=k,
                      task="F(at(b, l2))")


def test_task_true_at_start_costs_nothing():
    """b already stands at l1 and the task is F(at(b, l1)): the first letter
    ρ(v0) is accepted, so the robot has won before anyone moves.  E_p = 0,
    no position is explored, the play is empty; a budget of 0 suffices."""
    scene = make_scene({"b": "l1"}, ["l1", "l2"], {}, k=2, task="F(at(b, l1))")
    solution = solve_explicit(scene, budget=0)
    assert (solution.cost_bound, solution.units, solution.realizable) == (0.0, 0, True)
    assert solution.states == 0 and solution.principal_play == () and solution.counter_play is None


def test_pick_and_place_without_human():
    """k = 0.  The robot starts at home with ee = Else, so transit(b,top) is
    measured from every anchor it may stand at to l1/top:
    max(home 7, l1/top 0 (s = t), l2/top 3, e1/top 2) = 7.  Then grab 5,
    transfer(l2) from {l1/top} to {l2/top} = 4, drop 5:
    E_p = 7 + 5 + 4 + 5 = 21."""
    solution = solve_explicit(pick(k=0), budget=21)
    assert solution.cost_bound == 21 and solution.realizable is True
    assert actions(solution.principal_play) == ["transit(b,top)", "grab(b)", "transfer(l2)", "drop(b,l2)"]
    assert [s.cost for s in solution.principal_play] == [7, 5, 4, 5]
    assert solution.principal_play[-1].state == State(("l2",), None, ("b", "top"))
    over = solve_explicit(pick(k=0), budget=20)
    assert over.realizable is False and over.counter_play == over.principal_play
    assert solution.to_json()["cost_bound"] == 21


def test_pick_and_place_with_one_human_move():
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
    solution = solve_explicit(pick(k=1))
    assert solution.cost_bound == 34 and solution.realizable is None
    assert actions(solution.principal_play) == [
        "transit(b,top)", "move(b,Else)", "transit(b,top)", "grab(b)", "transfer(l2)", "drop(b,l2)"]
    assert [s.cost for s in solution.principal_play] == [7, 0, 8, 5, 9, 5]
    assert solve_explicit(pick(k=1), k=2).cost_bound == 42


def test_missing_costmap_entry_is_unrealizable():
    """Without b/top l1/top -> l2/top (nor e1/top -> l2/top) b can never
    reach l2.  The robot can still transit (7), grab (5) and drop b back at
    l1 (5), which returns to a position already seen: that circle is the
    counter play.  Without any transit entry the robot has no action at all
    and the counter play is empty."""
    motions = {key: c for key, c in PICK.items() if key[0] == "empty"}
    solution = solve_explicit(pick(k=0, motions=motions), budget=100)
    assert solution.cost_bound is None and solution.units is None and solution.realizable is False
    assert solution.strategy == {} and solution.principal_play == ()
    assert actions(solution.counter_play) == ["transit(b,top)", "grab(b)", "drop(b,l1)"]
    assert solution.to_json()["cost_bound"] is None

    stuck = solve_explicit(pick(k=0, motions={}))
    assert stuck.cost_bound is None and stuck.counter_play == () and stuck.states == 2


def test_conditional_rule_makes_the_robot_clear_a_location():
    """b at l1 must go to l3; a at l2 blocks the cheap transfer
    (b/top l1/top -> l3/top: 2 if l2 is free, else 40); k = 0, no Else.
    - Clear first: transit(a,top) from Else max(home 6, l1 2, l3 2, l4 2) = 6,
      grab 5, transfer(l4) 2 (l4 is a's only way out), drop 5,
      transit(b,top) l4/top -> l1/top 3, grab 5, transfer(l3) 2, drop 5: 33.
    - Straight: transit(b,top) max(home 5, l2 3, l3 2, l4 3) = 5, grab 5,
      transfer(l3) 40 (l2 occupied), drop 5: 55.
    - b first, then a: 5 + (l1/top -> l2/top 2) + 27 = 34.
    E_p = 33, starting with a."""
    motions = {
        ("empty", "home", "l2/top"): 6, ("empty", "l1/top", "l2/top"): 2,
        ("empty", "l3/top", "l2/top"): 2, ("empty", "l4/top", "l2/top"): 2,
        ("empty", "home", "l1/top"): 5, ("empty", "l2/top", "l1/top"): 3,
        ("empty", "l3/top", "l1/top"): 2, ("empty", "l4/top", "l1/top"): 3,
        ("a/top", "l2/top", "l4/top"): 2,
        ("b/top", "l1/top", "l3/top"): [(["l2"], 2), ([], 40)],
    }
    scene = make_scene({"a": "l2", "b": "l1"}, ["l1", "l2", "l3", "l4"], motions,
                       task="F(at(b, l3))")
    solution = solve_explicit(scene)
    assert solution.cost_bound == 33
    assert actions(solution.principal_play) == [
        "transit(a,top)", "grab(a)", "transfer(l4)", "drop(a,l4)",
        "transit(b,top)", "grab(b)", "transfer(l3)", "drop(b,l3)"]
    # With a at l4 instead, the cheap rule applies at once: 5 + 5 + 2 + 5.
    clear = make_scene({"a": "l4", "b": "l1"}, ["l1", "l2", "l3", "l4"], motions, task="F(at(b, l3))")
    assert solve_explicit(clear).cost_bound == 17


def test_costs_are_rounded_up_to_the_resolution():
    """transit 7.2, grab 5, transfer 4.1, drop 5 (exact sum 21.3).
    r = 0.5: 15 + 10 + 9 + 10 = 44 units = 22.0;  r = 1: 8 + 5 + 5 + 5 = 23;
    r = 2: 4 + 3 + 3 + 3 = 13 units = 26."""
    motions = dict(PICK) | {("empty", "home", "l1/top"): 7.2, ("b/top", "l1/top", "l2/top"): 4.1}
    scene = pick(k=0, motions=motions)
    half = solve_explicit(scene, resolution=0.5, budget=22)
    assert (half.units, half.cost_bound, half.realizable) == (44, 22.0, True)
    assert solve_explicit(scene).cost_bound == 23
    assert solve_explicit(scene, resolution=2).cost_bound == 26
    assert [quantize(c, 0.1) for c in (0.3, 0.7, 0.0)] == [3, 7, 0]  # float noise costs no unit
    with pytest.raises(InputError):
        solve_explicit(scene, resolution=0)


def test_bad_input_is_named():
    scene = pick(k=0)
    with pytest.raises(InputError, match="unknown object or tag 'zz'"):
        solve_explicit(scene, "F(at(zz, l1))")
    with pytest.raises(InputError, match="no costmap"):
        solve_explicit(scene_from_data({"name": "bare", "objects": {"b": {"at": "l1"}},
                                        "locations": ["l1", "l2"], "task": "F(at(b, l2))"}))
    with pytest.raises(InputError, match="k must be"):
        solve_explicit(scene, k=-1)


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

    @functools.cache
    def robot(v, q, h, b):
        best = math.inf
        for _, w, c in robot_moves(scene, v):
            units = quantize(c, 1.0)
            assert units >= 1, "brute force needs positive costs"
            if units <= b:
                q2 = read(q, w)
                rest = 0 if dfa.is_accepting(q2) else human(w, q2, h, b - units)
                best = min(best, units + rest)
        return best

    @functools.cache
    def human(v, q, h, b):
        worst = robot(v, q, h, b)  # pass
        for _, w in (human_moves(scene, v) if h > 0 else ()):
            q2 = read(q, w)
            if not dfa.is_accepting(q2):
                worst = max(worst, robot(w, q2, h - 1, b))
        return worst

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    return 0 if dfa.is_accepting(q0) else human(v0, q0, k, cap)


def game_graph(scene, formula, k):
    """The positions (v, q, h, robot's turn) reachable from the initial one,
    each with its successors as (units, position or "WIN"); None for the
    start when the first letter is already accepted."""
    props = interpret_all(formula, scene)
    dfa = compile_ltlf(formula)
    read = functools.cache(lambda q, v: dfa.step(q, letter(scene, props, v)))

    def successors(pos):
        v, q, h, robot = pos
        if robot:
            moves = [(quantize(c, 1.0), w) for _, w, c in robot_moves(scene, v)]
        else:
            moves = [(0, w) for _, w in human_moves(scene, v)] if h > 0 else []
        out = [] if robot else [(0, (v, q, h, True))]  # the pass
        for units, w in moves:
            q2 = read(q, w)
            out.append((units, "WIN" if dfa.is_accepting(q2) else (w, q2, h - (not robot), not robot)))
        return out

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    if dfa.is_accepting(q0):
        return None, {}
    start = (v0, q0, k, False)
    graph, todo = {}, [start]
    while todo:
        pos = todo.pop()
        if pos not in graph:
            graph[pos] = successors(pos)
            todo += [succ for _, succ in graph[pos] if succ != "WIN"]
    return start, graph


def horizon_value(scene, formula, k):
    """E_p by iterating the min-max equations down from infinity.

    The n-th iterate is the value of the game in which the robot must win
    within n rounds; it decreases with n.  A memoryless optimal strategy wins
    within (number of positions) rounds, so the iterates reach E_p and stay
    there: the first repeated iterate is E_p, zero-cost actions included.
    (Iterating up from 0 instead would let zero-cost circles look like wins.)
    """
    start, graph = game_graph(scene, formula, k)
    if start is None:
        return 0
    x = dict.fromkeys(graph, math.inf) | {"WIN": 0}
    while True:
        new = {pos: (min if pos[3] else max)((c + x[s] for c, s in succ), default=math.inf)
               for pos, succ in graph.items()} | {"WIN": 0}
        if new == x:
            return x[start]
        x = new


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


def worst_case_of(scene, solution, formula):
    """The largest cost the returned strategy pays against any human, found by
    following it through every human behaviour (raises on a cycle)."""
    props = interpret_all(formula, scene)
    dfa = compile_ltlf(formula)
    read = functools.cache(lambda q, v: dfa.step(q, letter(scene, props, v)))
    on_path = set()

    @functools.cache
    def robot(v, q, h):
        key = (v, q, h)
        assert key not in on_path, "the strategy goes in circles"
        on_path.add(key)
        action = solution.strategy[key]
        (w, c), = [(w, c) for a, w, c in robot_moves(scene, v) if a == action]
        q2 = read(q, w)
        units = quantize(c, solution.resolution)
        result = units + (0 if dfa.is_accepting(q2) else human(w, q2, h))
        on_path.discard(key)
        return result

    @functools.cache
    def human(v, q, h):
        worst = robot(v, q, h)
        for _, w in (human_moves(scene, v) if h > 0 else ()):
            q2 = read(q, w)
            if not dfa.is_accepting(q2):
                worst = max(worst, robot(w, q2, h - 1))
        return worst

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    return 0 if dfa.is_accepting(q0) else human(v0, q0, solution.k)


@pytest.mark.parametrize("seed", range(40))
def test_solution_properties(seed):
    scene = random_scene(seed + 200)
    formula = parse_ltlf(scene.task)
    solutions = [solve_explicit(scene, k=k) for k in range(3)]
    # More human moves never make it cheaper (inf counts as largest).
    values = [math.inf if s.units is None else s.units for s in solutions]
    assert values == sorted(values)

    solution = solutions[scene.k]
    for budget in (0, 5, 20, 60):
        verdict = solve_explicit(scene, budget=budget).realizable
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
