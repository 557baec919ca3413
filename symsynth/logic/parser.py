"""Parse LTLf text into the AST of `symsynth.logic.ast`.

The grammar is `grammars/ltlf.lark`, shipped as package data (its LALR
tables kept between runs: `lalr.py`).  A lark Transformer builds the frozen
AST; lark's exceptions are turned into one `LTLfSyntaxError` that names the
source, line and column.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable
from typing import Literal

import lark

from symsynth.errors import InputError, LTLfSyntaxError
from symsynth.logic import ast
from symsynth.logic.lalr import lalr_parser

NextSemantics = Literal["strong", "weak"]

# What a person calls each terminal, for "expected ..." messages.
_TERMINAL_NAMES = {
    "LPAR": "'('", "RPAR": "')'", "COMMA": "','",
    "EQUIV": "'<->'", "IMPLIES": "'->'", "OR": "'|'", "AND": "'&'",
    "UNTIL": "'U'", "RELEASE": "'R'", "RELEASE_V": "'V'", "WEAK_UNTIL": "'W'",
    "NOT": "'!'", "NEXT": "'X'", "STRONG_NEXT": "'X[!]'", "WEAK_NEXT": "'WX'",
    "WEAK_NEXT_N": "'N'", "EVENTUALLY": "'F'", "DIAMOND": "'<>'", "ALWAYS": "'G'",
    "BOX": "'[]'",
    "TRUE": "'true'", "FALSE": "'false'", "LAST": "'last'",
    "NAME": "an identifier", "NUMBER": "a number", "$END": "end of input",
}
_FORMULA_START = {"NOT"}  # only a place for a formula accepts "!"
_BINARY = {"EQUIV", "IMPLIES", "OR", "AND", "UNTIL", "RELEASE", "RELEASE_V", "WEAK_UNTIL"}

#: Formulas nested deeper than this (operators inside operators, after long
#: `&` and `|` chains are balanced) are refused: every pass over a formula
#: recurses once per level.
MAX_DEPTH = 200
#: `&` / `|` chains longer than this are balanced trees instead of left-leaning
#: ones, so that 10,000 conjuncts nest 14 deep, not 10,000.
BALANCE_FROM = 32


@functools.cache
def _parser(next_semantics: NextSemantics) -> lark.Lark:
    """The LALR parser with the AST built as it parses (lark's inline
    transformer): no parse tree, and no recursion however deep the input."""
    return lalr_parser("ltlf.lark", lexer="basic", propagate_positions=False, maybe_placeholders=False,
                       transformer=_ToAst(next_semantics))


class _Chain:
    """A run of one associative operator (`&` or `|`) being parsed: its
    operands, left to right; made a formula (`_done`) when something else
    takes it as an operand, or at the end."""

    __slots__ = ("node", "operands")

    def __init__(self, node: type, operands: list):
        self.node = node
        self.operands = operands


def _done(x):
    """A formula from a parsed operand: a `_Chain` becomes a left-leaning
    tree (as the grammar reads it) or, when long, a balanced one."""
    if not isinstance(x, _Chain):
        return x
    node, items = x.node, x.operands
    if len(items) <= BALANCE_FROM:
        result = items[0]
        for item in items[1:]:
            result = node(result, item)
        return result
    while len(items) > 1:  # pair neighbours, level by level
        items = [node(items[i], items[i + 1]) if i + 1 < len(items) else items[i]
                 for i in range(0, len(items), 2)]
    return items[0]


class _ToAst(lark.Transformer):
    """Parse tree -> AST, applied while parsing.  `X` means strong or weak
    next by convention."""

    def __init__(self, next_semantics: NextSemantics):
        super().__init__()
        self._next = ast.Next if next_semantics == "strong" else ast.WeakNext

    def _chain(self, node: type, c):
        left = c[0]
        if isinstance(left, _Chain) and left.node is node:
            left.operands.append(_done(c[2]))
            return left
        return _Chain(node, [_done(left), _done(c[2])])

    def true(self, _):
        return ast.TRUE

    def false(self, _):
        return ast.FALSE

    def last(self, _):
        return ast.Last()

    def atom(self, children):
        return ast.Atom(str(children[0]))

    def predicate(self, children):
        name, *args = children
        return ast.Atom(str(name), tuple(str(a) for a in args))

    def not_(self, c):
        return ast.Not(_done(c[1]))

    def next_(self, c):
        return self._next(_done(c[1]))

    def strong_next(self, c):
        return ast.Next(_done(c[1]))

    def weak_next(self, c):
        return ast.WeakNext(_done(c[1]))

    def eventually(self, c):
        return ast.Eventually(_done(c[1]))

    def always(self, c):
        return ast.Always(_done(c[1]))

    def until(self, c):
        return ast.Until(_done(c[0]), _done(c[2]))

    def release(self, c):
        return ast.Release(_done(c[0]), _done(c[2]))

    def weak_until(self, c):
        return ast.WeakUntil(_done(c[0]), _done(c[2]))

    def and_(self, c):
        return self._chain(ast.And, c)

    def or_(self, c):
        return self._chain(ast.Or, c)

    def implies(self, c):
        return ast.Implies(_done(c[0]), _done(c[2]))

    def equiv(self, c):
        return ast.Equiv(_done(c[0]), _done(c[2]))


#: Texts from this many characters on report their progress while parsed
#: (the parser reads about 300,000 characters a second).
PROGRESS_FROM = 1_000_000


def parse_ltlf(text: str, *, source: str = "<formula>", next_semantics: NextSemantics = "strong",
               progress: Callable[[int], None] | None = None) -> ast.Formula:
    """Parse `text` as an LTLf formula.

    `next_semantics="weak"` reads a plain `X` as weak next, as Lydia, Spot and
    SYNTCOMP's TLSF do; `X[!]` is strong next either way.  Raises
    `LTLfSyntaxError` naming `source`, line and column on a mistake.
    `progress(characters read)` is called now and then on a text of
    PROGRESS_FROM characters or more.
    """
    if next_semantics not in ("strong", "weak"):
        raise ValueError(f"next_semantics must be 'strong' or 'weak', not {next_semantics!r}")
    try:
        if progress is None or len(text) < PROGRESS_FROM:
            formula = _done(_parser(next_semantics).parse(text))
        else:  # token by token (lark's interactive parser), telling where it is
            interactive = _parser(next_semantics).parse_interactive(text)
            for count, token in enumerate(interactive.iter_parse()):
                if count % 8192 == 0:
                    progress(token.start_pos or 0)
            formula = _done(interactive.feed_eof())
            progress(len(text))
    except lark.UnexpectedInput as error:
        raise _syntax_error(text, source, error) from None
    _refuse_glued_operators(formula, text, source)
    depth = ast.depth(formula)
    if depth > MAX_DEPTH:
        raise LTLfTooDeep(f"{source}: the formula nests {depth} operators deep; symsynth reads at most "
                          f"{MAX_DEPTH} (long '&' and '|' chains count as balanced trees)")
    return formula


class LTLfTooDeep(InputError):
    """A formula nested beyond `MAX_DEPTH`."""


#: An identifier that is unary operators glued to an atom: `Fa`, `Xb`, `GFa`, `WXp1`.
_GLUED = re.compile(r"((?:WX|[XFGN])+)([A-Za-z_][A-Za-z0-9_]*)")
#: ... refused when the atom is a short name (a letter and digits, as in `Fp3`).
_SHORT = re.compile(r"[a-z][0-9]*")


def _refuse_glued_operators(formula: ast.Formula, text: str, source: str) -> None:
    """An `LTLfSyntaxError` for an atom named like unary operators glued to
    an atom (`Fa`, `Xb`, `GFa`): an identifier is read whole, so `Fa` would
    silently be an atom, not "eventually a".  Refused when the rest is an
    atom of the formula too (`G(a -> Fb) & b`) or a short name (a letter and
    digits: `Fa`, `Xp12`); `Found`, `Xpos` or `Gripper` stay atoms.  No atom
    of the public LTLf synthesis datasets or of symsynth's scenes has this
    form (they are lower case: `p12`, `heap_1_2`, `at(black, top)`)."""
    names = {a.name for a in ast.atoms(formula)}
    for atom in ast.atoms(formula):
        glued = _GLUED.fullmatch(atom.name)
        if glued is None or not (glued[2] in names or _SHORT.fullmatch(glued[2])):
            continue
        spaced = " ".join(re.findall(r"WX|[XFGN]", glued[1])) + " " + glued[2]
        found = re.search(rf"(?<![A-Za-z0-9_]){atom.name}(?![A-Za-z0-9_])", re.sub(r"#[^\n]*", _blank, text))
        raise _located(text, source, found.start() if found else 0,
                       f"'{atom.name}' would be one atom: did you mean '{spaced}'? (symsynth refuses "
                       f"atoms named like operators glued to an atom)")


def _blank(comment: re.Match) -> str:
    return " " * len(comment[0])


def _located(text: str, source: str, pos: int, message: str) -> LTLfSyntaxError:
    """The syntax error `message` at offset `pos` of `text`: line, column,
    and the line with a caret under the place."""
    line = text.count("\n", 0, pos) + 1
    line_start = text.rfind("\n", 0, pos) + 1
    column = pos - line_start + 1
    line_end = text.find("\n", pos)
    line_text = text[line_start: None if line_end < 0 else line_end]
    context = f"    {line_text}\n    {' ' * (column - 1)}^"
    return LTLfSyntaxError(source, line, column, context, message)


def _syntax_error(text: str, source: str, error: lark.UnexpectedInput) -> LTLfSyntaxError:
    if not re.sub(r"#[^\n]*", "", text).strip():
        return LTLfSyntaxError(source, 1, 1, "", "empty formula: expected a formula")
    pos = getattr(error, "pos_in_stream", None)
    token = getattr(error, "token", None)
    if isinstance(error, lark.UnexpectedToken) and token is not None and token.type == "$END":
        pos = len(text.rstrip())
    if pos is None:
        pos = len(text)
    return _located(text, source, pos, _explain(text, pos, error))


def _explain(text: str, pos: int, error: lark.UnexpectedInput) -> str:
    message = _explain_token(text, pos, error)
    glued = re.search(r"([A-Za-z_][A-Za-z0-9_]*)\s*$", text[:pos])
    if glued and len(glued[1]) > 1 and set(glued[1]) <= set("XFGNUWRV"):
        spaced = " ".join(glued[1])
        message += f" ('{glued[1]}' is one identifier; write '{spaced}' for the operators)"
    return message


def _explain_token(text: str, pos: int, error: lark.UnexpectedInput) -> str:
    if isinstance(error, lark.UnexpectedCharacters):
        char = text[pos]
        if char == "[" and text[:pos].rstrip().endswith("X"):
            return "'X[' must be followed by '!]' (strong next is written 'X[!]')"
        allowed = _expected_text(set(error.allowed or ()))
        return f"unexpected character {char!r}" + (f"; expected {allowed}" if allowed else "")
    token = getattr(error, "token", None)
    expected = set(getattr(error, "expected", ()) or ())
    found = "end of input" if token is None or token.type == "$END" else repr(str(token))
    if token is not None and token.type == "$END" and expected & _FORMULA_START:
        return "unexpected end of input; expected a formula after the operator"
    if token is not None and token.type == "RPAR" and expected & _FORMULA_START:
        return f"unexpected {found}; expected a formula"
    if token is not None and token.type in _BINARY and expected & _FORMULA_START:
        return f"unexpected {found}: a binary operator needs a formula on its left"
    return f"unexpected {found}; expected {_expected_text(expected)}"


def _expected_text(expected: set[str]) -> str:
    if expected & _FORMULA_START:
        return "a formula (an atom, 'true', 'false', 'last', '(' or a unary operator)"
    if expected & _BINARY:
        closing = sorted(_TERMINAL_NAMES.get(t, t) for t in expected - _BINARY - {"LPAR"})
        tail = f" or {', '.join(closing)}" if closing else ""
        return f"a binary operator ('&', '|', '->', '<->', 'U', 'R', 'W'){tail}"
    if {"NAME", "NUMBER"} <= expected:
        return "an argument (an identifier or a number)"
    names = sorted(_TERMINAL_NAMES.get(t, t) for t in expected)
    return ", ".join(names) if names else "something else"
