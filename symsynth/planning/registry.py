"""Planner plugins, found through the entry-point group `symsynth.planners`.

The built-in planners register the same way as third-party ones (see
pyproject.toml); a plugin that fails to import is reported by name.
"""

from __future__ import annotations

from symsynth import plugins
from symsynth.planning.protocol import Planner, PlannerError

GROUP = "symsynth.planners"
DEFAULT = "ompl-fcl"


def planner_names() -> tuple[str, ...]:
    return tuple(sorted(plugins.found(GROUP)))


def planner_class(name: str) -> type[Planner]:
    cls = plugins.load(GROUP, name, "planner", PlannerError)
    if not isinstance(getattr(cls, "name", None), str):
        raise PlannerError(f"planner plugin {name!r} ({plugins.found(GROUP)[name].value}) is not a Planner: "
                           "it has no 'name'")
    return cls


def planner_version(name: str) -> str | None:
    """The version of the package that provides planner `name` (recorded in
    the costmaps it builds); None when no installed package provides it."""
    return plugins.version(GROUP, name)
