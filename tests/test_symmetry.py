"""Interchangeable objects (symsynth/game/symmetry.py): which objects the
game cannot tell apart, and solving on canonical positions.

The values are checked against solving the same scene without the
reduction (the explicit solver on every real position, the reference the
other solvers are held to) and the strategies, mapped back to real
objects, are followed through every human behaviour (`worst_case_of`).
"""

from __future__ import annotations

import itertools
import math

import pytest

from symsynth.automata import compile_ltlf
from symsynth.game.abstraction import (State, human_moves, initial_state, letter,
                                       legal_human_moves, legal_robot_moves, robot_moves)
from symsynth.game.graph import GameGraph
from symsynth.game.symmetry import Symmetry, interchangeable
from symsynth.logic import parse_ltlf
from symsynth.scene.propositions import interpret_all
from symsynth.solvers.compiled import solve_compiled
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.forward import solve_forward
from symsynth.solvers.symbolic import solve_symbolic
from symsynth.testing.gamegen import alike_scene
from support.games import ALIKE_MOTIONS, make_scene, worst_case_of

MOTIONS = ALIKE_MOTIONS  # a and b alike, c with a dearer carry


def three(task, tags=None):
    tags = tags or {"a": ["block"], "b": ["block"], "c": ["block"]}
    return make_scene(dict(zip("abc", ("l1", "l2", "Else"))), ["l1", "l2", "l3"], MOTIONS,
                      task=task, tags=tags)


def names(scene, classes):
    return [[scene.object_names[i] for i in c] for c in classes]


def test_alike_objects_form_a_class():
    scene = three("F(at(block, l3))")
    # c's carries cost more: it is not interchangeable with a and b
    assert names(scene, interchangeable(scene, parse_ltlf(scene.task))) == [["a", "b"]]


def test_an_object_named_by_the_task_stands_alone():
    scene = three("F(at(a, l3))")
    assert interchangeable(scene, parse_ltlf(scene.task)) == ()


def test_tags_the_task_does_not_read_do_not_separate():
    tags = {"a": ["block", "red"], "b": ["block", "blue"], "c": ["block"]}
    scene = three("F(at(block, l3))", tags)
    assert names(scene, interchangeable(scene, parse_ltlf(scene.task))) == [["a", "b"]]
    scene = three("F(at(red, l3))", tags)
    assert interchangeable(scene, parse_ltlf(scene.task)) == ()


def test_canonical_states_are_one_per_orbit():
    """Every well-formed state of a class of three: canon is constant on each
    orbit (all 3! renamings) and different between orbits, and π maps the
    state onto its canonical one."""
    motions = {(f"{o}/top", "l1/top", "l2/top"): 1 for o in "abc"} | {("empty", "home", "l1/top"): 1}
    scene = make_scene({o: "Else" for o in "abc"}, ["l1", "l2", "l3"], motions,
                       task="F(at(block, l1))")
    symmetry = Symmetry.of(scene, parse_ltlf(scene.task))
    assert symmetry.classes == ((0, 1, 2),)
    places = ["l1", "l2", "l3", "Else", "Hand"]
    orbits = {}
    for at in itertools.product(places, repeat=3):
        if any(at.count(x) > 1 for x in ("l1", "l2", "l3", "Hand")):
            continue
        for ee_obj in (None, 0, 1, 2):
            if ee_obj is not None and at[ee_obj] == "Hand":
                continue
            v = State(at, "top" if "Hand" in at else None,
                      "Else" if ee_obj is None else ("abc"[ee_obj], "top"))
            c, perm = symmetry.canonical(v)
            assert sorted(perm) == [0, 1, 2]
            assert all(c.at[perm[i]] == v.at[i] for i in range(3))
            for p in itertools.permutations(range(3)):  # rename by p
                w_at = [None] * 3
                for i in range(3):
                    w_at[p[i]] = at[i]
                ee = v.ee if ee_obj is None else ("abc"[p[ee_obj]], "top")
                assert symmetry.canon(State(tuple(w_at), v.grip, ee)) == c
            orbits.setdefault(c, set()).add(v)
    for c, members in orbits.items():
        assert c in members  # the canonical state is a real one of its orbit
    # orbits are disjoint: 3 distinguishable objects have 6x as many states as orbits at most
    assert len(orbits) < sum(len(m) for m in orbits.values())


def _check_play(scene, formula, solution):
    """The principal play is legal in the real game, names real objects, and
    costs E_p."""
    dfa = compile_ltlf(formula)
    props = interpret_all(formula, scene)
    v = initial_state(scene)
    q = dfa.step(dfa.initial, letter(scene, props, v))
    for step in solution.principal_play:
        moves = robot_moves(scene, v) if step.who == "robot" else human_moves(scene, v)
        assert (step.action, step.state) in [m[:2] for m in moves]
        v = step.state
        q = dfa.step(q, letter(scene, props, v))
    assert dfa.is_accepting(q)
    assert sum(s.cost for s in solution.principal_play) == pytest.approx(solution.cost_bound)


@pytest.mark.parametrize("seed", range(60))
def test_canonical_solving_keeps_the_value(seed):
    scene = alike_scene(seed, contacts=seed % 3 == 0)
    formula = parse_ltlf(scene.task)
    plain = solve_explicit(scene, symmetric=False)
    for solve in (solve_explicit, solve_forward, solve_compiled):
        reduced = solve(scene)
        assert reduced.units == plain.units, solve.__name__
        if reduced.units is not None:
            assert worst_case_of(scene, reduced, formula) == reduced.units
            _check_play(scene, formula, reduced)
    assert solve_symbolic(scene).units == plain.units


def test_generated_scenes_have_classes():
    """The scenes above exercise the reduction: most have a class, and on
    those the explicit solver looks at fewer positions."""
    with_class = fewer = 0
    for seed in range(60):
        scene = alike_scene(seed)
        if interchangeable(scene, parse_ltlf(scene.task)):
            with_class += 1
            fewer += solve_explicit(scene).states < solve_explicit(scene, symmetric=False).states
    assert with_class >= 30 and fewer >= 20


def test_strategy_answers_at_every_real_position():
    """Looked up at a non-canonical position, the strategy names the real
    object standing where the canonical action acts."""
    scene = three("F(at(block, l3))")
    solution = solve_explicit(scene)
    assert solution.stats["interchangeable"] == "{a, b}"
    formula = parse_ltlf(scene.task)
    game = GameGraph(scene, formula, 1.0)
    v = initial_state(scene)  # a at l1, b at l2: the cheapest block to carry to l3 is b (l2 is nearer)
    q = game.read(game.dfa.initial, v)
    first = solution.strategy[(v, q, 0)]
    swapped = State(("l2", "l1", "Else"), None, "Else")
    assert solution.strategy[(swapped, q, 0)] == first.replace("b", "a") if "b" in first else first
    assert math.isfinite(worst_case_of(scene, solution, formula))


def test_sorting_family_classes_by_colour():
    """The game benchmark's sorting variant: blocks of one colour form a
    class, and the reduced solvers agree with the unreduced one."""
    from bench.gamefamily import pattern_scene

    scene = pattern_scene(4, 5, k=1, colours=2)
    assert names(scene, interchangeable(scene, parse_ltlf(scene.task))) == [["o1", "o3"], ["o2", "o4"]]
    plain = solve_explicit(scene, symmetric=False)
    reduced = solve_explicit(scene)
    assert reduced.units == plain.units == solve_forward(scene).units
    assert reduced.states < plain.states


# --- declared classes (`interchangeable:` in a scene file) -------------------

def declared(scene, *classes):
    import dataclasses
    return dataclasses.replace(scene, declared_classes=tuple(tuple(c) for c in classes))


def test_a_declared_class_is_used_and_gives_the_plain_value():
    """Declaring {a, b} of three alike blocks: only that class is reduced
    (a, b, c all alike otherwise), and the value is the unreduced one."""
    motions = {(f"{o}/top", f"l{i}/top", f"l{j}/top"): 2 for o in "abc" for i in range(1, 4)
               for j in range(1, 4) if i != j} | {k: v for k, v in MOTIONS.items() if k[0] == "empty"}
    scene = make_scene(dict(zip("abc", ("l1", "l2", "Else"))), ["l1", "l2", "l3"], motions,
                       task="F(at(block, l3))", tags={o: ["block"] for o in "abc"})
    formula = parse_ltlf(scene.task)
    assert names(scene, interchangeable(scene, formula)) == [["a", "b", "c"]]
    only_ab = declared(scene, ["b", "a"])
    assert names(only_ab, interchangeable(only_ab, formula)) == [["a", "b"]]
    plain = solve_explicit(scene, symmetric=False).units
    for solver in (solve_explicit, solve_forward, solve_compiled, solve_symbolic):
        solution = solver(only_ab)
        assert solution.units == plain and solution.stats["interchangeable"] == "{a, b}"


def test_declaring_no_class_switches_the_reduction_off():
    scene = declared(three("F(at(block, l3))"))
    assert interchangeable(scene, parse_ltlf(scene.task)) == ()
    assert "interchangeable" not in solve_explicit(scene).stats


@pytest.mark.parametrize("task, members, reason", [
    ("F(at(a, l3))", ["a", "b"], "the task names 'a', which a carries and b does not"),
    ("F(at(block, l3))", ["a", "c"], "the costmap's motions holding them differ (mode a/top against c/top"),
])
def test_a_declared_class_the_game_tells_apart_is_refused(task, members, reason):
    """Objects c (a dearer carry) and a, or a named by the task: declaring
    them alike would solve another game; the declaration is refused with
    what tells them apart."""
    from symsynth.errors import InputError

    scene = declared(three(task), members)
    with pytest.raises(InputError, match="interchangeable.0: a and [bc] are not interchangeable") as error:
        solve_explicit(scene)
    assert reason in str(error.value)


def test_declared_classes_in_a_scene_file(tmp_path, capsys):
    """Unknown names and an object in two classes are scene errors (line and
    key path); a class the task tells apart is refused by solve (exit 2)."""
    from symsynth.cli import main

    toy = (tmp_path / "toy.yaml")
    from pathlib import Path

    text = Path("scenes/toy.yaml").read_text()
    (tmp_path / "toy.costmap.json").write_text(Path("scenes/toy.costmap.json").read_text())
    toy.write_text(text + "interchangeable:\n  - [b, w]\n  - [w, x]\n")
    assert main(["solve", str(toy)]) == 2
    err = capsys.readouterr().err
    lines = text.count("\n")
    assert f"toy.yaml:{lines + 3}: interchangeable.1.0: 'w' is already in class 0" in err
    assert f"toy.yaml:{lines + 3}: interchangeable.1.1: unknown object 'x'" in err
    assert "Traceback" not in err
    toy.write_text(text + "interchangeable:\n  - [b, w]\n")
    assert main(["solve", str(toy)]) == 2
    err = capsys.readouterr().err
    assert f"toy.yaml:{lines + 2}: interchangeable.0: b and w are not interchangeable: the task names " \
           "'black', which b carries and w does not" in err
    assert "Traceback" not in err
