"""The registry of motion primitives: the entry-point group
`symsynth.primitives`, built-ins and third-party plugins alike (what a
primitive does is `planning.primitive_protocol`'s protocols; the lookup is
`plugins`').

It sits at the bottom of the package, so that a scene can check the
primitive each of its contacts names without the scene layer importing
the planning layer; loading a plugin imports whatever the plugin needs.
"""

from __future__ import annotations

from typing import Any

from symsynth import plugins
from symsynth.errors import InputError

GROUP = "symsynth.primitives"
KINDS = ("prehensile", "displacement")
#: What a plugin of each kind must have (`planning.primitive_protocol`).
MEMBERS = {"prehensile": ("holds", "reaches", "execute"), "displacement": ("fixed_cost", "slides", "execute")}
#: The game's prehensile actions (semantics §4): each is carried out by the
#: prehensile primitive registered under its name.
PREHENSILE_ACTIONS = ("grab", "drop")


class PrimitiveError(InputError):
    """A primitive that is not installed, does not load, or is of the wrong kind."""


def primitive_names(kind: str | None = None) -> tuple[str, ...]:
    """The installed primitives (of one kind), by entry-point name."""
    names = sorted(plugins.found(GROUP))
    return tuple(n for n in names if kind is None or primitive(n).kind == kind)


def primitive(name: str) -> Any:
    """The primitive registered as `name`, ready to use."""
    cls = plugins.load(GROUP, name, "primitive", PrimitiveError)
    if getattr(cls, "kind", None) not in KINDS or not isinstance(getattr(cls, "name", None), str):
        raise PrimitiveError(f"primitive plugin {name!r} ({plugins.found(GROUP)[name].value}) is not a "
                             f"primitive: it needs a 'name' and a 'kind' ({' or '.join(KINDS)})")
    missing = [m for m in MEMBERS[cls.kind] if not hasattr(cls, m)]
    if missing:
        raise PrimitiveError(f"primitive plugin {name!r} ({plugins.found(GROUP)[name].value}) is a {cls.kind} "
                             f"primitive without {', '.join(missing)} (planning/primitive_protocol.py)")
    return cls()


def displacement(name: str) -> Any:
    """The displacement primitive `name`; a prehensile one is an error that says so."""
    found = primitive(name)
    if found.kind != "displacement":
        raise PrimitiveError(f"{name!r} is a {found.kind} primitive; a contact needs a displacement primitive "
                             f"({', '.join(primitive_names('displacement')) or 'none are installed'})")
    return found


def prehensile_primitives() -> tuple[Any, ...]:
    """The primitives that carry out the game's prehensile actions
    (`PREHENSILE_ACTIONS`), each checked to be prehensile."""
    found = tuple(primitive(name) for name in PREHENSILE_ACTIONS)
    for name, plugin in zip(PREHENSILE_ACTIONS, found):
        if plugin.kind != "prehensile":
            raise PrimitiveError(f"the game's {name} action needs a prehensile primitive named {name!r}; "
                                 f"the one installed is a {plugin.kind} primitive")
    return found
