"""Strategy files of the objectives beyond the worst case (semantics §9),
format `symsynth.objective-strategy/1`: what `solve --objective ... -o`
writes, certified again when read.

Like `symsynth.strategy/1` (`game.strategy`: the same header fields, the
same position fields), plus the objective and, per objective::

    {"format": "symsynth.objective-strategy/1", "objective": "expected",
     "human_model": "random(0.3)", "budget_units": 21, "expected_cost": 11.3,
     "waiting": 42, "epsilon": 1e-06, "waiting_bound": 11.300001, ...,
     "positions": [{"at": ..., "q": ..., "h": 1, "left": 17, "action": "transit(b,side)"}, ...],
     "worst": [{"at": ..., "q": ..., "h": 1, "action": "grab(b)"}, ...]}

- `expected`: a position's entry is for the budget `left` (units) the robot
  still has there: the strategy keeps that counter as its memory.  When
  `waiting` is a number n (EX is an infimum, approached by waiting), the
  robot plays `positions` for its first n turns and then the worst-case
  strategy of `worst`, which wins within what is left; `waiting_bound` is
  the expected cost that guarantees (within `epsilon` of EX).  `waiting`
  null: `positions` alone win every play within the budget.
- `best-effort`: every position the strategy reaches, with its `class`
  (`winning` or `cooperative`; losing positions are not listed: nothing is
  kept there), `cooperative` (C there, units) and `steps` (the robot moves
  of that cheapest cooperative play), and the action: the worst-case
  strategy's at winning positions, the cheapest cooperative play's at
  cooperative ones.

`certify` follows the strategy through every human behaviour in the game
(`game.graph`), not trusting the solver: for `expected`, every play wins
within the budget (the counter never goes below 0); for `best-effort`,
from a winning position every play stays winning and wins, and at a
cooperative one the action leads to a reply whose listed C and steps are
what the entry claims minus the action (so a play with a cooperating human
wins at cost C, in `steps` moves): no robot move lowers the class.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symsynth.errors import InputError
from symsynth.files import write_atomic
from symsynth.game.abstraction import State, initial_state, state_json
from symsynth.game.graph import GameGraph, Node
from symsynth.game.solution import Position
from symsynth.game.strategy import StrategyFile, check_header, format_position
from symsynth.scene.model import Scene
from symsynth.scene.yamlpos import read_json

FORMAT = "symsynth.objective-strategy/1"
HEADER = ("objective", "scene", "task", "k", "resolution", "human_model", "budget_units", "expected_cost",
          "waiting", "epsilon", "waiting_bound", "cooperative_cost", "class", "objects", "dfa")


@dataclass
class ObjectiveStrategyFile:
    header: dict[str, Any]
    #: expected: (position, budget left) -> action; best effort: position -> action
    positions: dict[Any, str] = field(default_factory=dict)
    worst: dict[Position, str] = field(default_factory=dict)
    #: best effort: position -> (class, C units, steps)
    claims: dict[Position, tuple[str, int | None, int | None]] = field(default_factory=dict)

    @property
    def objects(self) -> tuple[str, ...]:
        return tuple(self.header["objects"])

    def as_table(self) -> StrategyFile:
        """The header as `game.strategy` reads it, for `check_header`."""
        h = self.header
        return StrategyFile(scene=h["scene"], task=h["task"], k=h["k"], resolution=h["resolution"], units=None,
                            cost_bound=None, objects=self.objects, dfa_bits=tuple(h["dfa"]["bits"]),
                            dfa_initial=tuple(bool(b) for b in h["dfa"]["initial"]), positions={}, budgets={},
                            dfa_numbering=h["dfa"].get("numbering", 1))


def write_objective_strategy(path: str | Path, table: ObjectiveStrategyFile) -> int:
    """Write `table` (one entry a line); the number of entries written."""
    objects = table.objects
    lines = []
    for key, action in table.positions.items():
        position, extra = (key[0], {"left": key[1]}) if table.header["objective"] == "expected" else (key, {})
        if position in table.claims:
            cls, c, steps = table.claims[position]
            extra |= {"class": cls, "cooperative": c, "steps": steps}
        lines.append(_entry(position, objects) | extra | {"action": action})
    worst = [_entry(p, objects) | {"action": a} for p, a in table.worst.items()]
    header = {"format": FORMAT} | {k: table.header.get(k) for k in HEADER}
    text = json.dumps(header, indent=1)[:-2] + ',\n "positions": [' + ",".join(
        "\n  " + json.dumps(e) for e in lines) + "\n ],\n \"worst\": [" + ",".join(
        "\n  " + json.dumps(e) for e in worst) + "\n ]\n}\n"
    write_atomic(path, text, "strategy file")
    return len(lines) + len(worst)


def _entry(position: Position, objects: tuple[str, ...]) -> dict[str, Any]:
    v, q, h = position
    return state_json(v, objects) | {"q": [int(b) for b in q], "h": h}


def read_objective_strategy(path: str | Path) -> ObjectiveStrategyFile:
    data = read_json(path, "strategy file")
    problems = []
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"{path}: not a {FORMAT} file (format: {FORMAT!r} expected)")
    for key in (*HEADER, "positions", "worst"):
        if key not in data:
            problems.append(f"{key} is required")
    if data.get("objective") not in ("expected", "best-effort"):
        problems.append(f"objective: expected 'expected' or 'best-effort', found {data.get('objective')!r}")
    if problems:
        raise InputError(f"{path}: not a valid {FORMAT} file:\n" + "\n".join(f"  {p}" for p in problems))
    objects = tuple(data["objects"])
    table = ObjectiveStrategyFile({k: data[k] for k in HEADER})
    try:
        for i, e in enumerate(data["positions"]):
            p = _position(e, objects)
            if data["objective"] == "expected":
                table.positions[(p, int(e["left"]))] = e["action"]
            else:
                table.positions[p] = e["action"]
                table.claims[p] = (e["class"], e["cooperative"], e["steps"])
        for e in data["worst"]:
            table.worst[_position(e, objects)] = e["action"]
    except (KeyError, TypeError, ValueError) as error:
        raise InputError(f"{path}: not a valid {FORMAT} file: an entry lacks or garbles {error}") from None
    return table


def _position(e: dict[str, Any], objects: tuple[str, ...]) -> Position:
    ee = tuple(e["ee"]) if isinstance(e["ee"], list) else e["ee"]
    return State(tuple(e["at"][o] for o in objects), e["grip"], ee), tuple(bool(b) for b in e["q"]), int(e["h"])


def certify_objective(scene: Scene, table: ObjectiveStrategyFile) -> int:
    """Check the file against the game (see the module doc); the number of
    robot turns checked.  The first failure is an `InputError`."""
    formula = check_header(scene, table.as_table())
    h = table.header
    game = GameGraph(scene, formula, h["resolution"])
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return 0
    start = Node(v0, q0, h["k"], False)
    if h["objective"] == "expected" and h["expected_cost"] is None:
        if table.positions or table.worst:
            raise InputError("it says EX is undefined (expected_cost null) but lists positions")
        return 0
    if h["objective"] == "expected":
        return _certify_expected(game, table, start)
    return _certify_best_effort(game, table, start)


def robot_moves_at(game: GameGraph, position: Position) -> dict[str, tuple[Node | None, int]]:
    """The robot's moves at a robot-turn position: action -> (the human turn
    after it, None when it wins; its cost in units)."""
    v, q, k = position
    return {a: (after, units) for a, after, units, _ in game.moves(Node(v, q, k, True))}


def _replies(game: GameGraph, node: Node | None) -> list[Position | None]:
    """The robot positions after each human choice at `node` (None: won)."""
    if node is None:
        return [None]
    return [None if n is None else (n.v, n.q, n.h) for _, n, _, _ in game.moves(node)]


def _certify_expected(game: GameGraph, table: ObjectiveStrategyFile, start: Node) -> int:
    h, objects = table.header, table.objects
    n = h["waiting"]
    done: dict[tuple, int] = {}
    path: set[tuple] = set()

    def robot(p: Position, left: int, turns: int) -> int:
        key = (p, left, turns)
        if key in done:
            return done[key]
        if key in path:
            raise InputError(f"it does not win: its plays go in circles at {format_position(p, objects)}")
        path.add(key)
        worst_mode = n is not None and turns >= n
        action = table.worst.get(p) if worst_mode else table.positions.get((p, left))
        if action is None:
            raise InputError(f"it has no action at {format_position(p, objects)} with {left} units left"
                             + (" (worst-case part)" if worst_mode else ""))
        moves = robot_moves_at(game, p)
        if action not in moves:
            raise InputError(f"it plays {action!r} at {format_position(p, objects)}, where the robot can only "
                             f"{', '.join(moves) or 'do nothing'}")
        after, units = moves[action]
        if units > left:
            raise InputError(f"its play {action!r} at {format_position(p, objects)} costs {units} units with "
                             f"only {left} left of the budget")
        nxt = turns + 1 if n is not None else 0
        cost = units + max((robot(r, left - units, min(nxt, n if n is not None else 0)) if r is not None else 0)
                           for r in _replies(game, after))
        path.discard(key)
        done[key] = cost
        return cost

    budget = h["budget_units"]
    try:
        worst = max(robot(r, budget, 0) if r is not None else 0 for r in _replies(game, start))
    finally:
        del robot  # the closure refers to itself: no cycle left to keep the DFA's BDDs alive
    if worst > budget:
        raise InputError(f"a play costs {worst} units, more than the budget {budget}")
    return len(done)


def _certify_best_effort(game: GameGraph, table: ObjectiveStrategyFile, start: Node) -> int:
    objects = table.objects
    claims: Mapping[Position, tuple[str, int | None, int | None]] = table.claims
    seen: set[Position] = set()
    todo = [r for r in _replies(game, start) if r is not None]
    winning_path: set[Position] = set()
    settled: set[Position] = set()

    def claim(r: Position | None) -> tuple[str, int, int] | None:
        if r is None:
            return "winning", 0, 0
        got = claims.get(r)
        return None if got is None or got[1] is None or got[2] is None else (got[0], got[1], got[2])

    def wins(p: Position) -> None:  # every play from a winning position stays winning and wins
        if p in settled:
            return
        if p in winning_path:
            raise InputError(f"it does not win from {format_position(p, objects)}: its plays go in circles")
        winning_path.add(p)
        action = table.positions.get(p)
        if action is None or claims.get(p, ("",))[0] != "winning":
            raise InputError(f"it reaches {format_position(p, objects)} from a winning position, but lists "
                             "no winning action there")
        moves = robot_moves_at(game, p)
        if action not in moves:
            raise InputError(f"it plays {action!r} at {format_position(p, objects)}, not available there")
        for r in _replies(game, moves[action][0]):
            if r is not None:
                wins(r)
        winning_path.discard(p)
        settled.add(p)

    try:
        _cooperative_walk(game, table, todo, seen, claim, wins)
    finally:
        del wins  # the closure refers to itself: no cycle left to keep the DFA's BDDs alive
    return len(seen)


def _cooperative_walk(game: GameGraph, table: ObjectiveStrategyFile, todo: list[Position], seen: set[Position],
                      claim: Any, wins: Any) -> None:
    objects, claims = table.objects, table.claims
    while todo:
        p = todo.pop()
        if p in seen:
            continue
        seen.add(p)
        if p not in claims:
            continue  # not listed: losing, nothing to keep (a false claim shows where it is listed)
        cls, c, steps = claims[p]
        if cls == "winning":
            wins(p)
            continue
        action = table.positions[p]
        moves = robot_moves_at(game, p)
        if action not in moves:
            raise InputError(f"it plays {action!r} at {format_position(p, objects)}, not available there")
        after, units = moves[action]
        replies = _replies(game, after)
        best = [x for r in replies if (x := claim(r)) is not None]
        if c is None or steps is None or not any(x[1] + units == c and x[2] + 1 == steps for x in best):
            raise InputError(f"at {format_position(p, objects)} it claims a cooperative play of cost {c} in "
                             f"{steps} moves, but no reply after {action!r} continues one (the class would drop)")
        todo += [r for r in replies if r is not None]
