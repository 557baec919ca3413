"""Small hand-made games and an independent check of a strategy, shared by
the solver suite (`testing.solver`) and symsynth's own game tests:
`make_scene` builds an abstract scene from a table of motion costs, `pick`
and `CLEAR` are the hand-solved ones, and `worst_case_of` follows a
strategy through every human behaviour (by the game's rules in
`game.abstraction`, not by any solver)."""

from __future__ import annotations

import functools

from symsynth.automata import compile_ltlf
from symsynth.game.abstraction import human_moves, initial_state, letter, quantize, robot_moves
from symsynth.scene import scene_from_data
from symsynth.scene.propositions import interpret_all


def make_scene(objects, locations, motions, *, else_samples=(), k=0, task="true",
               grasps=("top",), grab=5, drop=5, tags=None):
    """`objects`: name -> location; `motions`: (mode, from, to) -> cost, or a
    list of (free, cost) rules; `tags`: name -> tags (default `block`)."""
    entries = []
    for (mode, start, goal), rules in motions.items():
        rules = [([], rules)] if isinstance(rules, (int, float)) else rules
        entries.append({"mode": mode, "from": start, "to": goal,
                        "rules": [{"free": list(free), "cost": cost} for free, cost in rules]})
    return scene_from_data({
        "name": "hand", "objects": {o: {"at": at, "tags": (tags or {}).get(o, ["block"])}
                                       for o, at in objects.items()},
        "locations": list(locations), "else_samples": list(else_samples), "grasps": list(grasps),
        "primitives": {"grab": grab, "drop": drop}, "human": {"k": k}, "task": task,
        "costmap": {"format": "symsynth.costmap/1", "motions": entries}})


def actions(play):
    return [step.action for step in play]


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


#: b at l1 must go to l3; a at l2 blocks the cheap transfer (see
#: test_conditional_rule_makes_the_robot_clear_a_location).
CLEAR = {
    ("empty", "home", "l2/top"): 6, ("empty", "l1/top", "l2/top"): 2,
    ("empty", "l3/top", "l2/top"): 2, ("empty", "l4/top", "l2/top"): 2,
    ("empty", "home", "l1/top"): 5, ("empty", "l2/top", "l1/top"): 3,
    ("empty", "l3/top", "l1/top"): 2, ("empty", "l4/top", "l1/top"): 3,
    ("a/top", "l2/top", "l4/top"): 2,
    ("b/top", "l1/top", "l3/top"): [(["l2"], 2), ([], 40)],
}


def worst_case_of(scene, solution, formula):
    """The largest cost the returned strategy pays against any human, found by
    following it through every human behaviour (raises on a cycle).

    The recursive closures below form a reference cycle; the BDDs (the DFA's
    and the strategy's) are reached only through `held`, which is emptied on
    the way out, so no BDD manager is left for the cycle collector to free
    before its nodes."""
    props = interpret_all(formula, scene)
    held = {"dfa": compile_ltlf(formula), "strategy": solution.strategy}
    try:
        return _worst_case(scene, solution.k, solution.resolution, props, held)
    finally:
        held.clear()


def _worst_case(scene, k, resolution, props, held):
    dfa = held["dfa"]
    read = functools.cache(lambda q, v: held["dfa"].step(q, letter(scene, props, v)))
    on_path = set()

    @functools.cache
    def robot(v, q, h):
        key = (v, q, h)
        assert key not in on_path, "the strategy goes in circles"
        on_path.add(key)
        action = held["strategy"][key]
        (w, c), = [(w, c) for a, w, c in robot_moves(scene, v) if a == action]
        q2 = read(q, w)
        units = quantize(c, resolution)
        result = units + (0 if held["dfa"].is_accepting(q2) else human(w, q2, h))
        on_path.discard(key)
        return result

    @functools.cache
    def human(v, q, h):
        worst = robot(v, q, h)
        for _, w in (human_moves(scene, v) if h > 0 else ()):
            q2 = read(q, w)
            if not held["dfa"].is_accepting(q2):
                worst = max(worst, robot(w, q2, h - 1))
        return worst

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    return 0 if dfa.is_accepting(q0) else human(v0, q0, k)
