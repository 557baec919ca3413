"""The LTLf abstract syntax: frozen, hashable nodes, one class per operator.

Nodes compare by value, so two parses of the same text are equal and can be
used as dictionary keys.  A node's hash is computed once and kept (the
compiler keys dictionaries by subformulas: hashing a large formula anew at
every lookup walked all of it, a third of Syft syft_1/001's compilation).
Passes over the tree are small functions elsewhere (`printer`, `semantics`,
`normal`), not methods here.

The classes are written out rather than made by `dataclasses` (whose
methods are compiled from source for each class when the module is
imported: 5-10 ms of every `symsynth dfa` run for these fifteen).  They
behave as frozen dataclasses with slots would: `Until(left=..., right=...)`
as repr, equality by class and fields, `__match_args__` for `match`, no
assignment, pickles and copies of the fields only (the kept hash is not
carried: the hash of a string differs between processes).
"""

from __future__ import annotations

from typing import Any, NoReturn

_set = object.__setattr__


class Formula:
    """Base class of every LTLf node."""

    __slots__ = ("_hash",)
    __match_args__: tuple[str, ...] = ()
    _hash: int

    def _fields(self) -> tuple[Any, ...]:
        return tuple(getattr(self, name) for name in self.__match_args__)

    def __hash__(self) -> int:
        try:
            return self._hash
        except AttributeError:
            value = hash(self._fields())  # (the fields' own hashes are kept: one tuple)
            _set(self, "_hash", value)
            return value

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self is other or self._fields() == other._fields()

    def __repr__(self) -> str:
        shown = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__match_args__)
        return f"{type(self).__name__}({shown})"

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return type(self), self._fields()

    def __setattr__(self, name: str, value: object) -> NoReturn:
        raise AttributeError(f"cannot assign to field {name!r}: LTLf nodes are immutable")

    def __delattr__(self, name: str) -> NoReturn:
        raise AttributeError(f"cannot delete field {name!r}: LTLf nodes are immutable")


class Const(Formula):
    """`true` or `false`."""

    __slots__ = ("value",)
    __match_args__ = ("value",)
    value: bool

    def __init__(self, value: bool) -> None:
        _set(self, "value", value)


class Last(Formula):
    """`last`: true exactly at the final position of the trace."""

    __slots__ = ()


class Atom(Formula):
    """An atomic proposition `p`, or a predicate atom `name(arg, ...)`.

    Predicate atoms are plain propositions for the logic; the manipulation
    game gives them meaning.  `args` is empty for a bare proposition.
    """

    __slots__ = ("name", "args")
    __match_args__ = ("name", "args")
    name: str
    args: tuple[str, ...]

    def __init__(self, name: str, args: tuple[str, ...] = ()) -> None:
        _set(self, "name", name)
        _set(self, "args", args)

    @property
    def key(self) -> str:
        """The canonical text of the atom, used as its variable name."""
        if not self.args:
            return self.name
        return f"{self.name}({', '.join(self.args)})"


class _Unary(Formula):
    """An operator with one operand."""

    __slots__ = ("arg",)
    __match_args__ = ("arg",)
    arg: Formula

    def __init__(self, arg: Formula) -> None:
        _set(self, "arg", arg)

    __hash__ = Formula.__hash__  # (a class defining __eq__ alone would be unhashable)

    def __eq__(self, other: object) -> bool:  # (one field: no tuple)
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self is other or self.arg == other.arg


class _Binary(Formula):
    """An operator with two operands."""

    __slots__ = ("left", "right")
    __match_args__ = ("left", "right")
    left: Formula
    right: Formula

    def __init__(self, left: Formula, right: Formula) -> None:
        _set(self, "left", left)
        _set(self, "right", right)

    __hash__ = Formula.__hash__

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self is other or (self.left == other.left and self.right == other.right)


class Not(_Unary):
    __slots__ = ()


class Next(_Unary):
    """Strong next `X[!] f`: a next position exists and satisfies `f`."""

    __slots__ = ()


class WeakNext(_Unary):
    """Weak next `WX f`: no next position, or it satisfies `f`."""

    __slots__ = ()


class Eventually(_Unary):
    __slots__ = ()


class Always(_Unary):
    __slots__ = ()


class Until(_Binary):
    __slots__ = ()


class Release(_Binary):
    __slots__ = ()


class WeakUntil(_Binary):
    __slots__ = ()


class And(_Binary):
    __slots__ = ()


class Or(_Binary):
    __slots__ = ()


class Implies(_Binary):
    __slots__ = ()


class Equiv(_Binary):
    __slots__ = ()


TRUE = Const(True)
FALSE = Const(False)

UNARY = (Not, Next, WeakNext, Eventually, Always)
BINARY = (Until, Release, WeakUntil, And, Or, Implies, Equiv)


def children(node: Formula) -> tuple[Formula, ...]:
    """The operands of `node` (none for an atom or a constant), left first."""
    if isinstance(node, UNARY):
        return (node.arg,)
    if isinstance(node, BINARY):
        return (node.left, node.right)
    return ()


def atoms(formula: Formula) -> tuple[Atom, ...]:
    """The atoms of `formula`, each once, in order of first occurrence."""
    seen: dict[Atom, None] = {}
    stack = [formula]
    while stack:
        node = stack.pop()
        if isinstance(node, Atom):
            seen.setdefault(node, None)
        elif isinstance(node, UNARY):
            stack.append(node.arg)
        elif isinstance(node, BINARY):
            stack.append(node.right)
            stack.append(node.left)
    return tuple(seen)



def depth(formula: Formula) -> int:
    """How many operators nest in `formula` (an atom is 1), without recursion."""
    deepest = 0
    stack = [(formula, 1)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        if isinstance(node, UNARY):
            stack.append((node.arg, d + 1))
        elif isinstance(node, BINARY):
            stack.append((node.left, d + 1))
            stack.append((node.right, d + 1))
    return deepest
