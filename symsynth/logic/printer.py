"""Print an AST back to the grammar's syntax, with the fewest parentheses.

`parse_ltlf(to_string(f)) == f` for every formula `f` (default convention:
`X` is strong next, `WX` weak next).
"""

from __future__ import annotations

from functools import singledispatch

from symsynth.logic import ast

# Binding strength, loosest first; matches grammars/ltlf.lark.
_EQUIV, _IMPLIES, _OR, _AND, _TEMPORAL, _UNARY, _ATOMIC = range(7)

_UNARY_SYMBOL: dict[type[ast.Formula], str] = {ast.Not: "!", ast.Next: "X ", ast.WeakNext: "WX ",
                 ast.Eventually: "F ", ast.Always: "G "}
# operator, level, right-associative
_BINARY_SYMBOL: dict[type[ast.Formula], tuple[str, int, bool]] = {
    ast.Equiv: ("<->", _EQUIV, True), ast.Implies: ("->", _IMPLIES, True),
    ast.Or: ("|", _OR, False), ast.And: ("&", _AND, False),
    ast.Until: ("U", _TEMPORAL, True), ast.Release: ("R", _TEMPORAL, True),
    ast.WeakUntil: ("W", _TEMPORAL, True),
}


def to_string(formula: ast.Formula) -> str:
    """The formula as text that parses back to an equal AST."""
    return _print(formula)[0]


def _wrap(text_level: tuple[str, int], minimum: int) -> str:
    text, level = text_level
    return f"({text})" if level < minimum else text


@singledispatch
def _print(node: ast.Formula) -> tuple[str, int]:
    raise TypeError(f"not an LTLf node: {node!r}")


@_print.register
def _(node: ast.Const):
    return ("true" if node.value else "false"), _ATOMIC


@_print.register
def _(node: ast.Last):
    return "last", _ATOMIC


@_print.register
def _(node: ast.Atom):
    return node.key, _ATOMIC


def _unary(node):
    return _UNARY_SYMBOL[type(node)] + _wrap(_print(node.arg), _UNARY), _UNARY


def _binary(node):
    symbol, level, right_assoc = _BINARY_SYMBOL[type(node)]
    left_min, right_min = (level + 1, level) if right_assoc else (level, level + 1)
    left = _wrap(_print(node.left), left_min)
    right = _wrap(_print(node.right), right_min)
    return f"{left} {symbol} {right}", level


for _unary_class in _UNARY_SYMBOL:
    _print.register(_unary_class, _unary)
for _binary_class in _BINARY_SYMBOL:
    _print.register(_binary_class, _binary)
