"""The replanning bound's certificates play σ's actions one at a time
(`packed.replies._act`), generating only the action asked for: at every
well-formed state of generated scenes (alike objects, contacts, slides) and
for every action code, it gives what the full move generator
(`packed.kernels._robot_moves`) gives for that code, and "not available"
for a code the generator does not make there."""

from __future__ import annotations

import numpy as np

from symsynth.game.abstraction import State
from symsynth.game.solution import OutOfReach
from symsynth.logic import parse_ltlf
from symsynth.solvers.packed import replies
from symsynth.solvers.packed.kernels import _robot_moves
from symsynth.solvers.replan_budget import BudgetedBound
from support.games import planning_scene, well_formed_states


def _all_moves(x, P, G, S):
    """{code: (state after, units)} from the full generator at packed state x."""
    n, m, F, pb, eb, gb = P[:6]
    grab_units, drop_units, samples_mask = P[9], P[10], P[11]
    (anchor_at, anchor_count, home_starts, rule_start, rule_count, rule_free, rule_units, slide_start,
     slide_count, is_grasp) = G[:10]
    nm = _robot_moves(np.int64(x), n, m, F, pb, eb, gb, anchor_at, anchor_count, home_starts, samples_mask,
                      rule_start, rule_count, rule_free, rule_units, slide_start, slide_count, is_grasp,
                      grab_units, drop_units, S[1], S[2], S[3], S[4], S[6], S[7], S[8])
    return {int(c): (int(a), int(u)) for c, a, u in zip(S[8][:nm], S[6][:nm], S[7][:nm])}


def _codes(P):
    n, m, F = int(P[0]), int(P[1]), int(P[2])
    return range(7 * (n + 1) * (F + 1) * (m + 2))


def test_one_action_is_what_the_move_generator_makes_of_it():
    compared = states = 0
    for seed in range(24):
        scene = planning_scene(seed, 9200)
        if len(scene.object_names) > 3 or len(scene.locations) > 5:
            continue
        try:
            bound = BudgetedBound(scene, parse_ltlf(scene.task), 1)
        except OutOfReach:
            continue
        t, memo = bound.t, bound.memo
        P, G, S = memo.P, memo.G, memo.S()
        out = np.empty(3, np.int64)
        for at, grip, ee in well_formed_states(scene):
            x = t.pack(State(tuple(at[o] for o in scene.object_names), grip, ee))
            states += 1
            made = _all_moves(x, P, G, S)
            for code in _codes(P):
                replies._act(np.int64(x), np.int64(0), np.int64(code), P, G, S, out)
                after, units = made.get(code, (None, -1))
                assert int(out[2]) == units and (units < 0 or int(out[0]) == after), (seed, x, code)
                compared += units >= 0
    assert states >= 2000 and compared >= 10000, (states, compared)
