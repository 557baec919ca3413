"""The expressions of a TLSF specification evaluated as syfco evaluates them
(`Writer/Eval.hs`): numbers, sets, signals, buses (`b[n]` is the signals
`b_0` ... `b_{n-1}`, syfco's default delimiter), functions expanded where
they are called, big operators unrolled over the values their first
condition binds, and formulas, with `X` weak and `X[!]` strong next (the
`Finite` semantics).  The reading of a whole file is `tlsf.py`."""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import lark

from symsynth.errors import InputError
from symsynth.logic import ast

#: Function calls nested deeper than this are refused (a recursion without end).
MAX_CALLS = 200


class TLSFError(InputError):
    """A TLSF file that does not parse or does not evaluate."""

@dataclass(frozen=True)
class Signal:
    name: str
    kind: str  # "input" or "output"


@dataclass(frozen=True)
class Bus:
    name: str
    size: int
    kind: str

    def signal(self, index: int) -> str:
        return f"{self.name}_{index}"


class _Empty:
    """The value of a guarded case `c : v` whose guard is false."""


EMPTY = _Empty()


@dataclass(frozen=True)
class Function:
    params: tuple[str, ...]
    bodies: tuple[lark.Tree, ...]


class Unevaluated:
    def __init__(self, bodies: tuple[lark.Tree, ...]):
        self.bodies = bodies


def conjunction(items: list[ast.Formula]) -> ast.Formula:
    return _join(items, ast.And, ast.TRUE, ast.FALSE)


def disjunction(items: list[ast.Formula]) -> ast.Formula:
    return _join(items, ast.Or, ast.FALSE, ast.TRUE)


def _join(items: list[ast.Formula], node: type, unit: ast.Const, zero: ast.Const) -> ast.Formula:
    """`items` joined by `node` as a balanced tree, constants folded (as
    syfco's simplifier does: the language is the same)."""
    kept = [f for f in items if f != unit]
    if zero in kept:
        return zero
    if not kept:
        return unit
    while len(kept) > 1:
        kept = [node(kept[i], kept[i + 1]) if i + 1 < len(kept) else kept[i] for i in range(0, len(kept), 2)]
    return kept[0]


def _not(f: ast.Formula) -> ast.Formula:
    if isinstance(f, ast.Const):
        return ast.Const(not f.value)
    return ast.Not(f)


def implication(a: ast.Formula, b: ast.Formula) -> ast.Formula:
    if a == ast.TRUE or b == ast.TRUE:
        return b
    if a == ast.FALSE:
        return ast.TRUE
    if b == ast.FALSE:
        return _not(a)
    return ast.Implies(a, b)


def _repeat(f: ast.Formula, times: int, node: Callable[[ast.Formula], ast.Formula]) -> ast.Formula:
    for _ in range(times):
        f = node(f)
    return f




class Evaluator:
    """Expressions of TLSF evaluated to numbers, sets, signals, buses or
    LTLf formulas (syfco's Writer/Eval.hs)."""

    def __init__(self, source: str):
        self.source = source
        self.globals: dict[str, object] = {}
        self.calls = 0


    def error(self, node: lark.Tree | lark.Token | None, message: str) -> TLSFError:
        line, column = position(node)
        where = f"{self.source}:{line}:{column}" if line else self.source
        return TLSFError(f"{where}: {message}")

    # top level

    def lookup(self, name: str, scope: dict[str, object], node) -> object:
        if name in scope:
            return scope[name]
        if name not in self.globals:
            raise self.error(node, f"'{name}' is not defined (not a parameter, a definition, a signal or a bound "
                                   "variable here)")
        value = self.globals[name]
        if isinstance(value, Unevaluated):
            self.globals[name] = None  # (being evaluated: a definition that needs itself)
            value = self.cases(value.bodies, {}, node, name)
            self.globals[name] = value
        elif value is None:
            raise self.error(node, f"'{name}' is defined in terms of itself")
        elif isinstance(value, Function):
            raise self.error(node, f"'{name}' is a function of {len(value.params)} arguments; call it as "
                                   f"{name}({', '.join(value.params)})")
        return value

    def cases(self, bodies: tuple[lark.Tree, ...], scope: dict[str, object], node, name: str) -> object:
        """The first body that is not a case with a false guard."""
        for body in bodies:
            value = self.eval(body, scope)
            if value is not EMPTY:
                return value
        raise self.error(node, f"no case of '{name}' applies here")

    def eval(self, node, scope: dict[str, object]) -> object:
        if isinstance(node, lark.Token):
            raise self.error(node, f"unexpected {node!s}")  # (the grammar gives trees only)
        method = getattr(self, "e_" + node.data.rstrip("_"), None)
        if method is None:
            raise self.error(node, f"{node.data.replace('_', ' ')} is not read by symsynth")
        return method(node, scope)

    def formula(self, value: object, node) -> ast.Formula:
        if isinstance(value, ast.Formula):
            return value
        if isinstance(value, Signal):
            return ast.Atom(value.name)
        raise self.error(node, f"expected a formula, found {_describe(value)}")

    def number(self, value: object, node) -> int:
        if isinstance(value, int):
            return value
        raise self.error(node, f"expected a number, found {_describe(value)}")

    def truth(self, value: object, node) -> bool:
        if isinstance(value, ast.Const):
            return value.value
        raise self.error(node, f"expected a condition on numbers or sets, found {_describe(value)}")

    def f(self, node, scope) -> ast.Formula:
        return self.formula(self.eval(node, scope), node)

    def n(self, node, scope) -> int:
        return self.number(self.eval(node, scope), node)

    def s(self, node, scope) -> frozenset:
        value = self.eval(node, scope)
        if not isinstance(value, frozenset):
            raise self.error(node, f"expected a set, found {_describe(value)}")
        return value

    # leaves

    def e_true(self, node, scope):
        return ast.TRUE

    def e_false(self, node, scope):
        return ast.FALSE

    def e_otherwise(self, node, scope):
        return ast.TRUE

    def e_number(self, node, scope):
        return int(node.children[0])

    def e_name(self, node, scope):
        return self.lookup(str(node.children[0]), scope, node)

    def e_index(self, node, scope):
        bus = self.lookup(str(node.children[0]), scope, node)
        if not isinstance(bus, Bus):
            raise self.error(node, f"'{node.children[0]}' is {_describe(bus)}, not a bus: it has no [index]")
        i = self.n(node.children[1], scope)
        if not 0 <= i < bus.size:
            raise self.error(node, f"{bus.name}[{i}]: the bus has {bus.size} signals, indexed 0 to {bus.size - 1}")
        return Signal(bus.signal(i), bus.kind)

    def e_call(self, node, scope):
        name = str(node.children[0])
        function = self.globals.get(name)
        if not isinstance(function, Function):
            raise self.error(node, f"'{name}' is not a function of GLOBAL DEFINITIONS")
        args = [self.eval(a, scope) for a in node.children[1:]]
        if len(args) != len(function.params):
            raise self.error(node, f"{name} takes {len(function.params)} arguments "
                                   f"({', '.join(function.params)}), given {len(args)}")
        self.calls += 1
        if self.calls > MAX_CALLS:
            raise self.error(node, f"calls nested more than {MAX_CALLS} deep (a recursion without end?)")
        try:
            return self.cases(function.bodies, dict(zip(function.params, args)), node, name)
        finally:
            self.calls -= 1

    def e_set(self, node, scope):
        return frozenset(self.eval(c, scope) for c in node.children)

    def e_range(self, node, scope):
        first, second, last = (self.n(c, scope) for c in node.children if isinstance(c, lark.Tree))
        step = second - first
        if step == 0:
            raise self.error(node, "a range {a, b .. c} needs a != b")
        return frozenset(range(first, last + (1 if step > 0 else -1), step))

    def e_case(self, node, scope):
        guard, value = node.children
        return self.eval(value, scope) if self.truth(self.eval(guard, scope), guard) else EMPTY

    # numbers and sets

    def _arith(self, node, scope, op):
        a, _, b = node.children
        return op(self.n(a, scope), self.n(b, scope))

    def e_plus(self, node, scope):
        return self._arith(node, scope, lambda a, b: a + b)

    def e_minus(self, node, scope):
        return self._arith(node, scope, lambda a, b: a - b)

    def e_times(self, node, scope):
        return self._arith(node, scope, lambda a, b: a * b)

    def e_div(self, node, scope):
        if self.n(node.children[2], scope) == 0:
            raise self.error(node, "division by zero")
        return self._arith(node, scope, lambda a, b: a // b)

    def e_mod(self, node, scope):
        if self.n(node.children[2], scope) == 0:
            raise self.error(node, "modulo zero")
        return self._arith(node, scope, lambda a, b: a % b)

    def e_sizeof(self, node, scope):
        value = self.eval(node.children[1], scope)
        if isinstance(value, Signal):
            return 1
        if not isinstance(value, Bus):
            raise self.error(node, f"SIZEOF expects a bus, found {_describe(value)}")
        return value.size

    def e_size(self, node, scope):
        return len(self.s(node.children[1], scope))

    def e_min(self, node, scope):
        return self._extreme(node, scope, min)

    def e_max(self, node, scope):
        return self._extreme(node, scope, max)

    def _extreme(self, node, scope, pick):
        values = self.s(node.children[1], scope)
        if not values:
            raise self.error(node, f"{node.children[0]} of the empty set")
        return pick(self.number(v, node) for v in values)

    def _set_op(self, node, scope, op):
        a, _, b = node.children
        return op(self.s(a, scope), self.s(b, scope))

    def e_cup(self, node, scope):
        return self._set_op(node, scope, frozenset.union)

    def e_cap(self, node, scope):
        return self._set_op(node, scope, frozenset.intersection)

    def e_setminus(self, node, scope):
        return self._set_op(node, scope, frozenset.difference)

    def e_member(self, node, scope):
        a, _, b = node.children
        return ast.Const(self.eval(a, scope) in self.s(b, scope))

    def e_compare(self, node, scope):
        a, op, b = node.children
        left, right = self.eval(a, scope), self.eval(b, scope)
        op = {"EQ": "==", "NEQ": "!=", "/=": "!=", "LE": "<", "GE": ">", "LEQ": "<=", "GEQ": ">="}.get(str(op), str(op))
        if op in ("==", "!=") and isinstance(left, (Signal, Bus)) and isinstance(right, (Signal, Bus)):
            return self.bus_equality(node, left, right, op == "==")
        if op in ("==", "!="):
            return ast.Const((left == right) == (op == "=="))
        x, y = self.number(left, a), self.number(right, b)
        return ast.Const({"<": x < y, "<=": x <= y, ">": x > y, ">=": x >= y}[op])

    def bus_equality(self, node, left, right, equal: bool) -> ast.Formula:
        def bits(v):
            return [v.name] if isinstance(v, Signal) else [v.signal(i) for i in range(v.size)]
        xs, ys = bits(left), bits(right)
        if len(xs) != len(ys):
            raise self.error(node, f"comparing {left.name} ({len(xs)} signals) with {right.name} ({len(ys)})")
        same = conjunction([ast.Equiv(ast.Atom(x), ast.Atom(y)) for x, y in zip(xs, ys)])
        return same if equal else _not(same)

    # big operators

    def bound(self, conditions: list, scope: dict[str, object]) -> Iterator[dict[str, object]]:
        """The scopes the conditions `[0 <= i < N, j IN S, ...]` bind, in
        order (each variable over its values in increasing order)."""
        if not conditions:
            yield scope
            return
        first, rest = conditions[0], conditions[1:]
        name, values = self.binding(first, scope)
        for value in sorted(values, key=_order):
            yield from self.bound(rest, {**scope, name: value})

    def binding(self, condition, scope) -> tuple[str, frozenset]:
        if condition.data == "member" and _is_name(condition.children[0]):
            return str(condition.children[0].children[0]), self.s(condition.children[2], scope)
        if condition.data == "compare" and condition.children[0].data == "compare":
            low_node, op1, middle = condition.children[0].children
            op2, high_node = condition.children[1:]
            ops = {"<", "<=", "LE", "LEQ"}
            if _is_name(middle) and str(op1) in ops and str(op2) in ops:
                low = self.n(low_node, scope) + (1 if str(op1) in ("<", "LE") else 0)
                high = self.n(high_node, scope) - (1 if str(op2) in ("<", "LE") else 0)
                return str(middle.children[0]), frozenset(range(low, high + 1))
        raise self.error(condition, "expected a binding such as 'a <= i < b', 'a < i <= b' or 'i IN S'")

    def _big(self, node, scope, evaluate, combine):
        *conditions, body = node.children[1:]
        return combine([evaluate(body, inner) for inner in self.bound(conditions, scope)])

    def e_big_and(self, node, scope):
        return self._big(node, scope, self.f, conjunction)

    def e_big_or(self, node, scope):
        return self._big(node, scope, self.f, disjunction)

    def e_big_sum(self, node, scope):
        return self._big(node, scope, self.n, sum)

    def e_big_product(self, node, scope):
        return self._big(node, scope, self.n, lambda xs: functools.reduce(lambda a, b: a * b, xs, 1))

    def e_big_cup(self, node, scope):
        return self._big(node, scope, self.s, lambda xs: frozenset().union(*xs))

    def e_big_cap(self, node, scope):
        if len(node.children) < 3:
            raise self.error(node, "CAP[] needs a binding")
        return self._big(node, scope, self.s, lambda xs: frozenset.intersection(*xs) if xs else frozenset())

    # formulas

    def e_not(self, node, scope):
        return _not(self.f(node.children[1], scope))

    def e_next(self, node, scope):
        return ast.WeakNext(self.f(node.children[1], scope))

    def e_strong_next(self, node, scope):
        return ast.Next(self.f(node.children[1], scope))

    def e_always(self, node, scope):
        return ast.Always(self.f(node.children[1], scope))

    def e_eventually(self, node, scope):
        return ast.Eventually(self.f(node.children[1], scope))

    def e_next_n(self, node, scope):
        return _repeat(self.f(node.children[-1], scope), self.n(node.children[1], scope), ast.WeakNext)

    def e_strong_next_n(self, node, scope):
        return _repeat(self.f(node.children[-1], scope), self.n(node.children[1], scope), ast.Next)

    def _bounded(self, node, scope, combine, next_):
        """G[a:b] f / F[a:b] f as syfco unrolls them: next^a (f op next (f op ... next f))."""
        interval = node.children[1]
        if not (isinstance(interval, lark.Tree) and interval.data == "case"):
            raise self.error(interval, "expected an interval 'a : b'")
        low, high = self.n(interval.children[0], scope), self.n(interval.children[1], scope)
        if low > high:
            return ast.TRUE
        body = self.f(node.children[-1], scope)
        unrolled = body
        for _ in range(high - low):
            unrolled = combine([body, next_(unrolled)])
        return _repeat(unrolled, low, next_)

    def e_always_range(self, node, scope):
        return self._bounded(node, scope, conjunction, ast.WeakNext)

    def e_strong_always_range(self, node, scope):
        return self._bounded(node, scope, conjunction, ast.Next)

    def e_eventually_range(self, node, scope):
        return self._bounded(node, scope, disjunction, ast.WeakNext)

    def e_strong_eventually_range(self, node, scope):
        return self._bounded(node, scope, disjunction, ast.Next)

    def _binary(self, node, scope):
        a, _, b = node.children
        return self.f(a, scope), self.f(b, scope)

    def _chain(self, node, scope, kind: str) -> list[ast.Formula]:
        """The operands of a run of one associative operator (`a && b && ...`,
        nested to the left by the grammar), found without recursion: the
        datasets' Nim specifications chain thousands."""
        operands = []
        while isinstance(node, lark.Tree) and node.data == kind:
            operands.append(node.children[2])
            node = node.children[0]
        operands.append(node)
        return [self.f(x, scope) for x in reversed(operands)]

    def e_and(self, node, scope):
        return conjunction(self._chain(node, scope, node.data))

    def e_or(self, node, scope):
        return disjunction(self._chain(node, scope, node.data))

    def e_implies(self, node, scope):
        return implication(*self._binary(node, scope))

    def e_equiv(self, node, scope):
        return ast.Equiv(*self._binary(node, scope))

    def e_until(self, node, scope):
        return ast.Until(*self._binary(node, scope))

    def e_release(self, node, scope):
        return ast.Release(*self._binary(node, scope))

    def e_weak_until(self, node, scope):
        return ast.WeakUntil(*self._binary(node, scope))


def _is_name(node) -> bool:
    return isinstance(node, lark.Tree) and node.data == "name"


def _order(value: object):
    return (0, value, "") if isinstance(value, int) else (1, 0, repr(value))


def _describe(value: object) -> str:
    if isinstance(value, bool) or isinstance(value, ast.Const):
        return "a truth value"
    if isinstance(value, int):
        return f"the number {value}"
    if isinstance(value, frozenset):
        return "a set"
    if isinstance(value, Bus):
        return f"the bus {value.name}[{value.size}]"
    if isinstance(value, Signal):
        return f"the signal {value.name}"
    if value is EMPTY:
        return "no value (a case whose guard is false)"
    return "a formula"


def position(node) -> tuple[int, int]:
    if isinstance(node, lark.Token):
        return node.line or 0, node.column or 0
    if isinstance(node, lark.Tree) and not node.meta.empty:
        return node.meta.line, node.meta.column
    return 0, 0

