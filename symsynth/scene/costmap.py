"""The conditional costmap, format `symsynth.costmap/1` (semantics §5, §7).

For a mode (`empty` or `o/g`) and an ordered pair of anchors, a list of
rules "if every location in `free` is free, the motion costs `cost`".
Loader and writer live together so that what the planners write is what
`solve` reads.  A rule may carry its evidence path (waypoints), which the
loader keeps and the game ignores.

An optional top-level key `planner`, an extension of the spec's format,
records who built the costmap (`Provenance`): the planner plugin and the
settings of `symsynth costmap`.  Evidence paths start and end at that
planner's inverse kinematics solutions for the anchors, so whatever
follows or re-checks them (`costmap verify`, the simulator) must use the
same planner.  Hand-written costmaps have no such key.  As everywhere in
this format, keys the loader does not know are ignored, at the top level,
in a motion, a rule or `planner`: a reader of the spec's format alone
reads these files too.

An optional top-level key `absent` (an extension too: docs/game-semantics.md
§5's **choice**) lists anchors `x/a` that are no robot configuration: the
grasp or contact `a` cannot be reached, or not without a collision, for an
object standing at `x` (a top grasp under a low shelf board).  No motion
goes to or from an absent anchor and no slide starts or ends at one, and the
robot, which can never have been there, does not count it among the places
it may be (`game.abstraction.else_starts`).  A costmap without the key has
every anchor, as in the spec.
"""

from __future__ import annotations

import dataclasses

import json
import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from symsynth.errors import InputError
from symsynth.files import write_atomic
from symsynth.scene.yamlpos import read_json

FORMAT = "symsynth.costmap/1"

Key = tuple[str, str, str]  # (mode, from-anchor, to-anchor)
SlideKey = tuple[str, str, str]  # (contact, from-location, to-location)

#: The costmap methods a provenance may name (`planning.methods.METHODS`,
#: which imports this module; a test keeps the two equal).
METHODS = ("sg", "recursive")


@dataclass(frozen=True)
class Rule:
    free: frozenset[str]
    cost: float
    path: tuple[tuple[float, ...], ...] | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Provenance:
    """Who built a costmap (the optional key `planner`): the planner plugin
    by its entry-point name, the version of the package that provides it,
    and `symsynth costmap`'s method, seed and the scene's roadmap settings
    (`roadmap_size`, or `seconds` for a time-limited roadmap, and the
    `check_step` in radians between collision checks; files written before
    it was renamed say `resolution`).  Only `name` is required."""

    name: str
    version: str | None = None
    method: str | None = None
    seed: int | None = None
    roadmap_size: int | None = None
    seconds: float | None = None
    check_step: float | None = None

    def to_json(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}


@dataclass(frozen=True)
class Costmap:
    motions: Mapping[Key, tuple[Rule, ...]]
    #: Who built it; None for hand-written and older files.  Like a rule's
    #: path, the game ignores it, and so does equality.
    provenance: Provenance | None = field(default=None, compare=False)
    #: Slide rules (semantics §4b, v2): for a contact and an ordered pair of
    #: locations, "if every place in `free` is free, the slide costs `cost`".
    slides: Mapping[SlideKey, tuple[Rule, ...]] = field(default_factory=dict)
    #: Anchors that are no robot configuration (the key `absent`, module doc).
    absent: frozenset[str] = frozenset()
    #: The file it was read from (None: computed, or inline in a scene), so
    #: that no output is written over it.  Ignored by equality.
    source: Path | None = field(default=None, compare=False)

    def rules(self, mode: str, start: str, goal: str) -> tuple[Rule, ...]:
        return self.motions.get((mode, start, goal), ())

    def slide_rules(self, contact: str, start: str, goal: str) -> tuple[Rule, ...]:
        return self.slides.get((contact, start, goal), ())

    def all_rules(self) -> Iterator[Rule]:
        """Every rule, of motions and of slides."""
        for rules in (*self.motions.values(), *self.slides.values()):
            yield from rules

    def to_json(self) -> dict[str, Any]:
        motions = []
        for (mode, start, goal), rules in sorted(self.motions.items()):
            motions.append({"mode": mode, "from": start, "to": goal, "rules": _rules_json(rules)})
        head: dict[str, Any] = {"format": FORMAT}
        if self.provenance is not None:
            head["planner"] = self.provenance.to_json()
        slides = [{"contact": contact, "from": start, "to": goal, "rules": _rules_json(rules)}
                  for (contact, start, goal), rules in sorted(self.slides.items())]
        return (head | ({"absent": sorted(self.absent)} if self.absent else {}) | {"motions": motions}
                | ({"slides": slides} if slides else {}))


def _rules_json(rules: tuple[Rule, ...]) -> list[dict[str, Any]]:
    entries = []
    for rule in rules:
        entry: dict[str, Any] = {"free": sorted(rule.free), "cost": rule.cost}
        if rule.path is not None:
            entry["path"] = [list(q) for q in rule.path]
        entries.append(entry)
    return entries


class CostmapError(InputError):
    """A costmap file that is not valid `symsynth.costmap/1`."""


def costmap_from_data(data: Any, source: str = "<costmap>") -> Costmap:
    """Parse the JSON structure; every problem is reported, with its place."""
    problems: list[str] = []
    if not isinstance(data, dict):
        raise CostmapError(f"{source}: expected a JSON object with 'format' and 'motions'")
    if data.get("format") != FORMAT:
        problems.append(f"format: expected {FORMAT!r}, found {data.get('format')!r}")
    if not isinstance(data.get("motions"), list):
        problems.append("motions: expected a list")
    motions = _entries(data.get("motions"), "motions", "mode", problems)
    slides = {}
    if "slides" in data:
        if not isinstance(data["slides"], list):
            problems.append("slides: expected a list")
        slides = _entries(data["slides"], "slides", "contact", problems)
    provenance = None if "planner" not in data else _provenance(data["planner"], problems)
    absent = _absent(data.get("absent", []), problems)
    if problems:
        raise CostmapError(f"{source}: invalid costmap:\n" + "\n".join(f"  {p}" for p in problems))
    return Costmap(motions, provenance, slides, absent)


def _absent(value: Any, problems: list[str]) -> frozenset[str]:
    """The key `absent`: a list of anchor names `PLACE/GRASP` or
    `PLACE/CONTACT`, each once (whether they are the scene's anchors is
    `scene.load.costmap_problems`' question)."""
    if not isinstance(value, list):
        problems.append(f"absent: expected a list of anchors (PLACE/GRASP or PLACE/CONTACT), found {value!r}")
        return frozenset()
    seen: set[str] = set()
    for i, name in enumerate(value):
        if not isinstance(name, str) or name.count("/") != 1 or "" in name.split("/"):
            problems.append(f"absent[{i}]: expected an anchor PLACE/GRASP or PLACE/CONTACT, found {name!r}")
        elif name in seen:
            problems.append(f"absent[{i}]: {name!r} is listed twice")
        else:
            seen.add(name)
    return frozenset(seen)


def _entries(entries: Any, name: str, head: str, problems: list[str]) -> dict[Key, tuple[Rule, ...]]:
    """The list `motions` (keyed by mode, from, to) or `slides` (by contact,
    from, to): rules gathered by key."""
    gathered: dict[Key, list[Rule]] = {}
    fields = (head, "from", "to")
    for i, entry in enumerate(entries if isinstance(entries, list) else []):
        where = f"{name}[{i}]"
        if not isinstance(entry, dict):
            problems.append(f"{where}: expected an object with {head}, from, to, rules")
            continue
        missing = [k for k in (*fields, "rules") if k not in entry]
        if missing:
            problems.append(f"{where}: missing {', '.join(missing)}")
            continue
        if not all(isinstance(entry[k], str) for k in fields):
            problems.append(f"{where}: {head}, from and to must be strings")
            continue
        rules = gathered.setdefault((entry[head], entry["from"], entry["to"]), [])
        if not isinstance(entry["rules"], list):
            problems.append(f"{where}.rules: expected a list")
            continue
        for j, rule in enumerate(entry["rules"]):
            parsed = _rule(rule, f"{where}.rules[{j}]", problems)
            if parsed is not None:
                rules.append(parsed)
    return {k: tuple(v) for k, v in gathered.items()}


def _provenance(value: Any, problems: list[str]) -> Provenance | None:
    """The key `planner`; each bad field is a problem of its own."""
    if not isinstance(value, dict):
        problems.append("planner: expected an object with the name and settings of the planner that "
                        f"built the costmap, found {value!r}")
        return None
    found = len(problems)
    name = value.get("name")
    if not isinstance(name, str) or not name:
        problems.append(f"planner.name: expected the planner's name, found {name!r}")
    for key in ("version", "method"):
        text = value.get(key)
        if text is not None and (not isinstance(text, str) or not text):
            problems.append(f"planner.{key}: expected a non-empty string, found {text!r}")
    if isinstance(value.get("method"), str) and value["method"] and value["method"] not in METHODS:
        problems.append(f"planner.method: expected one of {', '.join(METHODS)}, found {value['method']!r}")
    for key, least in (("seed", 0), ("roadmap_size", 2)):
        number = value.get(key)
        if number is not None and (not isinstance(number, int) or isinstance(number, bool) or number < least):
            problems.append(f"planner.{key}: expected a whole number >= {least}, found {number!r}")
    for key in ("seconds", "check_step", "resolution"):  # resolution: check_step's old name
        number = value.get(key)
        if number is not None and (not _is_number(number) or number <= 0):
            problems.append(f"planner.{key}: expected a finite number > 0, found {number!r}")
    if value.get("roadmap_size") is not None and value.get("seconds") is not None:
        problems.append("planner: a roadmap has either a size (roadmap_size) or a time limit (seconds), not both")
    if len(problems) > found or not isinstance(name, str):  # a name that is no string is a problem above
        return None
    step = value.get("check_step", value.get("resolution"))
    return Provenance(name, value.get("version"), value.get("method"), value.get("seed"),
                      value.get("roadmap_size"),
                      None if value.get("seconds") is None else float(value["seconds"]),
                      None if step is None else float(step))


def _rule(rule: Any, where: str, problems: list[str]) -> Rule | None:
    if not isinstance(rule, dict) or "cost" not in rule:
        problems.append(f"{where}: expected an object with 'free' and 'cost'")
        return None
    cost = rule["cost"]
    if not _is_number(cost):
        problems.append(f"{where}.cost: expected a finite number, found {cost!r} "
                        "(leave a motion out when it is impossible)")
        return None
    if cost < 0:
        problems.append(f"{where}.cost: must be >= 0, found {cost}")
        return None
    free = rule.get("free", [])
    if not isinstance(free, list) or not all(isinstance(x, str) for x in free):
        problems.append(f"{where}.free: expected a list of location names")
        return None
    path = rule.get("path")
    if path is not None:
        if not isinstance(path, list) or not all(
                isinstance(q, list) and all(_is_number(x) for x in q) for q in path):
            problems.append(f"{where}.path: expected a list of waypoints (lists of numbers)")
            return None
        if len({len(q) for q in path}) > 1:
            problems.append(f"{where}.path: expected waypoints of one length (one number per joint), "
                            f"found lengths {', '.join(map(str, sorted({len(q) for q in path})))}")
            return None
        path = tuple(tuple(float(x) for x in q) for q in path)
    return Rule(frozenset(free), cost if isinstance(cost, int) else float(cost), path)  # ints exact


def _is_number(x: Any) -> bool:
    """A finite number that is a float too (a 400-digit integer is not)."""
    if not isinstance(x, (int, float)) or isinstance(x, bool):
        return False
    try:
        return math.isfinite(float(x))
    except OverflowError:
        return False


def load_costmap(path: Path) -> Costmap:
    costmap = costmap_from_data(read_json(path, "costmap", CostmapError), str(path))
    return dataclasses.replace(costmap, source=Path(path))


def write_costmap(costmap: Costmap, path: Path) -> None:
    """Write `costmap` to `path`, whole or not at all (`files.write_atomic`)."""
    write_atomic(path, json.dumps(costmap.to_json(), indent=1) + "\n", "costmap file")

