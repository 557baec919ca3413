"""The rise bounds of symsynth/solvers/rise.py against exact rises: on small pattern scenes,
every state w with a spare place available and every legal human move m at it, V_0 of both
scenes (S and S_Z) computed exactly for every state by a backward Dijkstra over the robot's
moves (`game.abstraction`); the relocation plans of C5^Z's proof played in the game; the
spare places, S_Z and the setting's refusals."""

from __future__ import annotations

import heapq
import itertools
import math
from collections import defaultdict

import dataclasses

import pytest

from bench.gamefamily import pattern_scene
from symsynth.game.abstraction import State, legal_human_moves, robot_moves
from symsynth.game.solution import task_formula
from symsynth.scene.model import ELSE, HAND
from symsynth.solvers.rise import (C5_CLASSES, available_spares, goals, move_class, rise_bounds, spare_places,
                                   without_drops_at)
from symsynth.solvers.rise_c5 import c5_cases
from symsynth.solvers.rise_costs import Costs


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


def solved(scene):
    """(bounds, every state, V_0, V_0^Z)."""
    formula = task_formula(scene, None)
    rises = rise_bounds(scene, formula)
    goal = goals(scene, formula)
    every = list(states(scene))
    return rises, every, values(scene, goal, every), values(without_drops_at(scene, rises.spares), goal, every)


def measured(scene):
    """(bounds, per class the largest rise found, violations)."""
    rises, every, V, VZ = solved(scene)
    worst, wrong = {}, []
    for w in every:
        if w not in V or V[w] == 0 or not available_spares(rises, w):
            continue
        for m in legal_human_moves(scene, w):
            name = move_class(scene, rises.spares, w, m)
            if name is None:
                continue
            after, spared = V.get(m.after, math.inf), VZ.get(w, math.inf)  # (S_Z may have no plan)
            if name in C5_CLASSES and spared == math.inf:
                continue
            rise = after - (spared if name in C5_CLASSES else V[w])
            worst[name] = max(worst.get(name, -math.inf), rise)
            total = rises.c5 if name in C5_CLASSES else rises.other
            if rise > rises.of(name) or rise > total or after > spared + total:
                wrong.append((w, m.action, name, rise, rises.of(name)))
    return rises, worst, wrong


@pytest.mark.parametrize("n, m, seed, grasps", [
    (3, 5, 0, ("top",)), (4, 6, 0, ("top",)), (4, 6, 1, ("top",)),
    (3, 5, 3, ("top",)),  # states where S_Z has no plan while S has one
    (3, 5, 5, ("top",)),  # two spare places
    (3, 5, 0, ("top", "side"))])
def test_every_rise_is_within_its_class_bound(n, m, seed, grasps):
    rises, worst, wrong = measured(pattern_scene(n, m, 3, seed, grasps=grasps))
    assert wrong == []
    assert set(worst) <= {name for name, _ in rises.classes}


def _play(scene, v, actions):
    """(the state after `actions` from v, what they cost), each checked against the game."""
    cost = 0
    for name in actions:
        v, c = next((after, c) for a, after, c in robot_moves(scene, v) if a == name)
        cost += c
    return v, cost


RELOCATED = ("Else->L, hand at Else", "Else->L, aimed at o", "Else->L, holding at L")


@pytest.mark.parametrize("n, m, seed", [(3, 5, 0), (4, 6, 0), (4, 6, 1)])
def test_the_relocation_plans_fit_their_bounds(n, m, seed):
    """E1, E4, H1: the proof's plan (put the held object down, relocate o to z, pick up again)
    played in the game, plus V_0 after it, is within V_0^Z(w) + the class bound."""
    scene = pattern_scene(n, m, 3, seed)
    rises, every, V, VZ = solved(scene)
    g, names, closest = scene.grasps[0], scene.object_names, {}
    for w in every:
        if w not in VZ or V[w] == 0:
            continue
        for z, m_ in itertools.product(available_spares(rises, w), legal_human_moves(scene, w)):
            name = move_class(scene, rises.spares, w, m_)
            if name not in RELOCATED:
                continue
            o, hold = m_.obj, name.endswith("holding at L")
            oh = names[w.at.index(HAND)] if hold else None
            steps = [f"drop({oh},{w.ee})"] if hold else []
            steps += [f"transit({o},{g})", f"grab({o})", f"transfer({z})", f"drop({o},{z})"]
            steps += [f"transit({oh},{w.grip})", f"grab({oh})"] if hold else []
            u, cost = _play(scene, m_.after, steps)
            slack = VZ[w] + rises.of(name) - cost - V.get(u, math.inf)
            closest[name] = min(closest.get(name, slack), slack)
    assert set(closest) == set(RELOCATED) and min(closest.values()) >= 0, closest


def test_spare_places_of_the_pattern_family():
    for (n, m, seed), spares in [((3, 5, 0), ("l1",)), ((4, 6, 0), ("l6",)), ((8, 12, 0), ("l9", "l12"))]:
        scene = pattern_scene(n, m, 3, seed)
        assert spare_places(scene, task_formula(scene, None)) == spares
    scene = pattern_scene(3, 5, 3, 0)
    for task in ["F(at(red, l2) & at(green, l3))",  # o3 named by no atom
                 "F(at(red, l2) & at(green, l3) & at(blue, l3))",  # two goals on one place
                 "F(at(red, l2) & at(green, l3) & at(blue, l4) & free(l5))",
                 "G(at(red, l2) & at(green, l3) & at(blue, l4))",
                 "F(at(block, l2))"]:  # a tag of every object
        assert spare_places(scene, task_formula(scene, task)) == (), task
    assert rise_bounds(scene, task_formula(scene, "F(at(block, l2))")) is None
    sort = pattern_scene(4, 6, 3, 0, colours=2)  # two objects of each colour
    assert spare_places(sort, task_formula(sort, None)) == ()


def test_a_rule_naming_an_else_sample_refuses_the_setting():
    scene = pattern_scene(3, 5, 3, 0)
    cm = scene.costmap
    key = next(k for k in cm.motions if k[0] == "empty")
    named = (dataclasses.replace(cm.motions[key][0], free=frozenset({"e1"})),) + cm.motions[key]
    changed = dataclasses.replace(scene, costmap=dataclasses.replace(cm, motions={**cm.motions, key: named}))
    assert spare_places(changed, task_formula(scene, None)) == ()


def test_a_scene_without_else_samples_refuses_the_setting():
    """The proofs move objects through Else's anchors; with none there is no bound (and no
    error: the anytime solve asks for it on every game)."""
    scene = pattern_scene(3, 5, 3, 0, initial={"o1": "l2", "o2": "l3", "o3": "l4"})
    assert rise_bounds(scene, task_formula(scene, None)) is not None
    bare = dataclasses.replace(scene, else_samples=())
    assert spare_places(bare, task_formula(bare, None)) == ()
    assert rise_bounds(bare, task_formula(bare, None)) is None


def test_without_drops_at_removes_the_carrying_motions_onto_the_places_only():
    scene = pattern_scene(3, 5, 3, 0)
    before, after = scene.costmap.motions, without_drops_at(scene, ("l1",)).costmap.motions
    gone = set(before) - set(after)
    assert gone and all(mode != "empty" and goal == "l1/top" for mode, _, goal in gone)
    assert all(after[k] == before[k] for k in after)
    assert {k for k in before if k[0] != "empty" and k[2] == "l1/top"} == gone


def test_the_bounds_are_in_units_of_the_resolution():
    scene = pattern_scene(8, 12, 3, 0)
    formula = task_formula(scene, None)
    whole, halves = rise_bounds(scene, formula), rise_bounds(scene, formula, 0.5)
    assert (whole.spares, whole.other, whole.c5) == (("l9", "l12"), 153, 156)
    assert (halves.other, halves.c5, halves.total) == (306, 312, 312)  # integer costs: twice the units
    assert whole.total == max(whole.other, whole.c5) == max(v for _, v in whole.classes)


def _carried(scene, u):
    """The least cost of every place the held object can be carried to from u (transfers
    only), by Dijkstra."""
    done, heap, count = {}, [(0, 0, u)], 1
    while heap:
        d, _, v = heapq.heappop(heap)
        if v.ee in done:
            continue
        done[v.ee] = d
        for a, after, c in robot_moves(scene, v):
            if a.startswith("transfer(") and after.ee not in done:
                heapq.heappush(heap, (d + c, count, after))
                count += 1
    return done


@pytest.mark.parametrize("n, m, seed", [(3, 5, 0), (4, 6, 0)])
def test_the_swap_plan_fits_its_bound(n, m, seed):
    """H2 swap: holding o_h at Else where an optimal plan of S_Z drops it first at t, and o
    put from Else on t: park o_h at the best free f, relocate o to z, carry o_h on to t and
    drop, played in the game, plus V_0 after it, is within V_0^Z(w) + the swap's bound."""
    scene = pattern_scene(n, m, 3, seed)
    rises, every, V, VZ = solved(scene)
    SZ, names = without_drops_at(scene, rises.spares), scene.object_names
    bound = c5_cases(Costs(scene), rises.spares)["H2 swap"][0]
    g, closest, met = scene.grasps[0], math.inf, 0
    for u in every:
        if HAND not in u.at or u.ee != ELSE or u not in VZ or V[u] == 0:
            continue
        oh, carried = names[u.at.index(HAND)], _carried(SZ, u)
        for z, mv in itertools.product(available_spares(rises, u), legal_human_moves(scene, u)):
            t = mv.location
            if move_class(scene, rises.spares, u, mv) != "Else->L, holding at Else" or t not in carried:
                continue
            u1, drop = _play(SZ, State(u.at, u.grip, t), [f"drop({oh},{t})"])
            if VZ[u] != carried[t] + drop + VZ.get(u1, math.inf):
                continue  # no optimal plan of S_Z drops first at t
            met += 1
            plans = []
            for f in scene.locations:
                if f in (t, z) or f in mv.after.at:
                    continue
                y, cost = _play(scene, mv.after, [f"transfer({f})", f"drop({oh},{f})", f"transit({mv.obj},{g})",
                                                  f"grab({mv.obj})", f"transfer({z})", f"drop({mv.obj},{z})",
                                                  f"transit({oh},{u.grip})", f"grab({oh})", f"transfer({t})",
                                                  f"drop({oh},{t})"])
                plans.append(cost + V.get(y, math.inf) - VZ[u])
            closest = min(closest, bound - min(plans))
    assert met > 0 and closest >= 0, (met, closest)
