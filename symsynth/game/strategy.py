"""The strategy file, format `symsynth.strategy/1`: what `solve -o` writes and
the simulator reads back.

The file lists every robot-turn position reachable from the initial one when
the robot follows the strategy and the human does anything legal (semantics §6),
each with the robot's action there::

    {"format": "symsynth.strategy/1",
     "scene": "pick", "task": "F(at(b, l2))", "k": 1,
     "resolution": 1.0, "units": 34, "cost_bound": 34.0,
     "objects": ["b"],
     "dfa": {"bits": ["#q0_0", "#q0_1"], "initial": [0, 0], "numbering": 3},
     "positions": [
      {"at": {"b": "l1"}, "grip": null, "ee": "Else", "q": [0, 1], "h": 1,
       "action": "transit(b,top)", "budget": 34.0},
      ...]}

- `units` and `cost_bound` are E_p in units of `resolution` and in costmap
  units; both null when no strategy wins (then `positions` is empty, as it
  is when the task holds in the initial state).
- `objects` orders the objects; every position's `at` names each of them.
- `dfa.bits` names the state bits of `compile_ltlf(task)` in order and
  `dfa.initial` is its initial state; a position's `q` is the DFA state
  after the trace so far, one 0/1 per bit.  A reader compiles the task and
  compares the bits before it trusts `q`.  `dfa.numbering` is the version
  of the compiler's state numbering (`symsynth.automata.NUMBERING`) the
  codes come from; a file without it predates the field (numbering 1).
- `grip` is a grasp or null (hand empty); `ee` is "Else", a location, or
  `[object, grasp]`; `h` is the number of human moves left.
- `budget` is the most the strategy can still spend, in costmap units, from
  this position to the win against any human: a run with that much left is
  sure to finish within it.  Null when the strategy does not win from there
  (it goes in circles), which a correct solver never produces.

Positions where the DFA has accepted are wins and are not listed.
"""

from __future__ import annotations

import json
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import jsonschema
from tqdm import tqdm

from symsynth.errors import InputError, SymsynthError
from symsynth.files import write_atomic
from symsynth.game.abstraction import (State, in_costmap_units, initial_state, robot_moves, state_json,
                                       state_problems)
from symsynth.automata import NUMBERING
from symsynth.automata.shared import dfa_of
from symsynth.game.graph import GameGraph, Node
from symsynth.scene.propositions import interpret_all
from symsynth.game.solution import Position, Solution
from symsynth.logic import ast, parse_ltlf
from symsynth.scene.model import Scene
from symsynth.scene.yamlpos import read_json

FORMAT = "symsynth.strategy/1"


class InconsistentStrategy(ValueError):
    """A strategy with no action, or an unavailable one, at a reachable
    position: a solver bug, not an input error."""


class MissingPosition(LookupError):
    """A position the strategy file has no action for."""


class Choice(NamedTuple):
    """The robot's move at a position and where it can lead."""

    action: str
    units: int  # the action's cost, quantized
    replies: tuple[Position, ...]  # robot positions after each human answer; () when it wins


# -- the positions a strategy reaches -----------------------------------------

def reachable_positions(scene: Scene, formula: str | ast.Formula,
                        solution: Solution) -> dict[Position, Choice]:
    """The robot-turn positions reachable under `solution.strategy`, in
    breadth-first order, each with the strategy's choice there.

    Only positions reached are looked up in the strategy, so it may compute
    its entries lazily.  Empty when no strategy wins (`cost_bound` is None)
    or the task holds in the initial state.
    """
    if isinstance(formula, str):
        formula = parse_ltlf(formula, source=f"{scene.name} (task)")
    if solution.cost_bound is None:
        return {}
    return _explore(GameGraph(scene, formula, solution.resolution), solution.strategy, solution.k,
                    solution.objects)


def _explore(game: GameGraph, strategy: Mapping[Position, str], k: int,
             objects: tuple[str, ...]) -> dict[Position, Choice]:
    """Breadth-first from the initial position, human first (semantics §6)."""
    v0 = initial_state(game.scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return {}
    choices: dict[Position, Choice] = {}
    start = _human_turn(game, Node(v0, q0, k, robot=False))
    queue = deque(start)
    seen = set(start)
    # delay: no bar unless it takes a while; disable=None: none when not a terminal
    with tqdm(desc="strategy positions", unit=" pos", delay=2.0, leave=False, disable=None) as bar:
        while queue:
            position = queue.popleft()
            choices[position] = choice = _follow(game, position, strategy, objects)
            for reply in choice.replies:
                if reply not in seen:
                    seen.add(reply)
                    queue.append(reply)
            bar.update()
    return choices


def _human_turn(game: GameGraph, node: Node) -> tuple[Position, ...]:
    """The robot positions after the human's pass or any of its moves;
    moves that make the DFA accept are wins, left out."""
    return tuple((n.v, n.q, n.h) for _, n, _, _ in game.moves(node) if n is not None)


def _follow(game: GameGraph, position: Position, strategy: Mapping[Position, str],
            objects: tuple[str, ...]) -> Choice:
    v, q, h = position
    try:
        action = strategy[position]
    except KeyError:
        raise InconsistentStrategy(f"the strategy has no action at reachable position "
                                   f"{format_position(position, objects)}") from None
    moves = {a: (after, units) for a, after, units, _ in game.moves(Node(v, q, h, robot=True))}
    if action not in moves:
        raise InconsistentStrategy(
            f"the strategy plays {action!r} at {format_position(position, objects)}, "
            f"where the robot can only {', '.join(moves) or 'do nothing'}")
    after, units = moves[action]
    return Choice(action, units, () if after is None else _human_turn(game, after))


def guaranteed_units(scene: Scene, formula: ast.Formula, solution: Solution) -> int | None:
    """The most units `solution.strategy` can spend from the initial
    position against any human, found by following it through every human
    behaviour in the real game (not by trusting the solver); None when it
    can go in circles.  0 when the task holds at the start."""
    game = GameGraph(scene, formula, solution.resolution)
    choices = _explore(game, solution.strategy, solution.k, scene.object_names)
    if not choices:
        return 0
    worst = worst_units(choices)
    v0 = initial_state(scene)
    start = _human_turn(game, Node(v0, game.read(game.dfa.initial, v0), solution.k, robot=False))
    values = [x for p in start if (x := worst[p]) is not None]
    return None if len(values) < len(start) else max(values, default=0)


def worst_units(choices: Mapping[Position, Choice]) -> dict[Position, int | None]:
    """For each position, the most units the strategy spends from there to the
    win against any human: its action's units plus the worst reply's.  None
    for positions from which the strategy can go in circles.

    Positions are settled once all their replies are (Kahn's algorithm on the
    reversed graph), so a position on or before a cycle is never settled.
    """
    waiting = {p: len(set(c.replies)) for p, c in choices.items()}
    askers: dict[Position, list[Position]] = {}
    for p, c in choices.items():
        for reply in set(c.replies):
            askers.setdefault(reply, []).append(p)
    worst: dict[Position, int] = {}
    ready = deque(p for p, n in waiting.items() if n == 0)
    while ready:
        p = ready.popleft()
        worst[p] = choices[p].units + max((worst[r] for r in choices[p].replies), default=0)
        for asker in askers.get(p, ()):
            waiting[asker] -= 1
            if waiting[asker] == 0:
                ready.append(asker)
    return {p: worst.get(p) for p in choices}


# -- the file ---------------------------------------------------------------

@dataclass(frozen=True)
class StrategyFile:
    """A strategy file's content, its header and position -> action: read
    back (`read_strategy`) or built without the file (`strategy_table`)."""

    scene: str
    task: str
    k: int
    resolution: float
    units: int | None
    cost_bound: float | None
    objects: tuple[str, ...]
    dfa_bits: tuple[str, ...]
    dfa_initial: tuple[bool, ...]
    positions: Mapping[Position, str]
    budgets: Mapping[Position, float | None]  # see the module docstring
    dfa_numbering: int = NUMBERING

    def lookup(self, state: State, q: tuple[bool | int, ...], h: int) -> str:
        """The action at a position; `q` may be bools or 0/1."""
        position = (state, tuple(bool(b) for b in q), h)
        if position not in self.positions:
            raise MissingPosition(f"no action for {format_position(position, self.objects)}: "
                                  "the strategy does not reach it")
        return self.positions[position]


def strategy_table(scene: Scene, formula_text: str, solution: Solution, *,
                   formula: ast.Formula | None = None) -> StrategyFile:
    """The strategy file's content without the file: every position the
    strategy reaches, its action and budget (what `read_strategy` returns
    for the file `write_strategy` writes).  `formula`: `formula_text`
    already parsed (else it is parsed here)."""
    if formula is None:
        formula = parse_ltlf(formula_text, source=f"{scene.name} (task)")
    game = GameGraph(scene, formula, solution.resolution)
    choices = {} if solution.cost_bound is None else _explore(game, solution.strategy, solution.k,
                                                               solution.objects)
    worst = worst_units(choices)
    return StrategyFile(
        scene=scene.name, task=formula_text.strip(), k=solution.k, resolution=solution.resolution,
        units=solution.units, cost_bound=solution.cost_bound, objects=scene.object_names,
        dfa_bits=tuple(game.dfa.bits), dfa_initial=tuple(bool(b) for b in game.dfa.initial),
        positions={p: c.action for p, c in choices.items()},
        budgets={p: None if (w := worst[p]) is None else in_costmap_units(w, solution.resolution) for p in choices})


def check_header(scene: Scene, table: StrategyFile) -> ast.Formula:
    """What a strategy file says of its game, against the scene: the same
    objects, a task that fits the scene, and the DFA that task compiles to.
    Returns the task's formula; every problem is in one `InputError`."""
    if table.dfa_numbering != NUMBERING:
        raise InputError(f"its DFA states are numbered by symsynth's DFA numbering {table.dfa_numbering} "
                         f"(dfa.numbering{'' if table.dfa_numbering != 1 else ' absent'}); this symsynth numbers "
                         f"them by numbering {NUMBERING}, so its q codes mean other states here: "
                         "solve again to write the strategy anew")
    problems = []
    if table.objects != scene.object_names:
        problems.append(f"its objects {', '.join(table.objects)} are not the scene's "
                        f"{', '.join(scene.object_names)}")
    try:
        formula = parse_ltlf(table.task, source="its task")
        interpret_all(formula, scene)
    except SymsynthError as error:
        problems.append(f"its task does not fit the scene: {error}")
    else:
        dfa = dfa_of(formula)  # the formula the strategy is then certified and played with
        if tuple(dfa.bits) != table.dfa_bits or tuple(dfa.initial) != table.dfa_initial:
            problems.append("its DFA (dfa.bits, dfa.initial) is not the one its task compiles to")
    if problems:
        raise InputError("; ".join(problems))
    return formula


def certify(scene: Scene, table: StrategyFile, formula: ast.Formula | None = None) -> None:
    """Check a strategy read from a file against the game it claims to win,
    before anything trusts it (the scene has its costmap): its header
    (`check_header`); every listed action is one the robot has at its
    position's state; from the initial position, the actions, followed
    through every human behaviour, are there and win within `units`; and
    every position reached carries the budget its actions guarantee from
    there.  The first thing that fails is an `InputError`.  `formula`: what
    `check_header` returned for this table (else the header is checked here)."""
    if formula is None:
        formula = check_header(scene, table)
    robot = {}
    for (v, q, h), action in table.positions.items():
        if problems := state_problems(scene, v):
            raise InputError(f"it lists {format_position((v, q, h), table.objects)}, not a state of the "
                             f"scene: {'; '.join(problems)}")
        if v not in robot:
            robot[v] = {a for a, _, _ in robot_moves(scene, v)}
        if action not in robot[v]:
            raise InputError(f"it plays {action!r} at {format_position((v, q, h), table.objects)}, where the "
                             f"robot can only {', '.join(sorted(robot[v])) or 'do nothing'}")
    if table.units is None:
        if table.positions:
            raise InputError("it says no strategy wins (units null) but lists positions")
        return
    game = GameGraph(scene, formula, table.resolution)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return
    try:
        choices = _explore(game, table.positions, table.k, table.objects)
    except InconsistentStrategy as error:
        raise InputError(f"it does not win: {error}") from None
    worst = worst_units(choices)
    starts = _human_turn(game, Node(v0, q0, table.k, robot=False))
    guaranteed = [w for p in starts if (w := worst[p]) is not None]
    if len(guaranteed) < len(starts):
        raise InputError("it does not win: its actions can go in circles")
    if max(guaranteed, default=0) > table.units:
        raise InputError(f"it claims E_p = {table.units} units, but its actions guarantee only "
                         f"{max(guaranteed)} against the worst human")
    for p in choices:
        # Every position reached from a start of finite worst case has one.
        w = worst[p]
        budget = None if w is None else in_costmap_units(w, table.resolution)
        # (files written before budgets were exact hold the float product w * resolution)
        if table.budgets.get(p) != budget and (w is None or table.budgets.get(p) != w * table.resolution):
            raise InputError(f"its budget at {format_position(p, table.objects)} is {table.budgets.get(p)}, "
                             f"but its actions guarantee {'nothing' if budget is None else f'{budget:g}'} "
                             "from there")


def write_strategy(path: str | Path, scene: Scene, formula_text: str, solution: Solution, *,
                   formula: ast.Formula | None = None) -> int:
    """Write the strategy of `solution` for `formula_text` to `path`;
    returns the number of positions written.  `formula`: `formula_text`
    already parsed (the one solved: its DFA is not compiled again)."""
    table = strategy_table(scene, formula_text, solution, formula=formula)
    header = {
        "format": FORMAT, "scene": table.scene, "task": table.task, "k": table.k,
        "resolution": table.resolution, "units": table.units, "cost_bound": table.cost_bound,
        "objects": list(table.objects),
        "dfa": {"bits": list(table.dfa_bits), "initial": [int(b) for b in table.dfa_initial],
                "numbering": table.dfa_numbering},
    }
    entries = [_position_json(p, action, table.budgets[p], table.objects)
               for p, action in table.positions.items()]
    # One position per line: the file stays short, diffable and greppable.
    text = json.dumps(header, indent=1)[:-2] + ',\n "positions": [' + ",".join(
        "\n  " + json.dumps(entry) for entry in entries) + "\n ]\n}\n"
    write_atomic(path, text, "strategy file")
    return len(entries)


def _position_json(position: Position, action: str, budget: float | None,
                   objects: tuple[str, ...]) -> dict[str, Any]:
    v, q, h = position
    return state_json(v, objects) | {"q": [int(b) for b in q], "h": h, "action": action, "budget": budget}


_NAME = {"type": "string", "minLength": 1}
_COUNT = {"type": ["integer", "null"], "minimum": 0}
_AMOUNT = {"type": ["number", "null"], "minimum": 0}
_BITS = {"type": "array", "items": {"enum": [0, 1]}}
SCHEMA: dict[str, Any] = {
    "type": "object",
    "required": ["format", "scene", "task", "k", "resolution", "units", "cost_bound",
                 "objects", "dfa", "positions"],
    "properties": {
        "format": {"const": FORMAT},
        "scene": {"type": "string"}, "task": {"type": "string"},
        "k": {"type": "integer", "minimum": 0},
        "resolution": {"type": "number", "exclusiveMinimum": 0},
        "units": _COUNT, "cost_bound": _AMOUNT,
        "objects": {"type": "array", "items": _NAME, "uniqueItems": True},
        "dfa": {"type": "object", "required": ["bits", "initial"],
                "properties": {"bits": {"type": "array", "items": _NAME}, "initial": _BITS,
                               "numbering": {"type": "integer", "minimum": 1}}},
        "positions": {"type": "array", "items": {
            "type": "object", "required": ["at", "grip", "ee", "q", "h", "action", "budget"],
            "properties": {
                "at": {"type": "object", "additionalProperties": _NAME},
                "grip": {"type": ["string", "null"]},
                "ee": {"oneOf": [_NAME, {"type": "array", "items": _NAME, "minItems": 2, "maxItems": 2}]},
                "q": _BITS, "h": {"type": "integer", "minimum": 0},
                "action": _NAME, "budget": _AMOUNT}}},
    },
}
_MAX_PROBLEMS = 10


def read_strategy(path: str | Path) -> StrategyFile:
    """Read and validate a strategy file; every problem is an `InputError`
    naming the file, the place in it and what was expected."""
    data = read_json(path, "strategy file")
    problems = [f"{_where(e.absolute_path)}: {_expected(e)}"
                for e in jsonschema.Draft202012Validator(SCHEMA).iter_errors(data)]
    if not problems:
        problems = _meaning_problems(data)
    if problems:
        shown = problems[:_MAX_PROBLEMS]
        if len(problems) > _MAX_PROBLEMS:
            shown.append(f"... and {len(problems) - _MAX_PROBLEMS} more")
        raise InputError(f"{path}: not a valid {FORMAT} file:\n" + "\n".join(f"  {p}" for p in shown))
    objects = tuple(data["objects"])
    positions: dict[Position, str] = {}
    budgets: dict[Position, float | None] = {}
    for entry in data["positions"]:
        ee = tuple(entry["ee"]) if isinstance(entry["ee"], list) else entry["ee"]
        state = State(tuple(entry["at"][o] for o in objects), entry["grip"], ee)
        position = (state, tuple(bool(b) for b in entry["q"]), entry["h"])
        positions[position] = entry["action"]
        budgets[position] = entry["budget"]
    return StrategyFile(
        scene=data["scene"], task=data["task"], k=data["k"], resolution=float(data["resolution"]),
        units=data["units"], cost_bound=data["cost_bound"], objects=objects,
        dfa_bits=tuple(data["dfa"]["bits"]), dfa_initial=tuple(bool(b) for b in data["dfa"]["initial"]),
        positions=positions, budgets=budgets, dfa_numbering=data["dfa"].get("numbering", 1))


def _meaning_problems(data: dict[str, Any]) -> list[str]:
    """What the schema cannot say: names and sizes that must agree."""
    problems = []
    objects, bits = set(data["objects"]), len(data["dfa"]["bits"])
    if len(data["dfa"]["initial"]) != bits:
        problems.append(f"dfa.initial: expected {bits} bits, one per dfa.bits, "
                        f"found {len(data['dfa']['initial'])}")
    if (data["units"] is None) != (data["cost_bound"] is None):
        problems.append("units, cost_bound: expected both null (no winning strategy) or both numbers")
    seen = set()
    for i, entry in enumerate(data["positions"]):
        where = f"positions[{i}]"
        if set(entry["at"]) != objects:
            problems.append(f"{where}.at: expected one place for each of the objects "
                            f"{', '.join(data['objects'])}, found {', '.join(entry['at']) or 'none'}")
        if len(entry["q"]) != bits:
            problems.append(f"{where}.q: expected {bits} bits, one per dfa.bits, found {len(entry['q'])}")
        if entry["h"] > data["k"]:
            problems.append(f"{where}.h: expected at most k = {data['k']} moves left, found {entry['h']}")
        key = json.dumps([entry[x] for x in ("at", "grip", "ee", "q", "h")], sort_keys=True)
        if key in seen:
            problems.append(f"{where}: the same position is listed twice")
        seen.add(key)
    return problems


def _where(path: Any) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else f".{part}"
    return out.lstrip(".") or "(top)"


def _expected(error: jsonschema.ValidationError) -> str:
    if error.validator == "const":
        return f"expected {error.validator_value!r}, found {error.instance!r}"
    if error.validator == "type":
        return f"expected {' or '.join(_listed(error.validator_value))}, found {error.instance!r}"
    if error.validator == "oneOf":
        return f"expected a location, 'Else' or [object, grasp], found {error.instance!r}"
    return error.message.replace("is a required property", "is required")


def _listed(value: str | list[str]) -> list[str]:
    return [value] if isinstance(value, str) else list(value)


# -- printing ----------------------------------------------------------------

def format_state(v: State, objects: tuple[str, ...]) -> str:
    """`at: b=l2 w=Hand | grip=top | ee=l1`; a pair end-effector prints as (o,g)."""
    at = " ".join(f"{o}={a}" for o, a in zip(objects, v.at))
    ee = f"({v.ee[0]},{v.ee[1]})" if isinstance(v.ee, tuple) else v.ee
    return f"at: {at} | grip={v.grip or 'none'} | ee={ee}"


def format_position(position: Position, objects: tuple[str, ...]) -> str:
    v, q, h = position
    return f"[{format_state(v, objects)} | q={''.join(str(int(b)) for b in q)} | h={h}]"
