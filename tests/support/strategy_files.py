"""Strategy-file helpers shared by the strategy and CLI tests."""

from __future__ import annotations

import functools
import pytest
from symsynth.automata import compile_ltlf
from symsynth.game.abstraction import human_moves, initial_state, letter, quantize, robot_moves
from symsynth.scene.propositions import interpret_all


def costmap_json(motions):
    """`motions`: (mode, from, to) -> cost, or a list of (free, cost) rules."""
    entries = []
    for (mode, start, goal), rules in motions.items():
        rules = [([], rules)] if isinstance(rules, (int, float)) else rules
        entries.append({"mode": mode, "from": start, "to": goal,
                        "rules": [{"free": list(free), "cost": cost} for free, cost in rules]})
    return {"format": "symsynth.costmap/1", "motions": entries}


def scene_data(objects, locations, *, else_samples=(), k=0, task="true", motions=None):
    data = {"name": "pick", "objects": {o: {"at": at, "tags": ["block"]} for o, at in objects.items()},
            "locations": list(locations), "else_samples": list(else_samples), "grasps": ["top"],
            "primitives": {"grab": 5, "drop": 5}, "human": {"k": k}, "task": task}
    if motions is not None:
        data["costmap"] = costmap_json(motions)
    return data


def check_file(scene, formula, solution, file):
    """The file is the solution's strategy on exactly the reachable positions,
    and it wins within cost_bound against every human."""
    assert (file.scene, file.k, file.units, file.cost_bound, file.objects) == (
        scene.name, solution.k, solution.units, solution.cost_bound, scene.object_names)
    dfa = compile_ltlf(formula)
    assert (file.dfa_bits, file.dfa_initial) == (dfa.bits, dfa.initial)
    if solution.cost_bound is None:
        assert file.positions == {}
        return
    total, worst = follow_file(scene, formula, file)
    assert set(file.positions) == set(worst)
    assert total == solution.units  # the strategy is optimal: it spends E_p, never more
    for position, units in worst.items():
        assert file.budgets[position] == pytest.approx(units * file.resolution)


def follow_file(scene, formula, file):
    """Follow the file's actions from the initial position against every
    human behaviour (pass, or any move while moves are left).  Returns the
    worst total units and, for each robot position reached, the worst units
    from there.  Fails on a missing position, an unavailable action or a
    cycle."""
    props = interpret_all(formula, scene)
    dfa = compile_ltlf(formula)
    read = functools.cache(lambda q, v: dfa.step(q, letter(scene, props, v)))
    worst, on_path = {}, set()

    def robot(v, q, h):
        key = (v, q, h)
        if key not in worst:
            assert key not in on_path, "the strategy goes in circles"
            on_path.add(key)
            action = file.lookup(v, q, h)
            (w, cost), = [(w, c) for a, w, c in robot_moves(scene, v) if a == action]
            q2 = read(q, w)
            rest = 0 if dfa.is_accepting(q2) else human(w, q2, h)
            worst[key] = quantize(cost, file.resolution) + rest
            on_path.discard(key)
        return worst[key]

    def human(v, q, h):
        outcomes = [robot(v, q, h)]
        for _, w in (human_moves(scene, v) if h > 0 else ()):
            q2 = read(q, w)
            if not dfa.is_accepting(q2):
                outcomes.append(robot(w, q2, h - 1))
        return max(outcomes)

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    total = 0 if dfa.is_accepting(q0) else human(v0, q0, file.k)
    return total, worst
