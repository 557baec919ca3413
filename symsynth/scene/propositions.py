"""The atoms of a manipulation task (semantics §3) and their meaning.

- `at(X, l)`: some object tagged `X` stands at `l` (`l` in L, or `Else`);
- `holding(X)`: some object tagged `X` is in the hand;
- `occupied(l)` / `free(l)`: some / no object stands at `l` in L.

An atom's tag may be an object's own name.  Anything else is an error that
lists what is known.
"""

from __future__ import annotations

from dataclasses import dataclass

from symsynth.errors import InputError
from symsynth.logic import ast
from symsynth.scene.model import ELSE, HAND, Scene


@dataclass(frozen=True)
class Proposition:
    kind: str  # "at", "holding", "occupied", "free"
    tag: str | None
    location: str | None

    @property
    def key(self) -> str:
        args = [a for a in (self.tag, self.location) if a is not None]
        return f"{self.kind}({', '.join(args)})"

    @property
    def place(self) -> str:
        """Where the atom looks: the hand for holding(X), else its location
        (at, occupied and free name one)."""
        if self.kind == "holding":
            return HAND
        if self.location is None:
            raise ValueError(f"{self.key} names no location")
        return self.location

    @property
    def named_tag(self) -> str:
        """The tag at(X, l) and holding(X) name."""
        if self.tag is None:
            raise ValueError(f"{self.key} names no tag")
        return self.tag


_ARITY = {"at": 2, "holding": 1, "occupied": 1, "free": 1}


def interpret(atom: ast.Atom, scene: Scene) -> Proposition:
    """The proposition an atom of the task denotes in `scene`."""
    kind = atom.name
    if kind not in _ARITY:
        raise InputError(f"unknown proposition {atom.key!r}; expected one of "
                         "at(TAG, LOCATION), holding(TAG), occupied(LOCATION), free(LOCATION)")
    if len(atom.args) != _ARITY[kind]:
        raise InputError(f"{atom.key!r}: {kind} takes {_ARITY[kind]} argument(s)")
    tags = sorted(scene.tags)
    if kind in ("at", "holding"):
        tag = atom.args[0]
        if tag not in scene.tags:
            raise InputError(f"{atom.key!r}: unknown object or tag {tag!r}; known: {', '.join(tags)}")
        if kind == "holding":
            return Proposition(kind, tag, None)
        location = atom.args[1]
        allowed = list(scene.locations) + [ELSE]
        if location not in allowed:
            raise InputError(f"{atom.key!r}: unknown location {location!r}; known: {', '.join(allowed)}")
        return Proposition(kind, tag, location)
    location = atom.args[0]
    if location not in scene.locations:
        raise InputError(f"{atom.key!r}: unknown location {location!r}; "
                         f"known: {', '.join(scene.locations)}")
    return Proposition(kind, None, location)


def interpret_all(formula: ast.Formula, scene: Scene) -> dict[str, Proposition]:
    """atom key -> proposition, for every atom of the task."""
    return {a.key: interpret(a, scene) for a in ast.atoms(formula)}
