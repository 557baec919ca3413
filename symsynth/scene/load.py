"""Load and validate a scene file (YAML, semantics §7).

Validation is a JSON Schema for the shape, every number finite (YAML has
.inf and .nan), then checks of meaning (names that must exist, one object
per location, the task's atoms).  Every problem is collected and reported
at once as `file:line: key.path: what was expected`; nothing here raises a
traceback for bad input.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import jsonschema

from symsynth import plugins
from symsynth.errors import InputError, LTLfSyntaxError, SymsynthWarning
from symsynth.logic import ast
from symsynth.logic.parser import parse_ltlf
from symsynth.primitive_registry import PrimitiveError, displacement
from symsynth.scene.costmap import Costmap, CostmapError, costmap_from_data, load_costmap
from symsynth.scene import physical
from symsynth.scene.model import ELSE, EMPTY, HAND, HOME, ObjectSpec, Scene
from symsynth.scene.propositions import interpret_all
from symsynth.scene.yamlpos import KeyPath, line_of, read_yaml

#: A human model as a scene writes it (semantics §9): NAME or NAME(ARGS), e.g. random(0.3)
MODEL_PATTERN = r"^\s*[A-Za-z_][\w-]*\s*(\(.*\))?\s*$"
MODEL_GROUP = "symsynth.human_models"


NAME = {"type": "string", "pattern": "^[A-Za-z0-9_]+$"}
NONNEG = {"type": "number", "minimum": 0}

SCHEMA: dict[str, Any] = {
    "type": "object",
    "required": ["name", "objects", "locations"],
    "additionalProperties": False,
    "properties": {
        "name": {"type": "string"},
        "objects": {
            "type": "object",
            "propertyNames": NAME,
            "additionalProperties": {
                "type": "object",
                "additionalProperties": False,
                "properties": {
                    "tags": {"type": "array", "items": NAME},
                    "at": {"type": "string"},
                },
            },
        },
        "locations": {"type": "array", "items": NAME, "uniqueItems": True},
        "else_samples": {"type": "array", "items": NAME, "uniqueItems": True},
        "grasps": {"type": "array", "items": NAME, "uniqueItems": True, "minItems": 1},
        "contacts": {"type": "array", "items": NAME, "uniqueItems": True},
        "primitives": {"type": "object", "additionalProperties": False,
                       "properties": {"grab": NONNEG, "drop": NONNEG}},
        "human": {"type": "object", "additionalProperties": False,
                  "properties": {"k": {"type": "integer", "minimum": 0},
                                 "model": {"type": "string", "pattern": MODEL_PATTERN}}},
        "task": {"type": "string"},
        "costmap": {"type": ["string", "object"]},
        "interchangeable": {"type": "array", "items": {"type": "array", "items": NAME,
                                                       "minItems": 2, "uniqueItems": True}},
    },
}


def _physical_schema() -> dict[str, Any]:
    """The abstract schema, with names turned into named poses and the
    physical keys added (see `physical.py`)."""
    schema = copy.deepcopy(SCHEMA)
    props = schema["properties"]
    obj = props["objects"]["additionalProperties"]
    obj["properties"].update(physical.OBJECT_KEYS)
    obj.update(physical.ONE_SHAPE)
    named = {"type": "object", "propertyNames": NAME, "additionalProperties": physical.POSE}
    props["locations"] = named
    props["else_samples"] = named
    props["grasps"] = {"type": "object", "propertyNames": NAME, "minProperties": 1,
                       "additionalProperties": physical.GRASP}
    props.update(robot=physical.ROBOT, costs=physical.COSTS, planner=physical.PLANNER,
                 obstacles={"type": "object", "propertyNames": NAME,
                            "additionalProperties": physical.OBSTACLE},
                 **{"else": physical.ELSE_REGION})
    schema["required"] = schema["required"] + ["grasps"]
    props["contacts"] = {"type": "object", "propertyNames": NAME, "additionalProperties": physical.CONTACT}
    return schema


PHYSICAL_SCHEMA = _physical_schema()

#: Problems listed in one message (a costmap of another scene has hundreds).
MAX_PROBLEMS = 12
#: The most objects a scene may have (docs/input-limits.md).
MAX_OBJECTS = 256


class SceneError(InputError):
    """A scene file with problems; the message lists all of them."""


def load_scene(path: str | Path, *, costmap: str | Path | None = None) -> Scene:
    """The scene of a YAML file; `costmap` (a file) replaces the scene's own
    costmap, which is then not read at all."""
    path = Path(path)
    data, lines = read_yaml(path, "scene", SceneError)
    return scene_from_data(data, source=path, lines=lines, costmap=costmap)


def scene_from_data(data: Any, source: Path | None = None,
                    lines: dict[KeyPath, int] | None = None,
                    costmap: str | Path | None = None) -> Scene:
    """Validate parsed YAML/JSON data and build the `Scene`; a `costmap` file
    replaces the data's costmap and is checked against the scene the same way."""
    report = Report(str(source) if source else "<scene>", lines or {})
    if not isinstance(data, dict):
        report.add((), "expected a mapping with name, objects, locations, ...")
        report.raise_if_any()
    is_physical = "robot" in data
    _check_schema(data, is_physical, report)
    report.raise_if_any()
    if "costs" in data and "primitives" in data:
        report.add(("primitives",), "give grab and drop costs either in costs or in primitives, not both")

    geometry = physical.geometry_from_data(data, source, report) if is_physical else None
    locations = tuple(data["locations"])
    else_samples = tuple(x for x in geometry.places if x not in locations) if geometry else tuple(
        data.get("else_samples", ()))
    grasps = tuple(data.get("grasps", ("top",)))
    contacts = tuple(data.get("contacts", ()))
    for i, name in enumerate(contacts):
        if name in grasps:
            report.add(("contacts", name if is_physical else i), f"{name!r} is already a grasp: a contact and "
                       "a grasp are aimed at by the same name in actions and anchors, so their names must differ")
    if is_physical:
        _check_primitives(data, report)
    _check_places(locations, else_samples, report)
    objects = _objects(data["objects"], locations, else_samples, report)
    declared, where = _declared_classes(data, objects, report)
    primitives = data.get("costs", data.get("primitives", {}))
    scene = Scene(
        name=data["name"], objects=tuple(objects), locations=locations,
        else_samples=else_samples, grasps=grasps, contacts=contacts,
        grab_cost=_cost(primitives.get("grab", 5)), drop_cost=_cost(primitives.get("drop", 5)),
        k=int(data.get("human", {}).get("k", 0)), task=data.get("task"), source=source,
        human_model=_human_model(data, report), human_model_where=report.where(("human", "model")),
        geometry=geometry, declared_classes=declared, declared_where=where,
    )
    if scene.task is not None:
        formula = _check_task(scene, scene.task, report)
        if formula is not None:
            scene = dataclasses.replace(scene, parsed=(scene.task, formula))
    if costmap is None:
        checks = report
        loaded = _costmap(data.get("costmap"), source, report)
    else:  # problems name the given file; a relative path is from where the user stands
        checks = Report(str(costmap), {})
        loaded = _costmap(str(costmap), None, checks)
    if loaded is not None:
        _check_costmap(scene, loaded, checks)
    report.raise_if_any()
    checks.raise_if_any()
    return dataclasses.replace(scene, costmap=loaded)


def _check_schema(data: dict, is_physical: bool, report: Report) -> None:
    """The scene schema's complaints, and the non-finite numbers it lets through."""
    schema = PHYSICAL_SCHEMA if is_physical else SCHEMA
    flagged = set()
    for error in sorted(jsonschema.Draft202012Validator(schema).iter_errors(data),
                        key=lambda e: list(map(str, e.absolute_path))):
        report.add(tuple(error.absolute_path), _schema_message(error, is_physical))
        flagged.add(tuple(error.absolute_path))
    # JSON Schema's bounds let YAML's .inf and .nan through (nan > 0 is false,
    # so is nan <= 0); the costmap, a format of its own, checks its numbers itself
    for where, value in non_finite({key: v for key, v in data.items() if key != "costmap"}):
        if where not in flagged:
            report.add(where, f"expected a finite number, found {_yaml_float(value)}")


def _check_places(locations: tuple[str, ...], else_samples: tuple[str, ...], report: Report) -> None:
    """Places apart from the reserved names and from each other."""
    for i, name in enumerate(locations):
        if name in (ELSE, HAND, HOME):
            report.add(("locations", i), f"{name!r} is reserved and cannot name a location")
    for i, name in enumerate(else_samples):
        if name in (ELSE, HAND, HOME):  # `at: Else`, the hand and the robot's home are these names
            report.add(("else_samples", i), f"{name!r} is reserved and cannot name an Else sample")
        elif name in locations:
            report.add(("else_samples", i), f"{name!r} is already a location of interest")


def _objects(specs: dict, locations: tuple[str, ...], else_samples: tuple[str, ...],
             report: Report) -> list[ObjectSpec]:
    """The objects in the order written, each at a known location no other one holds
    (too many objects stop the load here: the rest would only repeat it)."""
    if len(specs) > MAX_OBJECTS:
        report.add(("objects",), f"{len(specs):,} objects: symsynth solves games of at most "
                   f"{MAX_OBJECTS} (its positions grow as the places to the power of the objects; "
                   "docs/input-limits.md)")
        report.raise_if_any()
    objects = []
    standing: dict[str, str] = {}
    for name, spec in specs.items():
        _check_object_names(name, spec, locations, else_samples, report)
        at = spec.get("at", ELSE)
        if at != ELSE and at not in locations:
            report.add(("objects", name, "at"),
                       f"unknown location {at!r}; expected one of {', '.join(locations + (ELSE,))}")
        elif at != ELSE and at in standing:
            report.add(("objects", name, "at"), f"location {at!r} already holds {standing[at]!r}")
        elif at != ELSE:
            standing[at] = name
        objects.append(ObjectSpec(name, frozenset(spec.get("tags", ())) | {name}, at))
    return objects


def _human_model(data: dict, report: Report) -> str | None:
    """`human.model` as written, once its name is an installed human model
    (its arguments are the model's to check, when it is made)."""
    text = data.get("human", {}).get("model")
    if text is None:
        return None
    name = text.split("(")[0].strip()
    known = plugins.found(MODEL_GROUP)
    if name not in known:
        report.add(("human", "model"), f"unknown human model {name!r}; installed human models: "
                   f"{', '.join(sorted(known)) or 'none'} (e.g. random(0.3))")
    return text


def _declared_classes(data: dict, objects: list[ObjectSpec], report: Report
                      ) -> tuple[tuple[tuple[str, ...], ...] | None, tuple[str, ...]]:
    """The classes of `interchangeable:` (None when the key is absent) and
    where each was written.  Names and overlaps are checked here; whether the
    game really cannot tell a class's members apart needs the task and the
    costmap, and game/symmetry.py checks it before any solver relies on it."""
    if "interchangeable" not in data:
        return None, ()
    names = {o.name for o in objects}
    seen: dict[str, int] = {}
    where = []
    for i, members in enumerate(data["interchangeable"]):
        path = ("interchangeable", i)
        line = line_of(report.lines, path)
        where.append(f"{report.source}:{line}: interchangeable.{i}" if line else
                     f"{report.source}: interchangeable.{i}")
        for j, name in enumerate(members):
            if name not in names:
                report.add(path + (j,), f"unknown object {name!r}; expected one of {', '.join(sorted(names))}")
            elif name in seen and seen[name] != i:
                report.add(path + (j,), f"{name!r} is already in class {seen[name]}: an object belongs to one class")
            seen.setdefault(name, i)
    return tuple(tuple(c) for c in data["interchangeable"]), tuple(where)


def _check_primitives(data: dict, report: Report) -> None:
    """Each physical contact names an installed displacement primitive, and
    each fixed cost under `costs` (besides per_radian, grab and drop) one
    that some contact uses."""
    used = set()
    for name, spec in (data.get("contacts") or {}).items():
        try:
            displacement(spec["primitive"])
            used.add(spec["primitive"])
        except PrimitiveError as error:
            report.add(("contacts", name, "primitive"), str(error))
    for key in data.get("costs") or {}:
        if key not in ("per_radian", "grab", "drop") and key not in used:
            report.add(("costs", key), f"no contact uses a primitive {key!r}: expected per_radian, grab, drop "
                       "or the fixed cost of a contact's primitive"
                       + (f" ({', '.join(sorted(used))})" if used else ""))


def _check_object_names(name: str, spec: dict, locations: tuple[str, ...], else_samples: tuple[str, ...],
                        report: Report) -> None:
    """An object's name and tags are what `at(X, l)` and `holding(X)` name,
    and its name stands for it in places and modes: none may read as a
    place (`Else`, `Hand`, a location, an Else sample)."""
    places = {ELSE: "a reserved place", HAND: "a reserved place"} \
        | dict.fromkeys(locations, "a location") | dict.fromkeys(else_samples, "an Else sample")
    if name in places:
        report.add(("objects", name), f"{name!r} is {places[name]} and cannot name an object")
    for i, tag in enumerate(spec.get("tags", ())):
        if tag in places and tag != name:
            report.add(("objects", name, "tags", i), f"{tag!r} is {places[tag]} and cannot be a tag")


def non_finite(data: Any, path: KeyPath = ()) -> Iterator[tuple[KeyPath, float]]:
    """The key path and value of every float in `data` that is not finite."""
    if isinstance(data, float) and not math.isfinite(data):
        yield path, data
    elif isinstance(data, dict):
        for key, value in data.items():
            yield from non_finite(value, path + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from non_finite(value, path + (i,))


def _cost(value: float) -> float:
    """A cost as written: an integer stays a Python int, exact past a
    float's 2^53 (9007199254740993 is not 9007199254740992.0), a decimal
    the float whose repr it is (`game.abstraction.decimal` reads it back)."""
    return value if isinstance(value, int) else float(value)


def _yaml_float(value: float) -> str:
    """A non-finite float as YAML writes it (.inf, -.inf, .nan)."""
    return ".nan" if math.isnan(value) else ("-.inf" if value < 0 else ".inf")


def _check_task(scene: Scene, task: str, report: Report) -> ast.Formula | None:
    """The task parsed, if it parses and fits the scene (else reported)."""
    try:
        formula = parse_ltlf(task, source=f"{report.source} (task)")
        interpret_all(formula, scene)
    except LTLfSyntaxError as error:
        report.add(("task",), f"syntax error at column {error.column}: {error.expected}\n{error.context}")
    except InputError as error:
        report.add(("task",), str(error))
    else:
        return formula
    return None


def _costmap(value: Any, source: Path | None, report: Report) -> Costmap | None:
    if value is None:
        return None
    try:
        if isinstance(value, dict):
            return costmap_from_data(value, f"{report.source} (costmap)")
        base = source.parent if source else Path.cwd()
        return load_costmap(base / value)
    except CostmapError as error:
        report.add(("costmap",), str(error))
        return None


def _check_costmap(scene: Scene, costmap: Costmap, report: Report) -> None:
    for problem in costmap_problems(scene, costmap):
        report.add(("costmap",), problem)


def costmap_problems(scene: Scene, costmap: Costmap) -> list[str]:
    """What in `costmap` does not belong to `scene`: modes, anchors and the
    places its rules assume free.  The one check for every way a costmap
    enters (a file, the cache, a planner); its numbers were checked when it
    was read (`costmap_from_data`)."""
    problems = []
    modes, anchors = set(scene.modes), set(scene.anchors)
    places = set(scene.locations) | set(scene.else_samples)
    for (mode, start, goal), rules in costmap.motions.items():
        what = f"motion {mode} {start} -> {goal}"
        if mode not in modes:
            problems.append(f"{what}: unknown mode {mode!r}; expected {EMPTY!r} or OBJECT/GRASP "
                            f"with objects {_some(scene.object_names)} and grasps {_some(scene.grasps)}")
        for anchor in (start, goal):
            if anchor not in anchors:
                problems.append(f"{what}: unknown anchor {anchor!r}; expected {HOME!r} or "
                                f"PLACE/GRASP with places {', '.join(sorted(places))}"
                                + (f" (or PLACE/CONTACT with contacts {', '.join(scene.contacts)})"
                                   if scene.contacts else ""))
        problems += _unknown_places(what, rules, places)
        problems += [f"{what}: {anchor!r} is listed as absent (no robot configuration), so no motion "
                     "goes to or from it" for anchor in dict.fromkeys((start, goal)) if anchor in costmap.absent]
    for anchor in sorted(costmap.absent):
        if anchor == HOME or anchor not in anchors:
            problems.append(f"absent: {anchor!r} is not an anchor of the scene; expected PLACE/GRASP with "
                            f"places {', '.join(sorted(places))} and grasps {', '.join(scene.grasps)}"
                            + (f" (or PLACE/CONTACT with contacts {', '.join(scene.contacts)})"
                               if scene.contacts else ""))
    declared = None if scene.geometry is None else scene.geometry.absent
    if declared is not None and costmap.absent != declared:
        problems.append(f"absent: the costmap lists {', '.join(sorted(costmap.absent)) or 'no anchor'} as absent, "
                        f"the scene declares {', '.join(sorted(declared)) or 'none'} (absent_at of its grasps and "
                        "contacts): it is another scene's costmap")
    for (contact, start, goal), rules in costmap.slides.items():
        what = f"slide {contact} {start} -> {goal}"
        if contact not in scene.contacts:
            problems.append(f"{what}: unknown contact {contact!r}; "
                            + (f"expected one of {', '.join(scene.contacts)}" if scene.contacts
                               else "the scene has no contacts"))
        for end in (start, goal):
            if end not in scene.locations:
                problems.append(f"{what}: {end!r} is not a location of interest; slides go between "
                                f"locations ({', '.join(scene.locations)})")
        if start == goal:
            problems.append(f"{what}: a slide goes from one location to another")
        problems += [f"{what}: its anchor {end}/{contact} is listed as absent (no robot configuration), so "
                     "no slide starts or ends there" for end in dict.fromkeys((start, goal))
                     if f"{end}/{contact}" in costmap.absent]
        problems += _unknown_places(what, rules, places)
    return problems


def _unknown_places(what: str, rules: tuple, places: set[str]) -> list[str]:
    problems = []
    for rule in rules:
        unknown = sorted(rule.free - places)
        if unknown:
            problems.append(f"{what}: rule names unknown locations {', '.join(unknown)}")
    return problems


def _schema_message(error: jsonschema.ValidationError, is_physical: bool = False) -> str:
    """`schema_message`, with what a scene's mistakes mean (a shape, named poses)."""
    if error.validator == "pattern" and error.validator_value == MODEL_PATTERN:
        return f"expected a human model NAME(ARGS), e.g. random(0.3), found {error.instance!r}"
    if error.validator == "oneOf" and "box" in str(error.schema):
        return f"expected exactly one shape: {', '.join(physical.SHAPE_KEYS)}"
    if error.validator == "type" and not is_physical and error.validator_value == "array" \
            and isinstance(error.instance, dict):
        return ("expected a list of names; named poses are for physical scenes "
                "(add a 'robot' key)")
    if error.validator == "type" and is_physical and error.validator_value == "object" \
            and isinstance(error.instance, list):
        return ("expected a mapping from names to poses ({xyz: [x, y, z], rpy: [r, p, y]}): "
                "this is a physical scene, since it has a 'robot' key")
    return schema_message(error)


def schema_message(error: jsonschema.ValidationError) -> str:
    """A JSON Schema error in words for a YAML input file."""
    if error.validator == "required":
        return error.message.replace("is a required property", "is required")
    if error.validator == "additionalProperties":
        return f"{error.message}; allowed keys: {', '.join(sorted(error.schema.get('properties', {})))}"
    if error.validator == "type":
        return f"expected {error.validator_value}, found {error.instance!r}"
    return error.message


def _some(names: tuple[str, ...], shown: int = 12) -> str:
    """The first `shown` names and how many more (a message stays readable)."""
    more = f" and {len(names) - shown} more" if len(names) > shown else ""
    return ", ".join(names[:shown]) + more


def where(source: Path | None, path: KeyPath) -> str:
    """`file:line: key.path` of a key of a scene file, for an error found
    after loading (the file read again for its lines; `key.path` alone when
    there is no file or it cannot be read now)."""
    key = ".".join(map(str, path))
    if source is None:
        return key
    try:
        _, lines = read_yaml(source, "scene", SceneError)
    except InputError:
        return f"{source}: {key}"
    line = line_of(lines, path)
    return f"{source}:{line}: {key}" if line else f"{source}: {key}"


class Report:
    """The problems of one input file, each `file:line: key.path: message`,
    raised together as one `error` about the `what` (scene, human script)."""

    def __init__(self, source: str, lines: dict[KeyPath, int], what: str = "scene",
                 error: type[InputError] = SceneError):
        self.source, self.lines = source, lines
        self.problems: list[str] = []
        self.what, self.error = what, error

    def add(self, path: KeyPath, message: str) -> None:
        self.problems.append(f"{self.where(path)}: {message}")

    def where(self, path: KeyPath) -> str:
        """`file:line: key.path` of `path`."""
        line = line_of(self.lines, path)
        where = f"{self.source}:{line}" if line else self.source
        return f"{where}: {'.'.join(map(str, path)) or '(top)'}"

    def warn(self, path: KeyPath, message: str) -> None:
        """Something that does not stop the load (a deprecated key), located
        as `add` locates problems: a `SymsynthWarning`."""
        line = line_of(self.lines, path)
        where = f"{self.source}:{line}" if line else self.source
        warnings.warn(f"{where}: {'.'.join(map(str, path))}: {message}", SymsynthWarning, stacklevel=2)

    def raise_if_any(self) -> None:
        if self.problems:
            count = len(self.problems)
            shown = self.problems[:MAX_PROBLEMS]
            if count > MAX_PROBLEMS:
                shown.append(f"... and {count - MAX_PROBLEMS} more")
            raise self.error(f"{count} problem{'s' if count > 1 else ''} in the {self.what}:\n"
                             + "\n".join(shown))
