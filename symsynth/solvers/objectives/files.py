"""An objective's strategy as a `symsynth.objective-strategy/1` table
(`game.objective_strategy`): the turns a play of it can reach, by name."""

from __future__ import annotations

import math
from typing import Any

from symsynth.automata import NUMBERING
from symsynth.automata.shared import dfa_of
from symsynth.game.objective_strategy import ObjectiveStrategyFile
from symsynth.game.solution import Position
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.objectives import ObjectiveSolution
from symsynth.solvers.objectives.arena import INF, Arena
from symsynth.solvers.objectives.play import ExpectedStrategy, Strategy, replies
from symsynth.solvers.objectives.walk import Turns


def objective_table(scene: Scene, task: str, formula: ast.Formula, s: ObjectiveSolution) -> ObjectiveStrategyFile:
    """The table of `s`'s strategy (solved on the explicit solver's graph,
    whose turns have names)."""
    dfa = dfa_of(formula)
    header: dict[str, Any] = {
        "objective": s.objective, "scene": scene.name, "task": task.strip(), "k": s.k,
        "resolution": s.resolution, "human_model": s.human_model, "budget_units": s.budget_units,
        "expected_cost": s.expected_cost, "waiting": None if s.attained else s.waiting, "epsilon": s.epsilon,
        "waiting_bound": s.waiting_bound, "cooperative_cost": s.cooperative_cost, "class": s.position_class,
        "objects": list(scene.object_names),
        "dfa": {"bits": list(dfa.bits), "initial": [int(b) for b in dfa.initial], "numbering": NUMBERING}}
    table = ObjectiveStrategyFile(header)
    if (s.expected_cost is None and s.objective == "expected") or s.arena is None:
        return table  # nothing to play: undefined, or the task holds at the start
    arena = s.arena
    if not arena.positions:
        raise ValueError("a strategy table needs the explicit solver's arena, whose turns have names")
    strategy = s.strategy()
    if isinstance(strategy, ExpectedStrategy):
        _expected_turns(arena, strategy, s.reached(), table)
    else:
        _best_effort_turns(arena, strategy, s.classes(), table)
    return table


def _name(arena: Arena, e: int) -> str:
    return arena.names[int(arena.r_name[e])]


def _expected_turns(arena: Arena, strategy: ExpectedStrategy, turns: Turns, table: ObjectiveStrategyFile) -> None:
    switched = strategy.waiting is not None
    for i, b, w, e in zip(turns.node.tolist(), turns.budget.tolist(), turns.count.tolist(), turns.move.tolist()):
        position: Position = arena.positions[i]
        if switched and w >= strategy.waiting:
            table.worst[position] = _name(arena, e)
        else:
            table.positions[(position, b)] = _name(arena, e)


def _best_effort_turns(arena: Arena, strategy: Strategy, classes: Any, table: ObjectiveStrategyFile) -> None:
    n = arena.size
    reached: list[int] = []
    seen: set[int] = set()
    todo = [j for j in replies(arena, 0) if j >= 0]
    while todo:
        i = todo.pop()
        if i in seen or classes[n + i] == 2:
            continue
        seen.add(i)
        reached.append(i)
        t = int(arena.r_tgt[strategy.move((i, 0, 0))])
        if t >= 0:
            todo += [j for j in replies(arena, t) if j >= 0]
    # C and steps of the strategy's own cooperative plays: from above until nothing falls
    claim: dict[int, tuple[float, float]] = {i: (math.inf, math.inf) for i in reached}
    changed = True
    while changed:
        changed = False
        for i in reached:
            e = strategy.move((i, 0, 0))
            c, t = int(arena.r_units[e]), int(arena.r_tgt[e])
            best = min([(0.0, 0.0)] if t < 0 else [claim.get(j, (math.inf, math.inf)) if j >= 0 else (0.0, 0.0)
                                                    for j in replies(arena, t)])
            new = (c + best[0], 1 + best[1])
            if new < claim[i]:
                claim[i], changed = new, True
    for i in reached:
        e = strategy.move((i, 0, 0))
        position: Position = arena.positions[i]
        table.positions[position] = _name(arena, e)
        cost, steps = claim[i]
        table.claims[position] = ("winning" if arena.rval[i] < INF else "cooperative",
                                  None if math.isinf(cost) else int(cost), None if math.isinf(steps) else int(steps))


def to_pay_by_position(s: ObjectiveSolution) -> dict[tuple[Position, int, int], int]:
    """`play.still_to_pay` of the expected-cost strategy of `s` (solved on
    the explicit solver's graph), keyed by (position, budget left, count)."""
    if s.arena is None or s.expected_cost is None:
        return {}
    names = s.arena.positions
    turns = s.reached()
    return {(names[i], b, w): cost for i, b, w, cost in
            zip(turns.node.tolist(), turns.budget.tolist(), turns.count.tolist(), turns.worst.tolist())}
