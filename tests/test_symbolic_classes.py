"""The symbolic solver's class encoding (symsynth/solvers/bdd/classes.py):
per location the kind of object standing there, for scenes with
interchangeable objects.

- The codes are the orbits: the well-formed codes are exactly those of the
  real well-formed states, one per orbit of `game.symmetry`'s renamings
  (counted by canonicalizing every real state).
- The task's atoms read on a code are the letter of every real state of it.
- The relations, read back at the code of every real well-formed state,
  lead to exactly the codes of the real moves' targets, each at the least
  quantized cost of a real move into it (`game.abstraction`, the spec as
  code); the human relation likewise.
- Solved, the value is the unreduced explicit solver's at k = 0..3, and the
  strategy, answering at real positions with real objects, is followed
  through every human behaviour within E_p.
"""

from __future__ import annotations

import math

import pytest

from symsynth.testing.gamegen import alike_scene
from support.games import ALIKE_MOTIONS, make_scene, well_formed_states, worst_case_of
from symsynth.game.abstraction import (State, initial_state, legal_human_moves, legal_robot_moves,
                                       letter, quantize)
from symsynth.game.graph import GameGraph
from symsynth.game.symmetry import Symmetry, interchangeable
from symsynth.logic import parse_ltlf
from symsynth.scene.propositions import interpret_all
from symsynth.solvers.bdd.classes import ClassArena
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.symbolic import solve_symbolic
from symsynth.automata.bdd import cofactor


def with_classes(seeds, contacts=False):
    """Generated scenes that have a class of interchangeable objects."""
    for seed in seeds:
        scene = alike_scene(seed, contacts=contacts)
        formula = parse_ltlf(scene.task)
        classes = interchangeable(scene, formula)
        if classes:
            yield scene, formula, classes


def real_states(scene):
    for at, grip, ee in well_formed_states(scene):
        yield State(tuple(at[o] for o in scene.object_names), grip, ee)


SCENES = list(with_classes(range(40)))[:6] + list(with_classes(range(40), contacts=True))[:4]


def test_the_generated_scenes_have_classes_and_contacts():
    assert len(SCENES) == 10
    assert sum(bool(scene.contacts) for scene, _, _ in SCENES) == 4


@pytest.mark.parametrize("index", range(len(SCENES)))
def test_codes_are_the_orbits(index):
    """One well-formed code per orbit, and every code is a real state's."""
    scene, formula, classes = SCENES[index]
    arena = ClassArena(scene, formula, 0, 1.0, classes)
    bdd, enc = arena.bdd, arena.enc
    symmetry = Symmetry(scene, classes)
    orbits = {symmetry.canon(v) for v in real_states(scene)}
    assert bdd.count(enc.well_formed(), nvars=len(arena.state_bits)) == len(orbits)
    union = bdd.false
    for v in real_states(scene):
        union |= enc.encode(v)
    assert union == enc.well_formed()


@pytest.mark.parametrize("index", range(len(SCENES)))
def test_atoms_read_the_letter(index):
    scene, formula, classes = SCENES[index]
    arena = ClassArena(scene, formula, 0, 1.0, classes)
    props = interpret_all(formula, scene)
    predicates = {key: arena.enc.proposition(p) for key, p in props.items()}
    for v in real_states(scene):
        values = arena.enc.assignment(v)
        holds = {key for key, u in predicates.items() if cofactor(arena.bdd, values, u) == arena.bdd.true}
        assert holds == letter(scene, props, v), v


@pytest.mark.parametrize("index", range(len(SCENES)))
def test_relations_are_the_real_moves_between_orbits(index):
    scene, formula, classes = SCENES[index]
    resolution = (1.0, 0.5)[index % 2]
    arena = ClassArena(scene, formula, 0, resolution, classes)
    bdd, enc = arena.bdd, arena.enc
    (robot,) = arena.robot.values()
    nvars = len(arena.next_bits)
    code = lambda w: frozenset(enc.assignment(w, primed=True).items())  # noqa: E731
    moves = 0
    for v in real_states(scene):
        expected: dict[frozenset, int] = {}
        for m in legal_robot_moves(scene, v):
            units = quantize(m.cost, resolution)
            expected[code(m.after)] = min(units, expected.get(code(m.after), math.inf))
        options = bdd.let(enc.assignment(v), robot)  # over (v', c)
        targets = bdd.exist(set(arena.c.bits), options)
        assert bdd.count(targets, nvars=nvars) == len(expected), v
        for target, units in expected.items():
            assert arena.c.least(bdd, bdd.let(dict(target), options)) == units, (v, target)
        moves += len(expected)
        human = {code(m.after) for m in legal_human_moves(scene, v)}
        after = bdd.let(enc.assignment(v), arena.human)
        assert bdd.count(after, nvars=nvars) == len(human), v
        for target in human:
            assert bdd.let(dict(target), after) == bdd.true, (v, target)
    assert moves > 0


@pytest.mark.parametrize("seed", range(36))
def test_value_is_the_unreduced_explicit_one(seed):
    """k = 0..3 on generated scenes with kinds (a third with contacts); the
    strategy mapped to real objects wins within E_p against every human."""
    scene = alike_scene(seed, contacts=seed % 3 == 0)
    formula = parse_ltlf(scene.task)
    for k in range(4):
        solution = solve_symbolic(scene, k=k)
        assert solution.units == solve_explicit(scene, k=k, symmetric=False).units, k
        if solution.units is not None:
            assert worst_case_of(scene, solution, formula) == solution.units
        assert solution.stats["encoding"] == ("classes" if interchangeable(scene, formula) else "objects")


def test_value_checks_are_not_vacuous():
    """The scenes above use the class encoding, mostly, and have finite
    and infinite values."""
    encodings, finite = [], []
    for seed in range(36):
        solution = solve_symbolic(alike_scene(seed, contacts=seed % 3 == 0), k=1)
        encodings.append(solution.stats["encoding"])
        finite.append(solution.units is not None)
    assert encodings.count("classes") >= 24 and 8 <= sum(finite) <= 30


MOTIONS = ALIKE_MOTIONS  # a and b alike, c with a dearer carry


def test_strategy_names_the_real_object():
    """a at l1, b at l2, c at Else; some block must reach l3.  Worked by
    hand (k = 0): carry b from l2 (home -> l2 4, grab 5, carry 2, drop 5 =
    16; from l1 the approach costs 3 but nothing else changes, 15 -- so a,
    at l1, is the cheaper one).  With the blocks swapped the strategy names
    b, the block now at l1."""
    scene = make_scene({"a": "l1", "b": "l2", "c": "Else"}, ["l1", "l2", "l3"], MOTIONS,
                       task="F(at(block, l3))")
    solution = solve_symbolic(scene)
    assert solution.stats["encoding"] == "classes" and solution.stats["interchangeable"] == "{a, b}"
    assert solution.cost_bound == 15
    game = GameGraph(scene, parse_ltlf(scene.task), 1.0)
    v = initial_state(scene)
    q = game.read(game.dfa.initial, v)
    assert solution.strategy[(v, q, 0)] == "transit(a,top)"
    swapped = State(("l2", "l1", "Else"), None, "Else")
    assert solution.strategy[(swapped, q, 0)] == "transit(b,top)"
    assert [s.action for s in solution.principal_play] == ["transit(a,top)", "grab(a)",
                                                           "transfer(l3)", "drop(a,l3)"]


def test_distinct_objects_keep_the_object_encoding():
    scene = make_scene({"a": "l1", "b": "l2", "c": "Else"}, ["l1", "l2", "l3"], MOTIONS,
                       task="F(at(a, l3))")
    solution = solve_symbolic(scene)
    assert solution.stats["encoding"] == "objects" and "interchangeable" not in solution.stats
    plain = solve_symbolic(make_scene({"a": "l1", "b": "l2", "c": "Else"}, ["l1", "l2", "l3"], MOTIONS,
                                      task="F(at(block, l3))"), symmetric=False)
    assert plain.stats["encoding"] == "objects" and plain.cost_bound == 15
