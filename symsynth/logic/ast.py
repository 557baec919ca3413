"""The LTLf abstract syntax: frozen, hashable dataclasses, one per operator.

Nodes compare by value, so two parses of the same text are equal and can be
used as dictionary keys.  A node's hash is computed once and kept (the
compiler keys dictionaries by subformulas: hashing a large formula anew at
every lookup walked all of it, a third of Syft syft_1/001's compilation).
Passes over the tree are small functions elsewhere (`printer`, `semantics`,
`normal`), not methods here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypeVar

_Node = TypeVar("_Node", bound=type)


class Formula:
    """Base class of every LTLf node."""

    __slots__ = ("_hash",)

    def __hash__(self) -> int:
        """The hash a dataclass gives (of its fields' tuple), computed once:
        the fields' own hashes are kept too, so it costs one tuple."""
        try:
            return self._hash  # type: ignore[has-type]
        except AttributeError:
            value = hash(tuple(getattr(self, name) for name in self.__match_args__))  # type: ignore[attr-defined]
            object.__setattr__(self, "_hash", value)  # (frozen: not through the node's __setattr__)
            return value


def node(cls: _Node) -> _Node:
    """A frozen dataclass with slots that keeps `Formula.__hash__` (a frozen
    dataclass would make its own, which walks the whole subtree).  Pickles
    and copies carry the fields only (the dataclass's `__getstate__`): the
    hash of a string differs between processes."""
    cls.__hash__ = Formula.__hash__  # type: ignore[method-assign]  # (before: dataclass keeps it)
    return dataclass(frozen=True, slots=True)(cls)


@node
class Const(Formula):
    """`true` or `false`."""

    value: bool


@node
class Last(Formula):
    """`last`: true exactly at the final position of the trace."""


@node
class Atom(Formula):
    """An atomic proposition `p`, or a predicate atom `name(arg, ...)`.

    Predicate atoms are plain propositions for the logic; the manipulation
    game gives them meaning.  `args` is empty for a bare proposition.
    """

    name: str
    args: tuple[str, ...] = ()

    @property
    def key(self) -> str:
        """The canonical text of the atom, used as its variable name."""
        if not self.args:
            return self.name
        return f"{self.name}({', '.join(self.args)})"


@node
class Not(Formula):
    arg: Formula


@node
class Next(Formula):
    """Strong next `X[!] f`: a next position exists and satisfies `f`."""

    arg: Formula


@node
class WeakNext(Formula):
    """Weak next `WX f`: no next position, or it satisfies `f`."""

    arg: Formula


@node
class Eventually(Formula):
    arg: Formula


@node
class Always(Formula):
    arg: Formula


@node
class Until(Formula):
    left: Formula
    right: Formula


@node
class Release(Formula):
    left: Formula
    right: Formula


@node
class WeakUntil(Formula):
    left: Formula
    right: Formula


@node
class And(Formula):
    left: Formula
    right: Formula


@node
class Or(Formula):
    left: Formula
    right: Formula


@node
class Implies(Formula):
    left: Formula
    right: Formula


@node
class Equiv(Formula):
    left: Formula
    right: Formula


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
