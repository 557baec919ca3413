"""Negation normal form of LTLf, the input of formula progression.

In NNF, `Not` stands only in front of an `Atom`; `->` and `<->` are expanded;
`!last` becomes `X true` (a next position exists).  Dualities used
(finite-trace semantics, strong `X` / weak `WX`):

    !X f = WX !f      !F f = G !f      !(f U g) = !f R !g
    !WX f = X !f      !G f = F !f      !(f R g) = !f U !g
    !(f W g) = !g U (!f & !g)

`G` is pushed through `&` (`G(f & g) = G f & G g`) so that conjunctions under
`G` decompose too.
"""

from __future__ import annotations

from functools import singledispatch

from symsynth.logic import ast


def nnf(formula: ast.Formula, negate: bool = False) -> ast.Formula:
    """`formula` (or its negation when `negate`) in negation normal form."""
    return _nnf(formula, negate)


@singledispatch
def _nnf(node: ast.Formula, neg: bool) -> ast.Formula:
    raise TypeError(f"not an LTLf node: {node!r}")


@_nnf.register
def _(node: ast.Const, neg):
    return ast.Const(node.value != neg)


@_nnf.register
def _(node: ast.Last, neg):
    return ast.Next(ast.TRUE) if neg else node


@_nnf.register
def _(node: ast.Atom, neg):
    return ast.Not(node) if neg else node


@_nnf.register
def _(node: ast.Not, neg):
    return _nnf(node.arg, not neg)


@_nnf.register
def _(node: ast.Next, neg):
    return (ast.WeakNext if neg else ast.Next)(_nnf(node.arg, neg))


@_nnf.register
def _(node: ast.WeakNext, neg):
    return (ast.Next if neg else ast.WeakNext)(_nnf(node.arg, neg))


@_nnf.register
def _(node: ast.Eventually, neg):
    return (ast.Always if neg else ast.Eventually)(_nnf(node.arg, neg))


@_nnf.register
def _(node: ast.Always, neg):
    return (ast.Eventually if neg else ast.Always)(_nnf(node.arg, neg))


@_nnf.register
def _(node: ast.Until, neg):
    return (ast.Release if neg else ast.Until)(_nnf(node.left, neg), _nnf(node.right, neg))


@_nnf.register
def _(node: ast.Release, neg):
    return (ast.Until if neg else ast.Release)(_nnf(node.left, neg), _nnf(node.right, neg))


@_nnf.register
def _(node: ast.WeakUntil, neg):
    if neg:  # !(f W g) = !g U (!f & !g)
        not_right = _nnf(node.right, True)
        return ast.Until(not_right, ast.And(_nnf(node.left, True), not_right))
    return ast.WeakUntil(_nnf(node.left, False), _nnf(node.right, False))


@_nnf.register
def _(node: ast.And, neg):
    return (ast.Or if neg else ast.And)(_nnf(node.left, neg), _nnf(node.right, neg))


@_nnf.register
def _(node: ast.Or, neg):
    return (ast.And if neg else ast.Or)(_nnf(node.left, neg), _nnf(node.right, neg))


@_nnf.register
def _(node: ast.Implies, neg):
    if neg:  # !(f -> g) = f & !g
        return ast.And(_nnf(node.left, False), _nnf(node.right, True))
    return ast.Or(_nnf(node.left, True), _nnf(node.right, False))


@_nnf.register
def _(node: ast.Equiv, neg):
    left, right = _nnf(node.left, False), _nnf(node.right, False)
    not_left, not_right = _nnf(node.left, True), _nnf(node.right, True)
    if neg:  # exactly one side holds
        return ast.Or(ast.And(left, not_right), ast.And(not_left, right))
    return ast.Or(ast.And(left, right), ast.And(not_left, not_right))


def split_conjuncts(formula: ast.Formula) -> list[ast.Formula]:
    """The conjuncts of an NNF formula, with `G` distributed over `&`."""
    if isinstance(formula, ast.And):
        return split_conjuncts(formula.left) + split_conjuncts(formula.right)
    if isinstance(formula, ast.Always) and isinstance(formula.arg, ast.And):
        return [ast.Always(part) for part in split_conjuncts(formula.arg)]
    return [formula]


def expose(formula: ast.Formula, is_leaf=lambda f: False) -> tuple[str, list[ast.Formula]] | None:
    """The Boolean operator at the top of `formula`, with its operands, or
    None for a leaf of the Boolean skeleton.

    `!`, `&`, `|`, `->`, `<->` are on top as written; under `X`, `WX`, `G`
    and `F` a Boolean operator is pulled up where finite-trace semantics
    allows it:

        X(f & g) = X f & X g       WX(f & g) = WX f & WX g     G(f & g) = G f & G g
        X(f | g) = X f | X g       WX(f | g) = WX f | WX g     F(f | g) = F f | F g
        X !f = !WX f               WX !f = !X f                F(f -> g) = !G f | F g
        X(f -> g) = !WX f | X g    WX(f -> g) = !X f | WX g

    The operand of `X` / `WX` / `G` / `F` is exposed first (so `X G(f & g)`
    gives `X G f & X G g`); this recursion follows one chain of unary
    operators, as deep as the parser's nesting limit.  An operand for which
    `is_leaf` holds is not taken apart.
    """
    if isinstance(formula, ast.And):
        return "and", [formula.left, formula.right]
    if isinstance(formula, ast.Or):
        return "or", [formula.left, formula.right]
    if isinstance(formula, ast.Implies):
        return "implies", [formula.left, formula.right]
    if isinstance(formula, ast.Equiv):
        return "equiv", [formula.left, formula.right]
    if isinstance(formula, ast.Not):
        return "not", [formula.arg]
    if not isinstance(formula, (ast.Next, ast.WeakNext, ast.Always, ast.Eventually)):
        return None
    inner = None if is_leaf(formula.arg) else expose(formula.arg, is_leaf)
    if inner is None:
        return None
    op, args = inner
    if isinstance(formula, (ast.Next, ast.WeakNext)):
        same = type(formula)
        dual = ast.WeakNext if same is ast.Next else ast.Next
        if op in ("and", "or"):
            return op, [same(a) for a in args]
        if op == "not":
            return "not", [dual(args[0])]
        if op == "implies":
            return "or", [ast.Not(dual(args[0])), same(args[1])]
        return None
    if isinstance(formula, ast.Always):
        return ("and", [ast.Always(a) for a in args]) if op == "and" else None
    if op == "or":
        return "or", [ast.Eventually(a) for a in args]
    if op == "implies":
        return "or", [ast.Not(ast.Always(args[0])), ast.Eventually(args[1])]
    return None
