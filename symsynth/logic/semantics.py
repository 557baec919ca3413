"""The reference semantics of LTLf on a finite, non-empty trace.

A direct transcription of De Giacomo & Vardi (IJCAI 2013), kept deliberately
naive: it is the oracle that the automata are tested against, and the
definition the documentation points to.  A trace is a sequence of letters; a
letter is the set of atom keys (`Atom.key`) that hold at that position.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from functools import singledispatch

from symsynth.logic import ast

Letter = Collection[str]
Trace = Sequence[Letter]


def holds(formula: ast.Formula, trace: Trace, position: int = 0) -> bool:
    """Whether `trace, position |= formula`.  The trace must be non-empty."""
    if not trace:
        raise ValueError("LTLf is interpreted over non-empty traces")
    if not 0 <= position < len(trace):
        raise ValueError(f"position {position} outside a trace of length {len(trace)}")
    return _holds(formula, trace, position)


@singledispatch
def _holds(node: ast.Formula, trace: Trace, i: int) -> bool:
    raise TypeError(f"not an LTLf node: {node!r}")


@_holds.register
def _(node: ast.Const, trace, i):
    return node.value


@_holds.register
def _(node: ast.Last, trace, i):
    return i == len(trace) - 1


@_holds.register
def _(node: ast.Atom, trace, i):
    return node.key in trace[i]


@_holds.register
def _(node: ast.Not, trace, i):
    return not _holds(node.arg, trace, i)


@_holds.register
def _(node: ast.Next, trace, i):
    return i + 1 < len(trace) and _holds(node.arg, trace, i + 1)


@_holds.register
def _(node: ast.WeakNext, trace, i):
    return i + 1 >= len(trace) or _holds(node.arg, trace, i + 1)


@_holds.register
def _(node: ast.Eventually, trace, i):
    return any(_holds(node.arg, trace, j) for j in range(i, len(trace)))


@_holds.register
def _(node: ast.Always, trace, i):
    return all(_holds(node.arg, trace, j) for j in range(i, len(trace)))


@_holds.register
def _(node: ast.Until, trace, i):
    # some j >= i satisfies the right side, and every k in [i, j) the left
    return any(_holds(node.right, trace, j)
               and all(_holds(node.left, trace, k) for k in range(i, j))
               for j in range(i, len(trace)))


@_holds.register
def _(node: ast.Release, trace, i):
    # f R g  ==  !(!f U !g): g holds until and including the first f, or forever
    return all(_holds(node.right, trace, j)
               or any(_holds(node.left, trace, k) for k in range(i, j))
               for j in range(i, len(trace)))


@_holds.register
def _(node: ast.WeakUntil, trace, i):
    # f W g  ==  (f U g) | G f
    return (_holds(ast.Until(node.left, node.right), trace, i)
            or all(_holds(node.left, trace, j) for j in range(i, len(trace))))


@_holds.register
def _(node: ast.And, trace, i):
    return _holds(node.left, trace, i) and _holds(node.right, trace, i)


@_holds.register
def _(node: ast.Or, trace, i):
    return _holds(node.left, trace, i) or _holds(node.right, trace, i)


@_holds.register
def _(node: ast.Implies, trace, i):
    return not _holds(node.left, trace, i) or _holds(node.right, trace, i)


@_holds.register
def _(node: ast.Equiv, trace, i):
    return _holds(node.left, trace, i) == _holds(node.right, trace, i)
