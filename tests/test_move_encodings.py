"""The game's move rules are written four times: the reference rules
(`game/abstraction.py`, which the explicit and forward solvers read), the
per-object BDD relations (`solvers/bdd/arena.py`), the per-class ones on
orbits of interchangeable objects (`solvers/bdd/classes.py`) and the
compiled solver's kernels (`solvers/packed/kernels.py`).  Here they are compared
move by move: random well-formed positions of random small scenes
(`testing.gamegen`, with contacts, so slides too), and at each, the
successors of every encoding with their costs in units, by action family,
so a disagreement names the position, the family, the state it leads to
and the two costs.  (The whole-game value tests tie them together only
through E_p.)

Each encoding is asked for one position's successors the way its solver
asks: the reference by `legal_robot_moves`/`legal_human_moves`; a BDD
relation restricted to the position's bits (`let`) and enumerated over the
next state and the cost bits (the relation is upward closed in the cost:
the least cost that satisfies it is the move's); the kernels
`_robot_moves`/`_human_moves` on the packed state, symmetry off."""

from __future__ import annotations

import random

import numpy as np
import pytest

from support.games import well_formed_states
from symsynth.game.abstraction import State, legal_human_moves, legal_robot_moves, quantize
from symsynth.game.symmetry import interchangeable
from symsynth.logic import parse_ltlf
from symsynth.solvers import compiled
from symsynth.solvers.packed import kernels
from symsynth.solvers.bdd.arena import Arena
from symsynth.solvers.bdd.classes import ClassArena
from symsynth.testing.gamegen import alike_scene, random_scene

POSITIONS = 12  # drawn per scene
HUMAN = "move"


def positions(scene, seed):
    """Up to POSITIONS well-formed states of `scene`, drawn with `seed`."""
    every = [State(tuple(at[o] for o in scene.object_names), grip, ee)
             for at, grip, ee in well_formed_states(scene)]
    return random.Random(seed).sample(every, min(POSITIONS, len(every)))


def reference(scene, v, resolution=1.0):
    """(family, state after) -> least units, by game/abstraction.py."""
    found = {}
    for m in legal_robot_moves(scene, v):
        key = (m.kind, m.after)
        found[key] = min(found.get(key, 1 << 62), quantize(m.cost, resolution))
    for m in legal_human_moves(scene, v):
        found[(HUMAN, m.after)] = 0
    return found


def bdd_successors(arena, relations, assignment, decode):
    """(family, decoded next state) -> least units, from BDD relations
    restricted to the position's bit `assignment`."""
    bdd, found = arena.bdd, {}
    care = set(arena.next_bits) | set(arena.c.bits)
    for family, relation in relations.items():
        here = bdd.let(assignment, relation)
        for bits in bdd.pick_iter(here, care_vars=care if family != HUMAN else set(arena.next_bits)):
            key = (family, decode(bits))
            units = 0 if family == HUMAN else arena.c.decode(bits)
            found[key] = min(found.get(key, 1 << 62), units)
    return found


def differences(scene, v, expected, found, what):
    """The moves on which `found` (the encoding `what`) differs from the reference."""
    lines = []
    for key in sorted(set(expected) | set(found), key=repr):
        a, b = expected.get(key), found.get(key)
        if a != b:
            family, after = key
            lines.append(f"{scene.name} at {v}: {family} to {after}: reference "
                         f"{'none' if a is None else f'{a} units'}, {what} {'none' if b is None else f'{b} units'}")
    return lines


@pytest.mark.parametrize("seed", range(12))
def test_the_per_object_bdd_relations_make_the_reference_moves(seed):
    scene = random_scene(seed, contacts=True)
    arena = Arena(scene, parse_ltlf(scene.task), scene.k, 1.0)
    relations = dict(arena.robot) | {HUMAN: arena.human}
    problems = []
    for v in positions(scene, seed):
        found = bdd_successors(arena, relations, arena.enc.assignment(v),
                               lambda bits: arena.enc.decode(bits, primed=True))
        problems += differences(scene, v, reference(scene, v), found, "per-object BDD")
    assert problems == []


def classes_of(seed):
    scene = alike_scene(seed, contacts=True)
    return scene, interchangeable(scene, parse_ltlf(scene.task))


#: The first alike scenes with a class of interchangeable objects (a task
#: naming one object can set every one apart).
CLASS_SEEDS = [seed for seed in range(40) if classes_of(seed)[1]][:12]


def test_there_are_scenes_for_the_class_encoding():
    assert len(CLASS_SEEDS) == 12


@pytest.mark.parametrize("seed", CLASS_SEEDS)
def test_the_per_class_bdd_relations_make_the_reference_moves_between_orbits(seed):
    """On scenes with interchangeable objects; a move's target is its orbit
    (the class code), and the least cost of the moves to one orbit counts."""
    scene, classes = classes_of(seed)
    formula = parse_ltlf(scene.task)
    arena = ClassArena(scene, formula, scene.k, 1.0, classes)
    relations = {"transit": arena._transit(), "grab": arena._grab(), "transfer": arena._transfer(),
                 "drop": arena._drop(), "slide": arena._slide(), HUMAN: arena.human}
    code_bits = arena.next_bits

    def orbit(w):
        return tuple(sorted((b, arena.enc.assignment(w, primed=True)[b]) for b in code_bits))

    problems = []
    for v in positions(scene, seed):
        expected = {}
        for (family, w), units in reference(scene, v).items():
            key = (family, orbit(w))
            expected[key] = min(expected.get(key, 1 << 62), units)
        found = bdd_successors(arena, relations, arena.enc.assignment(v),
                               lambda bits: tuple(sorted((b, bool(bits.get(b, False))) for b in code_bits)))
        problems += differences(scene, v, expected, found, "per-class BDD")
    assert problems == []


@pytest.mark.parametrize("seed", range(12))
def test_the_compiled_kernels_make_the_reference_moves(seed):
    scene = random_scene(seed, contacts=True)
    tables = compiled.Tables(scene, parse_ltlf(scene.task), 1.0, None, scene.k)
    t = tables
    n, room = t.n, 4 * (t.n * t.F + t.m + 2) + 8
    at, free = np.empty(n, np.int64), np.empty(n, np.int64)
    S = np.empty(len(t.home_starts) + t.anchor_at.shape[2], np.int64)
    T = np.empty(t.anchor_at.shape[2], np.int64)
    after, units, codes = (np.empty(room, np.int64) for _ in range(3))
    no_class, no_pos = np.full(n, -1, np.int64), np.zeros(n, np.int64)
    problems = []
    for v in positions(scene, seed):
        x = np.int64(t.pack(v))
        count = kernels._robot_moves(x, n, t.m, t.F, t.pb, t.eb, t.gb, t.anchor_at, t.anchor_count,
                                     t.home_starts, t.samples_mask, t.rule_start, t.rule_count, t.rule_free,
                                     t.rule_units, t.slide_start, t.slide_count, t.is_grasp,
                                     np.int64(t.grab_units), np.int64(t.drop_units), at, free, S, T, after,
                                     units, codes)
        found = {}
        for e in range(count):
            key = (t.action(codes[e]).split("(")[0], t.unpack(int(after[e])))
            found[key] = min(found.get(key, 1 << 62), int(units[e]))
        count = kernels._human_moves(x, n, t.m, t.F, t.pb, t.eb, t.gb, after, no_class, no_pos,
                                     t.class_members, t.class_offsets, t.place_rank, t.rank_place,
                                     np.empty(n, np.int64), np.empty(room, np.int64), t.atom_at, t.free_at,
                                     t.free_all)
        for e in range(count):
            found[(HUMAN, t.unpack(int(after[e])))] = 0
        problems += differences(scene, v, reference(scene, v), found, "compiled kernel")
    assert problems == []


def test_a_disagreement_names_the_move():
    """The comparison itself: a reference with one cost changed is reported
    as that move, with both costs."""
    scene = random_scene(0, contacts=True)
    v = positions(scene, 0)[0]
    expected = reference(scene, v)
    (family, w), cost = next(iter(sorted(expected.items(), key=repr)))
    wrong = dict(expected) | {(family, w): cost + 1}
    assert differences(scene, v, expected, wrong, "an encoding") == [
        f"{scene.name} at {v}: {family} to {w}: reference {cost} units, an encoding {cost + 1} units"]
