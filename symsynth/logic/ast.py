"""The LTLf abstract syntax: frozen, hashable dataclasses, one per operator.

Nodes compare by value, so two parses of the same text are equal and can be
used as dictionary keys.  Passes over the tree are small functions elsewhere
(`printer`, `semantics`, `normal`), not methods here.
"""

from __future__ import annotations

from dataclasses import dataclass


class Formula:
    """Base class of every LTLf node."""

    __slots__ = ()


@dataclass(frozen=True, slots=True)
class Const(Formula):
    """`true` or `false`."""

    value: bool


@dataclass(frozen=True, slots=True)
class Last(Formula):
    """`last`: true exactly at the final position of the trace."""


@dataclass(frozen=True, slots=True)
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


@dataclass(frozen=True, slots=True)
class Not(Formula):
    arg: Formula


@dataclass(frozen=True, slots=True)
class Next(Formula):
    """Strong next `X[!] f`: a next position exists and satisfies `f`."""

    arg: Formula


@dataclass(frozen=True, slots=True)
class WeakNext(Formula):
    """Weak next `WX f`: no next position, or it satisfies `f`."""

    arg: Formula


@dataclass(frozen=True, slots=True)
class Eventually(Formula):
    arg: Formula


@dataclass(frozen=True, slots=True)
class Always(Formula):
    arg: Formula


@dataclass(frozen=True, slots=True)
class Until(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class Release(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class WeakUntil(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class And(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class Or(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
class Implies(Formula):
    left: Formula
    right: Formula


@dataclass(frozen=True, slots=True)
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
