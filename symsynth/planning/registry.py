"""Planner plugins, found through the entry-point group `symsynth.planners`.

The built-in planners register the same way as third-party ones (see
pyproject.toml); a plugin that fails to import is reported by name.
"""

from __future__ import annotations

from importlib.metadata import EntryPoint, entry_points

from symsynth.planning.protocol import Planner, PlannerError

GROUP = "symsynth.planners"
DEFAULT = "ompl-fcl"


def _entry_points() -> dict[str, EntryPoint]:
    return {ep.name: ep for ep in entry_points(group=GROUP)}


def planner_names() -> tuple[str, ...]:
    return tuple(sorted(_entry_points()))


def planner_class(name: str) -> type[Planner]:
    found = _entry_points()
    if name not in found:
        known = ", ".join(sorted(found)) or "none are installed"
        raise PlannerError(f"unknown planner {name!r}; known planners: {known}")
    try:
        cls = found[name].load()
    except (ImportError, AttributeError) as error:
        raise PlannerError(f"planner plugin {name!r} ({found[name].value}) failed to load: {error}") from None
    if not isinstance(getattr(cls, "name", None), str):
        raise PlannerError(f"planner plugin {name!r} ({found[name].value}) is not a Planner: "
                           "it has no 'name'")
    return cls


def planner_version(name: str) -> str | None:
    """The version of the package that provides planner `name` (recorded in
    the costmaps it builds); None when no installed package provides it."""
    found = _entry_points().get(name)
    dist = None if found is None else found.dist
    return None if dist is None else dist.version
