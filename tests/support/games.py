"""Small games and the independent checks the game tests share: hand-made
scenes (`make_scene`, `pick`) and the cost a strategy pays against every
human (`worst_case_of`), both from `symsynth.testing.games` (the solver
suite uses them too); the game graph of a scene, the well-formed states
of semantics §2 enumerated, the symbolic solver's queries."""

from __future__ import annotations

import functools
import itertools
import math

from symsynth.automata import compile_ltlf
from symsynth.game.abstraction import human_moves, initial_state, letter, quantize, robot_moves
from symsynth.testing.games import CLEAR, PICK, actions, make_scene, pick, worst_case_of  # noqa: F401  (shared here)
from symsynth.scene.propositions import interpret_all
from symsynth.solvers.bound import LowerBound
from symsynth.game.graph import GameGraph, Node
from symsynth.solvers.explicit import _dijkstra
from symsynth.solvers.symbolic import _Queries
from symsynth.logic import parse_ltlf
from symsynth.solvers.bdd.arena import Arena


def game_graph(scene, formula, k, units=lambda c: quantize(c, 1.0)):
    """The positions (v, q, h, robot's turn) reachable from the initial one,
    each with its successors as (units(cost), position or "WIN"); None for
    the start when the first letter is already accepted."""
    props = interpret_all(formula, scene)
    dfa = compile_ltlf(formula)
    read = functools.cache(lambda q, v: dfa.step(q, letter(scene, props, v)))

    def successors(pos):
        v, q, h, robot = pos
        if robot:
            moves = [(units(c), w) for _, w, c in robot_moves(scene, v)]
        else:
            moves = [(0, w) for _, w in human_moves(scene, v)] if h > 0 else []
        out = [] if robot else [(0, (v, q, h, True))]  # the pass
        for cost, w in moves:
            q2 = read(q, w)
            out.append((cost, "WIN" if dfa.is_accepting(q2) else (w, q2, h - (not robot), not robot)))
        return out

    v0 = initial_state(scene)
    q0 = read(dfa.initial, v0)
    if dfa.is_accepting(q0):
        return None, {}
    start = (v0, q0, k, False)
    graph, todo = {}, [start]
    while todo:
        pos = todo.pop()
        if pos not in graph:
            graph[pos] = successors(pos)
            todo += [succ for _, succ in graph[pos] if succ != "WIN"]
    return start, graph


def well_formed_states(scene):
    """Spec §2, enumerated: at most one object per location and in the hand;
    grip set iff holding; holding => ee in L + {Else}; empty hand =>
    ee in {Else} + {(o, a) : at[o] != Hand, a a grasp or contact}."""
    objects, locations, grasps = scene.object_names, scene.locations, scene.grasps
    for at in itertools.product(locations + ("Else", "Hand"), repeat=len(objects)):
        if any(at.count(x) > 1 for x in locations + ("Hand",)):
            continue
        holding = "Hand" in at
        for grip in (grasps if holding else (None,)):  # a contact never holds
            if holding:
                ees = ("Else",) + locations
            else:
                ees = ("Else",) + tuple((o, a) for o, x in zip(objects, at) for a in grasps + scene.contacts)
            for ee in ees:
                yield dict(zip(objects, at)), grip, ee


def queries(scene, k=1, resolution=1.0):
    return _Queries(Arena(scene, parse_ltlf(scene.task), k, resolution))


def bound_holds_everywhere(scene, k):
    """The forward solver's lower bound, at every position reachable with
    k human moves, is at most the explicit solver's value there; returns
    the bound and how many positions were checked."""
    formula = parse_ltlf(scene.task)
    game = GameGraph(scene, formula, 1.0)
    bound = LowerBound(game, formula)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return bound, 0
    nodes, edges = game.explore(Node(v0, q0, k, False))
    value, _ = _dijkstra(nodes, edges)
    checked = 0
    for i, node in enumerate(nodes):
        if i == 0:
            continue
        b = bound(node.v, node.h, node.robot)
        assert b <= value.get(i, math.inf), (scene.name, node, b, value.get(i))
        checked += 1
    return bound, checked


def horizon_value(scene, formula, k, units=None):
    """E_p by iterating the min-max equations down from infinity.

    The n-th iterate is the value of the game in which the robot must win
    within n rounds; it decreases with n.  A memoryless optimal strategy wins
    within (number of positions) rounds, so the iterates reach E_p and stay
    there: the first repeated iterate is E_p, zero-cost actions included.
    (Iterating up from 0 instead would let zero-cost circles look like wins.)
    `units`: what a cost counts as (default: whole units at resolution 1).
    """
    start, graph = game_graph(scene, formula, k, **({} if units is None else {"units": units}))
    if start is None:
        return 0
    x = dict.fromkeys(graph, math.inf) | {"WIN": 0}
    while True:
        new = {pos: (min if pos[3] else max)((c + x[s] for c, s in succ), default=math.inf)
               for pos, succ in graph.items()} | {"WIN": 0}
        if new == x:
            return x[start]
        x = new


#: Motions over l1..l3 with one grasp `top` for objects a, b, c: a and b have
#: the same rows (interchangeable), c's carries cost more.
ALIKE_MOTIONS = {
    ("empty", "home", "l1/top"): 3, ("empty", "home", "l2/top"): 4, ("empty", "home", "l3/top"): 5,
    ("empty", "l1/top", "l2/top"): 1, ("empty", "l2/top", "l1/top"): 1,
    ("empty", "l1/top", "l3/top"): 2, ("empty", "l3/top", "l1/top"): 2,
    ("empty", "l2/top", "l3/top"): 1, ("empty", "l3/top", "l2/top"): 1,
    **{(f"{o}/top", f"l{i}/top", f"l{j}/top"): (7 if o == "c" else 2)
       for o in "abc" for i in range(1, 4) for j in range(1, 4) if i != j},
}


class TickClock:
    """A clock that ticks once per look: deadlines fall after a known number
    of looks, whatever the machine's speed (patched over time.perf_counter)."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        self.now += 1.0
        return self.now


def cut_answer(monkeypatch, scene, k, chunk, limit, **andor_settings):
    """`solve_andor` with a time limit, its questions cut every `chunk` steps and
    its clock ticking once per look (`TickClock`); `andor_settings` are set on
    the module for the call (e.g. REPLAN_SHARE).  The kernels are warmed up
    first: `prepare` solves a warm-up game with no deadline, which in chunks
    of a few steps would take hours (a test run alone hung there)."""
    from symsynth.solvers import andor

    andor.prepare()
    monkeypatch.setattr(andor, "CHUNK", chunk)
    for name, value in andor_settings.items():
        monkeypatch.setattr(andor, name, value)
    monkeypatch.setattr(andor.time, "perf_counter", TickClock())
    try:
        return andor.solve_andor(scene, k=k, time_limit=limit)
    finally:
        monkeypatch.undo()


def enumerated_bounds(seeds, base):
    """(seed, scene, k, formula, the replanning bound by enumeration) over
    `planning_scene`s, k = 1 + seed % 3; scenes with a zero-cost move
    (slides: the k = 0 search does not answer them) left out."""
    from symsynth.game.solution import OutOfReach
    from symsynth.logic import parse_ltlf
    from symsynth.solvers.replan import replanning_bound

    for seed in seeds:
        scene = planning_scene(seed, base)
        k = 1 + seed % 3
        formula = parse_ltlf(scene.task)
        try:
            yield seed, scene, k, formula, replanning_bound(scene, formula, k)
        except OutOfReach:
            continue


def planning_scene(seed, base):
    """A generated scene for the replanning bound's tests: alike objects (with
    contacts every eighth) at every fourth seed, else a random one from base + seed."""
    from symsynth.testing.gamegen import alike_scene, random_scene

    if seed % 4 == 0:
        return alike_scene(seed, contacts=seed % 8 == 0)
    return random_scene(base + seed, positive=True, contacts=seed % 3 == 0)


def explicit_and_paid(scene, formula, k, strategy):
    """(E_p by the explicit solver, what `strategy` pays against the worst human
    there): the replanning tests' check of a strategy behind an upper end."""
    import dataclasses

    from symsynth.solvers.explicit import solve_explicit

    exact = solve_explicit(scene, k=k)
    return exact.units, worst_case_of(scene, dataclasses.replace(exact, strategy=strategy), formula)


def asked_least(scene, formula, k, oracle=None):
    """(the replanning question on the scene, with `oracle` when given, and
    B_k found by bisection over it in [0, 5000]); None when the k = 0 search
    does not answer the game (a zero-cost move) or B_k is infinite."""
    from symsynth.game.solution import OutOfReach
    from symsynth.solvers.replan_budget import BudgetedBound

    try:
        asked = BudgetedBound(scene, formula, k, oracle=oracle)
        upper = asked.least(0, 5000)
    except OutOfReach:
        return None
    return None if upper == math.inf else (asked, upper)
