"""The explicit solver: the game of semantics §6 position by position.

It searches the graph of positions (`game.graph`: `(v, q, h, robot)`,
every accepting move leading to WIN).  The value is the least fixpoint of

    val(WIN) = 0
    val(robot position p) = min over actions p -a-> p' of cost(a) + val(p')
    val(human position p) = max over pass and moves p -> p' of val(p')

computed with Dijkstra's algorithm for min-cost reachability games with
non-negative weights (Khachiyan et al., 2008): positions settle in order of
value; a robot position settles with its best settled successor, a human
position once all its successors have settled, with the last (largest)
value.  Positions that never settle have infinite value: the human can keep
the robot from winning, if need be by passing forever.  A robot position's
strategy edge leads to a position settled before it, so following the
strategy always reaches WIN, zero-cost actions included.
"""

from __future__ import annotations

import heapq
import time


from symsynth.game.abstraction import in_costmap_units, initial_state
from symsynth.game.graph import PASS, START, WIN, Edge, GameGraph, Node
from symsynth.game.solution import (Solution, Step, check_parameters, task_formula, verdict,
                                   won_at_start)
from symsynth.logic import ast
from symsynth.scene.model import Scene


def solve_explicit(scene: Scene, formula: str | ast.Formula | None = None, *,
                   k: int | None = None, budget: float | None = None,
                   resolution: float = 1.0, symmetric: bool = True) -> Solution:
    """E_p, a strategy and plays for `formula` (default: the scene's task)
    against a human with `k` moves (default: the scene's k); with
    `symmetric`, on canonical positions (`game.symmetry`)."""
    k = check_parameters(scene, k, resolution)
    clock = time.perf_counter()
    game = GameGraph(scene, task_formula(scene, formula), resolution, symmetric=symmetric)
    seconds = {"dfa": time.perf_counter() - clock}

    clock = time.perf_counter()
    v0 = game.canon(initial_state(scene))
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):  # ρ(v0) alone is accepted
        return won_at_start(scene, k, resolution, budget, seconds | {"explore": 0.0, "solve": 0.0})
    nodes, edges = game.explore(Node(v0, q0, k, False))
    seconds["explore"] = time.perf_counter() - clock

    clock = time.perf_counter()
    value, choice = _dijkstra(nodes, edges)
    strategy = {(n.v, n.q, n.h): edges[i][e].action for i, e in choice.items() if (n := nodes[i]) is not None}
    units = value.get(START)
    realizable = verdict(units, resolution, budget)
    principal: tuple[Step, ...]
    counter: tuple[Step, ...] | None
    if units is None:
        principal, counter = (), _counter_play(nodes, edges, value, resolution)
    else:  # over budget, the principal play is the human's winning answer
        principal = _principal_play(nodes, edges, value, choice, resolution)
        counter = principal if realizable is False else None
    seconds["solve"] = time.perf_counter() - clock
    solution = Solution(None if units is None else in_costmap_units(units, resolution), units, resolution, budget,
                        realizable, k, len(nodes) - 1, seconds, strategy, principal, counter,
                        scene.object_names)
    return solution if game.symmetry is None else game.symmetry.realize(solution)


def _dijkstra(nodes: list[Node | None], edges: list[list[Edge]]) -> tuple[dict[int, int], dict[int, int]]:
    """Settled values (units) and, for robot positions, the chosen edge index."""
    robot = _robot_turns(nodes)
    preds: list[list[tuple[int, int]]] = [[] for _ in nodes]
    for i, out in enumerate(edges):
        for e, edge in enumerate(out):
            preds[edge.target].append((i, e))
    waiting = [len(out) for out in edges]  # human positions: unsettled successors
    best: dict[int, tuple[int, int]] = {}  # robot positions: (value, edge) so far
    value: dict[int, int] = {}
    choice: dict[int, int] = {}
    heap = [(0, WIN)]
    while heap:
        d, j = heapq.heappop(heap)
        if j in value:
            continue
        value[j] = d
        if robot[j]:
            choice[j] = best[j][1]
        for i, e in preds[j]:
            if i in value:
                continue
            if robot[i]:
                candidate = d + edges[i][e].units
                if i not in best or candidate < best[i][0]:
                    best[i] = (candidate, e)
                    heapq.heappush(heap, (candidate, i))
            else:
                waiting[i] -= 1
                if waiting[i] == 0:  # d is the largest value of its successors
                    heapq.heappush(heap, (d, i))
    return value, choice


def _principal_play(nodes: list[Node | None], edges: list[list[Edge]], value: dict[int, int],
                    choice: dict[int, int], resolution: float) -> tuple[Step, ...]:
    """The strategy against the human's worst replies (argmax; a pass on ties,
    then the first move), from the initial position to the win."""
    robot = _robot_turns(nodes)
    play = []
    i = START
    while i != WIN:
        if robot[i]:
            edge = edges[i][choice[i]]
            play.append(Step("robot", edge.action, in_costmap_units(edge.units, resolution), edge.state))
        else:  # edges[i][0] is the pass; max() keeps the first of equal values
            edge = max(edges[i], key=lambda x: value[x.target])
            if edge.action != PASS:
                play.append(Step("human", edge.action, 0.0, edge.state))
        i = edge.target
    return tuple(play)


def _counter_play(nodes: list[Node | None], edges: list[list[Edge]], value: dict[int, int],
                  resolution: float) -> tuple[Step, ...]:
    """A play from the initial position where the robot never wins: the human
    keeps to positions of infinite value (passing when that does), the robot
    takes its cheapest action.  It ends where the robot has no available
    action, or with the step that comes back to a position already visited
    (from there the robot goes in circles)."""
    robot = _robot_turns(nodes)
    play = []
    i, seen = START, set()
    while i not in seen:
        seen.add(i)
        if robot[i]:
            if not edges[i]:
                break
            edge = min(edges[i], key=lambda x: x.units)
        else:
            edge = next(x for x in edges[i] if x.target not in value)
        if edge.action != PASS:
            who = "robot" if robot[i] else "human"
            play.append(Step(who, edge.action, in_costmap_units(edge.units, resolution), edge.state))
        i = edge.target
    return tuple(play)


def _robot_turns(nodes: list[Node | None]) -> list[bool]:
    """Whose turn each position is (True: the robot's); WIN (None) is no one's."""
    return [node is not None and node.robot for node in nodes]
