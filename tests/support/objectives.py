"""An independent reference for semantics §9: EX_μ(B) under random(P), the
class of the initial position and its cooperative cost C.

It reads the game through `games.game_graph` (positions (v, q, h, robot's
turn) with their successors as (units, position or "WIN"), built from
`game.abstraction` and the DFA, not from `game.graph` or any solver), writes
the model random(P) out again, and iterates the equations of §9 from +inf,
position by position, in plain Python:

- V: min at robot turns, max at human turns, from +inf until nothing
  changes (integers: it reaches the fixpoint);
- C: min at both, from +inf until nothing changes;
- EX: for each budget level b = 0..B in turn, at robot turns the min over
  moves a with cost(a) + V(after a) <= b of cost(a) + Y_{b - cost}(after),
  at human turns the model's mean, iterated from +inf until no value moves
  by more than `TOLERANCE` (zero-cost moves make the level a system whose
  limit is approached, not reached: no search over simple paths can find
  it).
"""

from __future__ import annotations

import math
from fractions import Fraction

from tests.support.games import game_graph

WIN = "WIN"
TOLERANCE = 1e-14


def worst_values(graph):
    x = dict.fromkeys(graph, math.inf) | {WIN: 0}
    while True:
        new = {p: (min if p[3] else max)((c + x[s] for c, s in succ), default=math.inf)
               for p, succ in graph.items()} | {WIN: 0}
        if new == x:
            return x
        x = new


def cooperative_values(graph):
    x = dict.fromkeys(graph, math.inf) | {WIN: 0}
    while True:
        new = {p: min((c + x[s] for c, s in succ), default=math.inf) for p, succ in graph.items()} | {WIN: 0}
        if new == x:
            return x
        x = new


def human_shares(position, succ, probability):
    """random(P) at a human turn: (probability, successor) for the pass and each move."""
    pass_, moves = succ[0], succ[1:]
    if position[2] > 0 and moves:
        return [(1 - probability, pass_[1])] + [(probability / len(moves), s) for _, s in moves]
    return [(1.0, pass_[1])]


def expected_value(graph, start, budget, probability, V):
    """EX at the start with `budget` units, by levels from +inf."""
    robot = [p for p in graph if p[3]]
    human = [p for p in graph if not p[3]]
    X: dict = {}  # (robot position, b) -> value
    Y: dict = {}  # (human position, b)
    shares = {p: human_shares(p, graph[p], float(probability)) for p in human}

    def y(p, b):
        if p == WIN:
            return 0.0
        return Y[(p, b)]

    def x(p, b):
        return 0.0 if p == WIN else X[(p, b)]

    for b in range(budget + 1):
        for p in robot:
            X[(p, b)] = math.inf
        for p in human:
            Y[(p, b)] = math.inf
        while True:
            moved = 0.0
            for p in robot:
                best = math.inf
                for c, s in graph[p]:
                    if c + V[s] <= b:
                        best = min(best, c + y(s, b - c))
                old = X[(p, b)]
                X[(p, b)] = best
                moved = max(moved, _change(old, best))
            for p in human:
                if V[p] > b:
                    continue
                value = sum(w * x(s, b) for w, s in shares[p] if w > 0)
                old = Y[(p, b)]
                Y[(p, b)] = value
                moved = max(moved, _change(old, value))
            if moved <= TOLERANCE:
                break
    return Y[(start, budget)]


def _change(old, new):
    if old == new:
        return 0.0
    if math.isinf(old) or math.isinf(new):
        return math.inf
    return abs(old - new) / max(1.0, abs(new))


def reference(scene, formula, k, probability=Fraction(3, 10), budget=None):
    """{"E_p", "class", "C", "EX", "B"} for the initial position (units;
    None where infinite or undefined); `budget` in units (default E_p)."""
    start, graph = game_graph(scene, formula, k)
    if start is None:
        return {"E_p": 0, "class": "winning", "C": 0, "EX": 0.0, "B": budget or 0}
    V = worst_values(graph)
    C = cooperative_values(graph)
    e_p = None if math.isinf(V[start]) else V[start]
    cls = "winning" if e_p is not None else "losing" if math.isinf(C[start]) else "cooperative"
    out = {"E_p": e_p, "class": cls, "C": None if math.isinf(C[start]) else C[start]}
    B = e_p if budget is None else budget
    out["B"] = B
    out["EX"] = None if e_p is None or B < e_p else expected_value(graph, start, B, probability, V)
    return out
