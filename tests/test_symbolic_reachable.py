"""The symbolic solver restricted to the positions a play reaches
(`solve_symbolic(reachable_only=True)`, `solvers.bdd.fixpoint.reachable`).

- The reached sets are those of a breadth-first walk of semantics §6's plays
  on real states (`game.abstraction`'s moves, the DFA stepped state by
  state): per layer h, the same codes (per-object states, or orbits on the
  class encoding) at non-accepting positions, at either turn.
- Solved so, the value is the explicit solver's, and the strategy, followed
  through every human behaviour, wins within it.
"""

from __future__ import annotations

from collections import deque

import pytest

from symsynth.testing.gamegen import alike_scene, random_scene
from support.games import worst_case_of
from symsynth.game.abstraction import initial_state, legal_human_moves, letter, robot_moves
from symsynth.game.symmetry import interchangeable
from symsynth.logic import parse_ltlf
from symsynth.solvers.bdd.arena import Arena
from symsynth.solvers.bdd.classes import ClassArena
from symsynth.solvers.bdd.fixpoint import reachable
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.symbolic import solve_symbolic
from symsynth.automata.bdd import cofactor


def scene_of(seed):
    """Distinct objects for even seeds, interchangeable ones (some with
    contacts) for odd ones."""
    if seed % 2 == 0:
        return random_scene(3000 + seed, positive=seed % 4 == 0)
    return alike_scene(3000 + seed, contacts=seed % 3 == 0)


def arena_of(scene, k):
    formula = parse_ltlf(scene.task)
    classes = interchangeable(scene, formula)
    if classes:
        return ClassArena(scene, formula, k, 1.0, classes)
    return Arena(scene, formula, k, 1.0)


def walked(scene, arena):
    """(code, q, h) of every non-accepting position a play reaches, at either
    turn, by a walk over real states (the code: the arena's bits of v)."""
    dfa = arena.dfa

    def read(q, v):
        return dfa.step(q, letter(scene, arena.props, v))

    def code(v, q, h):
        return frozenset(arena.enc.assignment(v).items()), q, h

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    if dfa.is_accepting(q0):
        return set()
    start = (v0, q0, arena.k, False)  # False: the human's turn
    seen, queue = {start}, deque([start])
    while queue:
        v, q, h, robot = queue.popleft()
        if robot:
            successors = [(w, read(q, w), h, False) for _, w, _ in robot_moves(scene, v)]
        else:
            successors = [(v, q, h, True)] + [(m.after, read(q, m.after), h - 1, True)
                                              for m in (legal_human_moves(scene, v) if h > 0 else ())]
        for node in successors:
            if not dfa.is_accepting(node[1]) and node not in seen:
                seen.add(node)
                queue.append(node)
    return {code(v, q, h) for v, q, h, _ in seen}


@pytest.mark.parametrize("seed", range(16))
def test_reached_sets_are_the_walked_positions(seed):
    scene = scene_of(seed)
    arena = arena_of(scene, k=seed % 4)
    expected = walked(scene, arena)
    bdd = arena.bdd
    v0 = initial_state(scene)
    q0 = arena.dfa.step(arena.dfa.initial, letter(scene, arena.props, v0))
    start = bdd.cube(arena.enc.assignment(v0) | dict(zip(arena.dfa.bits, q0)))
    layers = reachable(arena, start)
    assert len(layers) == arena.k + 1
    nvars = len(arena.state_bits) + len(arena.dfa.bits)
    for h, u in enumerate(layers):
        here = [(dict(c), q) for c, q, hh in expected if hh == h]
        live = u & ~arena.accepting
        assert bdd.count(live, nvars=nvars) == len(here), h
        for values, q in here:
            assert cofactor(bdd, values | dict(zip(arena.dfa.bits, q)), live) == bdd.true, (h, values, q)


def test_reached_sets_are_not_everything():
    """The walks above leave out positions the encoding has, and classes
    occur among the scenes, so the restriction is tested doing something."""
    smaller = classes = 0
    for seed in range(16):
        scene = scene_of(seed)
        arena = arena_of(scene, k=seed % 4)
        nvars = len(arena.state_bits) + len(arena.dfa.bits)
        space = arena.enc.well_formed() & arena.dfa.reachable & ~arena.accepting
        total = arena.bdd.count(space, nvars=nvars) * (arena.k + 1)
        smaller += len(walked(scene, arena)) < total
        classes += isinstance(arena, ClassArena)
    assert smaller >= 12 and classes >= 6


@pytest.mark.parametrize("seed", range(32))
def test_value_and_strategy_when_restricted(seed):
    scene = scene_of(seed)
    k = seed % 4
    solution = solve_symbolic(scene, k=k, reachable_only=True)
    assert solution.units == solve_explicit(scene, k=k, symmetric=False).units
    if solution.units is not None:
        assert worst_case_of(scene, solution, parse_ltlf(scene.task)) == solution.units
        if solution.units > 0:
            assert solution.stats["reachable_positions"] > 0
