"""Entry-point registries, one per kind of plugin: planners
(`symsynth.planners`), motion primitives (`symsynth.primitives`), game
solvers (`symsynth.solvers`) and simulated humans (`symsynth.humans`).
symsynth's own implementations register through the same groups as
third-party ones (pyproject.toml), so what a user installs is found the
way the built-ins are.

It sits at the bottom of the package, next to the errors: any layer may
look a plugin up by name without importing the layer that defines it.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator, Mapping
from importlib.metadata import EntryPoint, entry_points
from typing import Any

from symsynth.errors import SymsynthError


def found(group: str) -> dict[str, EntryPoint]:
    """The entry points of `group` by name.  Kept while `sys.path` and the
    modification times of its folders stay the same (a scan of the
    installed packages costs 2-5 ms; a lookup per solve and per planner
    adds up), so a folder put on the path, or a package installed into
    one, is seen at the next lookup."""
    key = (group, _path_state())
    points = _found.get(key)
    if points is None:
        if len(_found) > 64:
            _found.clear()
        points = _found[key] = {ep.name: ep for ep in entry_points(group=group)}
    return dict(points)


_found: dict[tuple[str, tuple], dict[str, EntryPoint]] = {}


def _path_state() -> tuple:
    state: list[tuple[str, int | None]] = []
    for entry in sys.path:
        try:
            state.append((entry, os.stat(entry or ".").st_mtime_ns))
        except OSError:
            state.append((entry, None))
    return tuple(state)


def load(group: str, name: str, what: str, error: type[SymsynthError]) -> Any:
    """The object registered as `name` in `group`; `error` (naming `what`,
    e.g. "planner") when there is none or it does not import."""
    points = found(group)
    if name not in points:
        known = ", ".join(sorted(points)) or "none are installed"
        raise error(f"unknown {what} {name!r}; installed {what}s: {known}")
    try:
        return points[name].load()
    except (ImportError, AttributeError) as failure:
        raise error(f"{what} plugin {name!r} ({points[name].value}) failed to load: {failure}") from None


def version(group: str, name: str) -> str | None:
    """The version of the package that provides `name` in `group`."""
    point = found(group).get(name)
    dist = None if point is None else point.dist
    return None if dist is None else dist.version


class Registry(Mapping[str, Any]):
    """A group as a read-only mapping, name -> the loaded object (loaded
    when asked for, so a broken plugin fails only the one who uses it)."""

    def __init__(self, group: str, what: str, error: type[SymsynthError]):
        self.group, self.what, self.error = group, what, error

    def __getitem__(self, name: str) -> Any:
        if name not in found(self.group):
            raise KeyError(name)
        return load(self.group, name, self.what, self.error)

    def get_or_fail(self, name: str) -> Any:
        """`self[name]`, with the registry's error (the installed names) for an unknown one."""
        return load(self.group, name, self.what, self.error)

    def __iter__(self) -> Iterator[str]:
        return iter(sorted(found(self.group)))

    def __len__(self) -> int:
        return len(found(self.group))
