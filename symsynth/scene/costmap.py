"""The conditional costmap, format `symsynth.costmap/1` (spec §5, §7).

For a mode (`empty` or `o/g`) and an ordered pair of anchors, a list of
rules "if every location in `free` is free, the motion costs `cost`".
Loader and writer live together so that what the planners write is what
`solve` reads.  A rule may carry its evidence path (waypoints), which the
loader keeps and the game ignores.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from symsynth.errors import InputError, read_text

FORMAT = "symsynth.costmap/1"

Key = tuple[str, str, str]  # (mode, from-anchor, to-anchor)


@dataclass(frozen=True)
class Rule:
    free: frozenset[str]
    cost: float
    path: tuple[tuple[float, ...], ...] | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Costmap:
    motions: Mapping[Key, tuple[Rule, ...]]

    def rules(self, mode: str, start: str, goal: str) -> tuple[Rule, ...]:
        return self.motions.get((mode, start, goal), ())

    def to_json(self) -> dict[str, Any]:
        motions = []
        for (mode, start, goal), rules in sorted(self.motions.items()):
            entries = []
            for rule in rules:
                entry: dict[str, Any] = {"free": sorted(rule.free), "cost": rule.cost}
                if rule.path is not None:
                    entry["path"] = [list(q) for q in rule.path]
                entries.append(entry)
            motions.append({"mode": mode, "from": start, "to": goal, "rules": entries})
        return {"format": FORMAT, "motions": motions}


class CostmapError(InputError):
    """A costmap file that is not valid `symsynth.costmap/1`."""


def costmap_from_data(data: Any, source: str = "<costmap>") -> Costmap:
    """Parse the JSON structure; every problem is reported, with its place."""
    problems: list[str] = []
    if not isinstance(data, dict):
        raise CostmapError(f"{source}: expected a JSON object with 'format' and 'motions'")
    if data.get("format") != FORMAT:
        problems.append(f"format: expected {FORMAT!r}, found {data.get('format')!r}")
    motions: dict[Key, list[Rule]] = {}
    entries = data.get("motions")
    if not isinstance(entries, list):
        problems.append("motions: expected a list")
        entries = []
    for i, entry in enumerate(entries):
        where = f"motions[{i}]"
        if not isinstance(entry, dict):
            problems.append(f"{where}: expected an object with mode, from, to, rules")
            continue
        missing = [k for k in ("mode", "from", "to", "rules") if k not in entry]
        if missing:
            problems.append(f"{where}: missing {', '.join(missing)}")
            continue
        if not all(isinstance(entry[k], str) for k in ("mode", "from", "to")):
            problems.append(f"{where}: mode, from and to must be strings")
            continue
        key = (entry["mode"], entry["from"], entry["to"])
        rules = motions.setdefault(key, [])
        if not isinstance(entry["rules"], list):
            problems.append(f"{where}.rules: expected a list")
            continue
        for j, rule in enumerate(entry["rules"]):
            parsed = _rule(rule, f"{where}.rules[{j}]", problems)
            if parsed is not None:
                rules.append(parsed)
    if problems:
        raise CostmapError(f"{source}: invalid costmap:\n" + "\n".join(f"  {p}" for p in problems))
    return Costmap({k: tuple(v) for k, v in motions.items()})


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
        path = tuple(tuple(float(x) for x in q) for q in path)
    return Rule(frozenset(free), float(cost), path)


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def load_costmap(path: Path) -> Costmap:
    text = read_text(path, "costmap", CostmapError)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as error:
        raise CostmapError(f"{path}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None
    return costmap_from_data(data, str(path))


def write_costmap(costmap: Costmap, path: Path) -> None:
    Path(path).write_text(json.dumps(costmap.to_json(), indent=1) + "\n", encoding="utf-8")

