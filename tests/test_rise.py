"""The rise bounds of symsynth/solvers/rise.py against exact rises: on small pattern scenes,
every state w with a spare place available and every legal human move m at it, V_0 of both
scenes (S and S_Z) computed exactly for every state by a backward Dijkstra over the robot's
moves (`game.abstraction`)."""

from __future__ import annotations

import heapq
import itertools
from collections import defaultdict

import pytest

from bench.gamefamily import pattern_scene
from symsynth.game.abstraction import State, legal_human_moves, robot_moves
from symsynth.game.solution import task_formula
from symsynth.scene.model import ELSE, HAND
from symsynth.solvers.rise import (C5_CLASSES, Rises, available_spares, goals, move_class, rise_bounds,
                                   spare_places, without_drops_at)


def states(scene):
    """Every well-formed state in which a held object's place is free (the invariant every
    reachable state keeps)."""
    names, L = scene.object_names, scene.locations
    for at in itertools.product(L + (ELSE, HAND), repeat=len(names)):
        on = [a for a in at if a != ELSE]
        if len(on) != len(set(on)):
            continue
        if HAND in at:
            for g in scene.grasps:
                for ee in (ELSE,) + tuple(l for l in L if l not in at):
                    yield State(at, g, ee)
        else:
            yield State(at, None, ELSE)
            for o, a in itertools.product(names, scene.preimages):
                yield State(at, None, (o, a))


def values(scene, goal, all_states):
    """V_0 of every state (None: no plan): least cost to a state where every object is on its
    goal, by Dijkstra backwards from those states."""
    names = scene.object_names
    back = defaultdict(list)
    for v in all_states:
        for _, after, cost in robot_moves(scene, v):
            back[after].append((v, cost))
    done = {}
    heap = [(0, i, v) for i, v in enumerate(all_states) if all(v.at[j] == goal[o] for j, o in enumerate(names))]
    heapq.heapify(heap)
    count = len(heap)
    while heap:
        d, _, v = heapq.heappop(heap)
        if v in done:
            continue
        done[v] = d
        for u, c in back[v]:
            if u not in done:
                count += 1
                heapq.heappush(heap, (d + c, count, u))
    return done


def measured(scene):
    """(bounds, per class the largest rise found and its bound, violations)."""
    formula = task_formula(scene, None)
    rises = rise_bounds(scene, formula)
    goal = goals(scene, formula)
    every = list(states(scene))
    V = values(scene, goal, every)
    VZ = values(without_drops_at(scene, rises.spares), goal, every)
    worst, wrong = {}, []
    for w in every:
        if w not in V or V[w] == 0 or not available_spares(rises, w):
            continue
        for m in legal_human_moves(scene, w):
            name = move_class(scene, rises.spares, w, m)
            if name is None:
                continue
            after = V.get(m.after, float("inf"))
            rise = after - (VZ[w] if name in C5_CLASSES else V[w])
            worst[name] = max(worst.get(name, -1e9), rise)
            total = rises.c5 if name in C5_CLASSES else rises.other
            if rise > rises.of(name) or rise > total or after > VZ[w] + total:
                wrong.append((w, m.action, name, rise, rises.of(name)))
    return rises, worst, wrong


@pytest.mark.parametrize("n, m, seed", [(3, 5, 0), (4, 6, 0), (4, 6, 1)])
def test_every_rise_is_within_its_class_bound(n, m, seed):
    rises, worst, wrong = measured(pattern_scene(n, m, 3, seed))
    assert wrong == []
    assert set(worst) <= {name for name, _ in rises.classes}
