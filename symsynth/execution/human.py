"""The simulated human: instantaneous moves of objects between the robot's
actions (paper Sec. IV-B), at most `k` in a run.

On each human turn the simulator offers a `Turn`: the position if the human
passes, and every move that is legal in the abstraction (semantics §4) *and*
possible in the world, one `Option` per physical target (a location's
pose, or each free Else sample for a move to Else).  A move is impossible
in the world when the object would penetrate the robot, the held object or
another object there (the hand hovering over a location, say).  A human
answers with an option, a `Request` (a scripted move, which the simulator
checks the same way), or None to pass.

- `NoHuman` always passes.
- `RandomHuman` is the human model `random(p)` (semantics §9): it moves with
  probability `p` on each turn it can, uniformly among the abstraction's
  legal moves, then among the world's options for the move drawn, from its
  own seeded generator.
- `AdversarialHuman` follows the solver's worst case: it takes the option
  (or the pass) after which the strategy may still have to spend the most
  (the strategy's `budget` of the position it leads to), ties broken by
  its generator.  Against it the run's abstract cost is E_p itself, unless
  the world forbids a move the abstraction allows.
- `ScriptedHuman` plays a script file (`read_script`).
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import jsonschema

from symsynth import plugins
from symsynth.errors import InputError
from symsynth.game.abstraction import Move, decimal, legal_human_moves, robot_action_names
from symsynth.game.human_model import RandomModel, draw
from symsynth.game.solution import Position
from symsynth.scene.geometry import Pose, vec3
from symsynth.scene.model import ELSE, Scene
from symsynth.scene.load import Report, schema_message
from symsynth.scene.yamlpos import read_yaml


@dataclass(frozen=True)
class Option:
    """A possible human move: the abstract action, the object and the pose
    it goes to, and the robot position after it (None when the move
    completes the task)."""

    action: str
    obj: str
    pose: Pose
    after: Position | None


@dataclass(frozen=True)
class Request:
    """A scripted move: object `obj` to `to` (a location, `Else`, an Else
    sample, or a pose)."""

    obj: str
    to: str | Pose
    entry: int  # index in the script, for messages


@dataclass(frozen=True)
class Turn:
    position: Position  # the robot's position if the human passes
    actions: int  # robot actions done so far
    last: str | None  # the robot's last action
    options: tuple[Option, ...]


class Human(Protocol):
    name: str

    def choose(self, turn: Turn) -> Option | Request | None: ...


class NoHuman:
    name = "none"

    def choose(self, turn: Turn) -> None:
        return None


class RandomHuman:
    """The human model `random(P)` (semantics §9, `game.human_model`) in the
    world: the model draws the pass or one of the abstraction's legal moves
    (each with P / |M|), then one of the world's options for that move
    (which Else sample, say) is taken at random; a move the world forbids
    here is a pass.  Without the scene (a third party's context), the moves
    are the world's options by name."""

    name = "random"

    def __init__(self, seed: int, probability: float = 0.3, scene: Scene | None = None) -> None:
        self.rng = random.Random(f"human/random/{seed}")
        self.probability = probability
        self.model = RandomModel(decimal(probability))
        self.scene = scene

    def choose(self, turn: Turn) -> Option | None:
        v, _, h = turn.position
        if self.scene is not None:
            moves = legal_human_moves(self.scene, v) if h > 0 else []
        else:
            moves = list({o.action: Move("move", o.action, o.obj, 0, None, "", v) for o in turn.options}.values())
        move = draw(self.model, self.rng, v, h, moves)
        if move is None:
            return None
        options = [o for o in turn.options if o.action == move.action]
        return self.rng.choice(options) if options else None


class AdversarialHuman:
    name = "adversarial"

    def __init__(self, seed: int, budget: Callable[[Position], float | None]) -> None:
        self.rng = random.Random(f"human/adversarial/{seed}")
        self.budget = budget

    def choose(self, turn: Turn) -> Option | None:
        def worth(after: Position | None) -> float:
            if after is None:
                return -1.0  # completes the task for the robot
            value = self.budget(after)
            return float("inf") if value is None else value

        candidates: list[Option | None] = [None, *turn.options]
        values = [worth(turn.position)] + [worth(o.after) for o in turn.options]
        best = max(values)
        return self.rng.choice([c for c, v in zip(candidates, values) if v == best])


@dataclass(frozen=True)
class HumanContext:
    """What a registered human is made from, one per run: the run's seed,
    the move probability (`--move-probability`) and the budget the strategy
    guarantees from a position (None where it does not win, and everywhere
    for a human that does not declare it `needs` "budgets": `NEEDS`)."""

    seed: int
    probability: float
    budget: Callable[[Position], float | None]
    scene: Scene | None = None  # the abstraction's legal moves, for the model of `random`


def no_human(context: HumanContext) -> Human:
    return NoHuman()


def random_human(context: HumanContext) -> Human:
    return RandomHuman(context.seed, context.probability, context.scene)


def adversarial_human(context: HumanContext) -> Human:
    return AdversarialHuman(context.seed, context.budget)


#: What a registered human may declare it needs of a run, in a `needs`
#: attribute of its factory (a set of these names; none by default):
#: "budgets": `HumanContext.budget` answers for every position the strategy
#: reaches, which explores the whole strategy before the first run
#: (`game.strategy.strategy_table`); without it the runs look the strategy
#: up only where they go, and `budget` answers None everywhere.
NEEDS = frozenset({"budgets"})
adversarial_human.needs = frozenset({"budgets"})  # type: ignore[attr-defined]  # see NEEDS

#: The entry-point group of simulated humans: a name -> a function from a
#: `HumanContext` to a `Human` (none, random, adversarial are registered
#: there; a script file is not a registered human).
HUMANS = plugins.Registry("symsynth.humans", "human", InputError)


def human_needs(name: str) -> frozenset[str]:
    """What the registered human `name` needs of a run (`NEEDS`); an
    unknown need is the plugin's error, named so."""
    factory = HUMANS.get_or_fail(name)
    declared: Any = getattr(factory, "needs", frozenset())
    if isinstance(declared, str) or not all(isinstance(n, str) for n in declared):
        raise InputError(f"human plugin {name!r}: 'needs' must be a set of names from {', '.join(sorted(NEEDS))}, "
                         f"found {declared!r}")
    unknown = set(declared) - NEEDS
    if unknown:
        raise InputError(f"human plugin {name!r} needs {', '.join(sorted(unknown))}, which symsynth does not "
                         f"provide; known needs: {', '.join(sorted(NEEDS))}")
    return frozenset(declared)


class ScriptedHuman:
    """Entries fire in order, one per human turn: an entry fires on the
    first human turn at which its `after` holds and every earlier entry has
    fired (`after: N`: N robot actions are done, 0 = before the first;
    `after: ACTION`: the robot's last action was ACTION)."""

    name = "script"

    def __init__(self, entries: Sequence[dict[str, Any]]) -> None:
        self.entries = list(entries)
        self.next = 0

    def choose(self, turn: Turn) -> Request | None:
        if self.next >= len(self.entries):
            return None
        entry = self.entries[self.next]
        after = entry["after"]
        due = turn.actions >= after if isinstance(after, int) else turn.last == after
        if not due:
            return None
        self.next += 1
        return Request(entry["move"], entry["to"], self.next - 1)

    def unfired(self) -> list[tuple[int, dict[str, Any]]]:
        """The entries that have not fired, numbered from 1 as in the script."""
        return list(enumerate(self.entries[self.next:], start=self.next + 1))


# -- script files --------------------------------------------------------------

SCRIPT_SCHEMA: dict[str, Any] = {
    "type": "object", "additionalProperties": False, "required": ["moves"],
    "properties": {
        "moves": {"type": "array", "items": {
            "type": "object", "additionalProperties": False, "required": ["after", "move", "to"],
            "properties": {
                "after": {"oneOf": [{"type": "integer", "minimum": 0}, {"type": "string", "minLength": 1}]},
                "move": {"type": "string", "minLength": 1},
                "to": {"oneOf": [{"type": "string", "minLength": 1},
                                 {"type": "array", "items": {"type": "number"}, "minItems": 2, "maxItems": 3}]},
            }}},
    },
}


def read_script(path: str | Path, scene: Scene) -> ScriptedHuman:
    """A human script (YAML)::

        moves:
          - {after: 0, move: b, to: support1}              # before the robot's first action
          - {after: "drop(w1,support1)", move: w1, to: Else}
          - {after: 6, move: w2, to: [0.62, 0.1]}          # a pose: between places, it is Else

    `to` is a location, `Else` (the first free Else sample), an Else sample
    by name, or `[x, y]` / `[x, y, z]` on the table.  Every problem is an
    `InputError` naming the file, the line and what was expected.
    """
    data, lines = read_yaml(path, "human script")
    report = Report(str(path), lines, "human script", InputError)
    for error in jsonschema.Draft202012Validator(SCRIPT_SCHEMA).iter_errors(data):
        report.add(tuple(error.absolute_path), _schema_message(error))
    entries = []
    if not report.problems:
        targets = scene.locations + (ELSE,) + scene.else_samples
        actions = robot_action_names(scene)
        for i, entry in enumerate(data["moves"]):
            where = ("moves", i)
            if entry["move"] not in scene.object_names:
                report.add(where + ("move",), f"unknown object {entry['move']!r}; the objects: "
                           f"{', '.join(scene.object_names)}")
            to = entry["to"]
            if isinstance(to, str) and to not in targets:
                report.add(where + ("to",), f"unknown place {to!r}; expected one of {', '.join(targets)} "
                           "or [x, y] / [x, y, z]")
            if isinstance(entry["after"], str) and entry["after"].replace(" ", "") not in actions:
                report.add(where + ("after",), f"{entry['after']!r} is no robot action of this scene; "
                           "expected a number of robot actions, or transit(o,g), grab(o), transfer(l) "
                           "or drop(o,l) with the scene's names")
            if isinstance(to, list) and not all(math.isfinite(v) for v in to):
                report.add(where + ("to",), "expected finite numbers [x, y] or [x, y, z]")
            elif isinstance(to, list):
                to = Pose(vec3([*to, 0.0] if len(to) == 2 else to))  # the schema allows 2 or 3 numbers
            after = entry["after"]
            if isinstance(after, str):
                after = after.replace(" ", "")
            else:
                after = int(after)  # the schema's integers include 1.0, which a count compares as 1
            entries.append({"after": after, "move": entry["move"], "to": to})
        if len(entries) > scene.k:
            report.add(("moves",), f"{len(entries)} moves, but the human has only k = {scene.k}; "
                       "the moves beyond k would be refused")
    report.raise_if_any()
    return ScriptedHuman(entries)


def _schema_message(error: jsonschema.ValidationError) -> str:
    """`schema_message`, with what a script's `after` and `to` can be."""
    if error.validator == "oneOf" and error.absolute_path and error.absolute_path[-1] == "after":
        return f"expected a number of robot actions (>= 0) or a robot action, found {error.instance!r}"
    if error.validator == "oneOf":
        return f"expected a place name or [x, y] / [x, y, z], found {error.instance!r}"
    return schema_message(error)
