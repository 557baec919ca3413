"""The strategy file `symsynth.strategy/1`: written from every solver's
solution, read back, and checked by following it against every human.

The check (`follow_file`) is independent of `symsynth.game.strategy`: it
walks the game from the initial position with the file's actions and every
legal human behaviour, so it fails if the file misses a reachable position,
names an unavailable action, goes in circles or costs more than it says.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Mapping

import pytest

from symsynth.testing.gamegen import random_scene
from symsynth.automata import compile_ltlf
from symsynth.errors import InputError
from symsynth.game.abstraction import State, initial_state, letter, state_problems
from symsynth.scene.propositions import interpret_all
from symsynth.solvers import SOLVERS
from symsynth.game.strategy import (FORMAT, InconsistentStrategy, certify, MissingPosition, read_strategy,
                                    reachable_positions, strategy_table, worst_units, write_strategy)
from symsynth.logic import parse_ltlf
from symsynth.scene import scene_from_data
from support.games import CLEAR, PICK
from support.strategy_files import check_file, scene_data

SOLVER_NAMES = sorted(SOLVERS)

# PICK (one block, E_p = 21 for k = 0, 34 for k = 1) and CLEAR (a second
# block blocks the cheap transfer, E_p = 33) are the hand-solved scenes of
# test_game_explicit and test_game_solvers, where the values are worked out.


def pick(k, motions=PICK, task="F(at(b, l2))"):
    return scene_from_data(scene_data({"b": "l1"}, ["l1", "l2"], else_samples=["e1"], k=k,
                                      task=task, motions=motions))


def clear():
    return scene_from_data(scene_data({"a": "l2", "b": "l1"}, ["l1", "l2", "l3", "l4"],
                                      task="F(at(b, l3))", motions=CLEAR))




def start_position(scene):
    """The robot's first position if the human passes: (v0, q after ρ(v0), k)."""
    formula = parse_ltlf(scene.task)
    dfa = compile_ltlf(formula)
    v0 = initial_state(scene)
    return v0, dfa.step(dfa.initial, letter(scene, interpret_all(formula, scene), v0)), scene.k


def solve_and_write(tmp_path, solver, scene, task=None, **options):
    task = scene.task if task is None else task
    solution = SOLVERS[solver](scene, task, **options)
    target = tmp_path / "strategy.json"
    count = write_strategy(target, scene, task, solution)
    file = read_strategy(target)
    assert count == len(file.positions)
    # what simulate uses instead of the file when it solves the game itself
    assert file == strategy_table(scene, task, solution)
    return solution, file


# -- files written from solutions ----------------------------------------------------

@pytest.mark.parametrize("solver", SOLVER_NAMES)
@pytest.mark.parametrize("k, expected", [(0, 21), (1, 34), (2, 42)])
def test_pick_strategy_file_wins_within_its_bound(tmp_path, solver, k, expected):
    scene = pick(k)
    solution, file = solve_and_write(tmp_path, solver, scene)
    assert file.cost_bound == expected
    check_file(scene, parse_ltlf(scene.task), solution, file)
    first = start_position(scene)
    assert file.lookup(*first) == "transit(b,top)"
    assert file.budgets[first] == expected


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_file_keeps_the_given_task_and_k(tmp_path, solver):
    """Not the scene's: F(holding(b)) costs transit 7 + grab 5 = 12; the
    scene (k = 0) solved with k = 1 costs 34 (PICK, worked out in test_game_solvers)."""
    scene = pick(0)
    solution, file = solve_and_write(tmp_path, solver, scene, task="F(holding(b))")
    assert (file.task, file.k, file.cost_bound) == ("F(holding(b))", 0, 12)
    check_file(scene, parse_ltlf("F(holding(b))"), solution, file)
    solution, file = solve_and_write(tmp_path, solver, scene, k=1)
    assert (file.k, file.cost_bound) == (1, 34)
    check_file(scene, parse_ltlf(scene.task), solution, file)


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_clearing_strategy_file(tmp_path, solver):
    scene = clear()
    solution, file = solve_and_write(tmp_path, solver, scene)
    assert file.cost_bound == 33 and len(file.positions) == 8  # k = 0: one position per action
    check_file(scene, parse_ltlf(scene.task), solution, file)
    assert sorted(file.positions.values()) == sorted([
        "transit(a,top)", "grab(a)", "transfer(l4)", "drop(a,l4)",
        "transit(b,top)", "grab(b)", "transfer(l3)", "drop(b,l3)"])


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_resolution_is_kept(tmp_path, solver):
    """r = 2: transit 4 units, grab 3, transfer 2, drop 3 = 12 units = 24."""
    scene = pick(0)
    solution, file = solve_and_write(tmp_path, solver, scene, resolution=2)
    assert (file.resolution, file.units, file.cost_bound) == (2.0, 12, 24)
    check_file(scene, parse_ltlf(scene.task), solution, file)


@pytest.mark.parametrize("solver", SOLVER_NAMES)
@pytest.mark.parametrize("seed", range(30))
def test_generated_scenes(tmp_path, solver, seed):
    scene = random_scene(seed)
    solution, file = solve_and_write(tmp_path, solver, scene)
    check_file(scene, parse_ltlf(scene.task), solution, file)


def test_generated_scenes_are_varied():
    """The generated cases above cover won, lost and trivial games, and
    strategies that must answer human moves."""
    solutions = [(random_scene(s), SOLVERS["explicit"](random_scene(s))) for s in range(30)]
    assert sum(x.cost_bound is None for _, x in solutions) >= 3
    assert sum(x.cost_bound == 0 for _, x in solutions) >= 1
    answered = [len({h for _, _, h in reachable_positions(scene, scene.task, x)}) > 1
                for scene, x in solutions]
    assert sum(answered) >= 3


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_no_winning_strategy_writes_no_positions(tmp_path, solver):
    """Without b/top motions b never reaches l2: E_p is infinite."""
    scene = pick(0, motions={key: c for key, c in PICK.items() if key[0] == "empty"})
    solution, file = solve_and_write(tmp_path, solver, scene)
    assert (file.units, file.cost_bound, file.positions) == (None, None, {})
    data = json.loads((tmp_path / "strategy.json").read_text())
    assert data["format"] == FORMAT and data["positions"] == []


@pytest.mark.parametrize("solver", SOLVER_NAMES)
def test_task_true_at_start_needs_no_position(tmp_path, solver):
    scene = pick(1, task="F(at(b, l1))")
    solution, file = solve_and_write(tmp_path, solver, scene)
    assert (file.units, file.cost_bound, file.positions) == (0, 0, {})


# -- reachable_positions on its own --------------------------------------------------

class LazyStrategy(Mapping):
    """A strategy that only answers lookups, and records them."""

    def __init__(self, table):
        self.table, self.asked = table, []

    def __getitem__(self, position):
        self.asked.append(position)
        return self.table[position]

    def __iter__(self):
        raise AssertionError("a strategy must not be enumerated")

    def __len__(self):
        raise AssertionError("a strategy must not be counted")


def test_only_reachable_positions_are_looked_up():
    """The explicit solver's strategy also covers positions off the optimal
    plays (b moved first, say); only the 8 on the play are looked up."""
    scene = clear()
    solution = SOLVERS["explicit"](scene)
    lazy = LazyStrategy(solution.strategy)
    choices = reachable_positions(scene, scene.task, _with_strategy(solution, lazy))
    assert sorted(map(repr, lazy.asked)) == sorted(map(repr, choices))  # each looked up once
    assert len(choices) == 8 < len(solution.strategy)
    assert sorted(worst_units(choices).values()) == [5, 7, 12, 15, 20, 22, 27, 33]


def test_inconsistent_strategy_is_named():
    scene = pick(0)
    solution = SOLVERS["explicit"](scene)
    start = start_position(scene)
    wrong = dict(solution.strategy) | {start: "drop(b,l2)"}
    with pytest.raises(InconsistentStrategy, match=r"'drop\(b,l2\)'.*can only transit\(b,top\)"):
        reachable_positions(scene, scene.task, _with_strategy(solution, wrong))
    missing = {p: a for p, a in solution.strategy.items() if a != "grab(b)"}
    with pytest.raises(InconsistentStrategy, match="no action at reachable position"):
        reachable_positions(scene, scene.task, _with_strategy(solution, missing))


def test_a_strategy_in_circles_has_no_budget():
    """Transit to b, then 'transit' back to where it is: positions after the
    first never reach the win, so their worst cost is unknown."""
    scene = pick(0, motions=PICK | {("empty", "l1/top", "l1/top"): 0})
    solution = SOLVERS["explicit"](scene)
    choices = reachable_positions(scene, scene.task, solution)
    loop = {p: c._replace(replies=(p,)) for p, c in choices.items()}
    assert set(worst_units(loop).values()) == {None}
    assert worst_units(choices)[next(iter(choices))] == 21


def _with_strategy(solution, strategy):
    return dataclasses.replace(solution, strategy=strategy)


# -- reading -----------------------------------------------------------------------

@pytest.fixture
def valid(tmp_path):
    """The k = 1 pick file's JSON."""
    scene = pick(1)
    write_strategy(tmp_path / "s.json", scene, scene.task, SOLVERS["explicit"](scene))
    return json.loads((tmp_path / "s.json").read_text())


def _set(path, value):
    def change(data):
        *parents, last = path
        for key in parents:
            data = data[key]
        data[last] = value
    return change


def _delete(key):
    return lambda data: data.pop(key)


def _duplicate(data):
    data["positions"].append(dict(data["positions"][0]))


@pytest.mark.parametrize("change, expected", [
    (_set(["format"], "symsynth.strategy/0"), "format: expected 'symsynth.strategy/1', found 'symsynth.strategy/0'"),
    (_delete("positions"), "'positions' is required"),
    (_set(["k"], -1), "k: -1 is less than the minimum of 0"),
    (_set(["positions", 0, "q"], [0, 1]), "positions[0].q: expected 1 bits"),
    (_set(["positions", 0, "q"], [2]), "positions[0].q[0]"),
    (_set(["positions", 0, "at"], {"c": "l1"}), "positions[0].at: expected one place for each of the objects b"),
    (_set(["positions", 0, "at"], {}), "positions[0].at: expected one place for each of the objects b"),
    (_set(["positions", 0, "h"], 5), "positions[0].h: expected at most k = 1"),
    (_set(["positions", 0, "ee"], ["b"]), "positions[0].ee: expected a location, 'Else' or [object, grasp]"),
    (_set(["positions", 0, "action"], 3), "positions[0].action: expected string, found 3"),
    (_set(["cost_bound"], None), "units, cost_bound: expected both null"),
    (_set(["dfa", "initial"], []), "dfa.initial: expected 1 bits"),
    (_duplicate, "listed twice"),
    (lambda data: data.clear() or data.update(format=FORMAT), "'scene' is required"),
])
def test_bad_files_name_the_file_the_place_and_the_expectation(tmp_path, valid, change, expected):
    change(valid)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(valid))
    with pytest.raises(InputError) as error:
        read_strategy(path)
    message = str(error.value)
    assert message.startswith(f"{path}: not a valid symsynth.strategy/1 file")
    assert expected in message


def test_unreadable_files(tmp_path):
    with pytest.raises(InputError, match="cannot read strategy file .*nowhere.json"):
        read_strategy(tmp_path / "nowhere.json")
    broken = tmp_path / "broken.json"
    broken.write_text('{"format": ')
    with pytest.raises(InputError, match=r"broken.json:1:\d+: not JSON"):
        read_strategy(broken)
    many = tmp_path / "many.json"
    many.write_text(json.dumps({"format": FORMAT, "positions": [{}] * 20}))
    with pytest.raises(InputError, match=r"and \d+ more"):
        read_strategy(many)


def test_lookup(tmp_path):
    scene = pick(0)
    _, file = solve_and_write(tmp_path, "explicit", scene)
    (state, q, h), = [p for p, a in file.positions.items() if a == "grab(b)"]
    assert file.lookup(state, [int(b) for b in q], h) == "grab(b)"  # q as 0/1 works too
    nowhere = State(("l2",), None, "Else")
    with pytest.raises(MissingPosition, match=r"at: b=l2 \| grip=none \| ee=Else"):
        file.lookup(nowhere, q, h)


# -- certifying positions that are no state ------------------------------------

@pytest.mark.parametrize("at, grip, ee, expected", [
    ({"b": "Hand"}, None, "l1", "b is in the hand but grip is none"),
    ({"b": "l1"}, "top", "Else", "grip is 'top' but the hand is empty"),
    ({"b": "Hand"}, "side", "l1", "grip 'side' is not a grasp of the scene (top)"),
    ({"b": "l9"}, None, "Else", "b is at 'l9', which is no location, Else or Hand"),
    ({"b": "Hand"}, "top", ["b", "top"], "holding b, ee must be Else or a location"),
    ({"b": "l1"}, None, "l2", "with the hand empty, ee must be Else or [object, grasp or contact]"),
    ({"b": "l1"}, None, ["c", "top"], "with the hand empty, ee must be Else or [object, grasp or contact]"),
])
def test_certify_refuses_a_position_that_is_no_state(tmp_path, valid, at, grip, ee, expected):
    """A file may list any JSON the schema admits; certify checks each
    position against semantics §2 before it asks for the robot's moves
    there (found by the fuzz test: a held object without a grasp was a
    ValueError traceback)."""
    valid["positions"][0].update(at=at, grip=grip, ee=ee)
    path = tmp_path / "forged.json"
    path.write_text(json.dumps(valid))
    with pytest.raises(InputError, match="not a state of the scene") as error:
        certify(pick(1), read_strategy(path))
    assert expected in str(error.value)


def test_two_objects_in_one_place_are_no_state():
    scene = clear()
    assert state_problems(scene, State(("l1", "l1"), None, "Else")) == ["a and b are both at l1"]
    assert state_problems(scene, State(("Hand", "Hand"), "top", "Else")) == ["a and b are both at Hand"]


@pytest.mark.parametrize("seed", range(10))
def test_every_position_a_solver_reaches_is_a_state(seed):
    """No false refusals: the states of every position a strategy reaches
    (and the initial one) are well formed."""
    scene = random_scene(seed)
    solution = SOLVERS["explicit"](scene)
    positions = reachable_positions(scene, scene.task, solution)
    assert all(state_problems(scene, v) == [] for v, _, _ in [*positions, (initial_state(scene), 0, 0)])
