"""The LTLf parser and printer: round trips, precedence, spellings, error messages."""

from __future__ import annotations

import pytest
from hypothesis import given, settings

from support.strategies import formula_texts, parser_formulas
from symsynth.errors import LTLfSyntaxError
from symsynth.logic import atoms, parse_ltlf, to_string
from symsynth.logic.ast import (
    FALSE, TRUE, Always, And, Atom, Equiv, Eventually, Implies, Last, Next, Not, Or,
    Release, Until, WeakNext, WeakUntil,
)

a, b, c, d = Atom("a"), Atom("b"), Atom("c"), Atom("d")


# ------------------------------------------------------------- round trips


@settings(max_examples=200, deadline=None)
@given(formula_texts())
def test_text_from_the_grammar_parses_to_the_intended_tree(text_and_formula):
    text, formula = text_and_formula
    assert parse_ltlf(text) == formula


@settings(max_examples=200, deadline=None)
@given(formula_texts(next_semantics="weak"))
def test_text_from_the_grammar_parses_to_the_intended_tree_with_weak_next(text_and_formula):
    # under the weak convention plain X is WX; X[!] stays strong
    text, formula = text_and_formula
    assert parse_ltlf(text, next_semantics="weak") == formula


@settings(max_examples=200, deadline=None)
@given(parser_formulas())
def test_print_then_parse_gives_the_same_tree(formula):
    assert parse_ltlf(to_string(formula)) == formula


@settings(max_examples=200, deadline=None)
@given(formula_texts())
def test_parse_print_parse_is_stable(text_and_formula):
    text, _ = text_and_formula
    once = parse_ltlf(text)
    printed = to_string(once)
    assert parse_ltlf(printed) == once
    assert to_string(parse_ltlf(printed)) == printed


# ------------------------------------------------- precedence and spellings


@pytest.mark.parametrize(("text", "expected"), [
    # binary temporal operators bind tighter than the Boolean ones
    ("a & b U c", And(a, Until(b, c))),
    ("a U b & c", And(Until(a, b), c)),
    ("a | b R c", Or(a, Release(b, c))),
    ("a W b -> c", Implies(WeakUntil(a, b), c)),
    # & tighter than |, | tighter than ->, -> tighter than <->
    ("a | b & c", Or(a, And(b, c))),
    ("a & b | c & d", Or(And(a, b), And(c, d))),
    ("a -> b | c", Implies(a, Or(b, c))),
    ("a <-> b -> c", Equiv(a, Implies(b, c))),
    ("a -> b <-> c", Equiv(Implies(a, b), c)),
    # associativity: ->, <->, U, R, W to the right; &, | to the left
    ("a -> b -> c", Implies(a, Implies(b, c))),
    ("a <-> b <-> c", Equiv(a, Equiv(b, c))),
    ("a U b U c", Until(a, Until(b, c))),
    ("a R b R c", Release(a, Release(b, c))),
    ("a W b U c", WeakUntil(a, Until(b, c))),
    ("a & b & c", And(And(a, b), c)),
    ("a | b | c", Or(Or(a, b), c)),
    ("(a -> b) -> c", Implies(Implies(a, b), c)),
    # unary operators bind tighter than every binary one
    ("!a & b", And(Not(a), b)),
    ("!a U b", Until(Not(a), b)),
    ("F a U b", Until(Eventually(a), b)),
    ("G a -> F b", Implies(Always(a), Eventually(b))),
    ("X a & b", And(Next(a), b)),
    ("!F G a", Not(Eventually(Always(a)))),
    ("G F a", Always(Eventually(a))),
    ("G(a -> F b)", Always(Implies(a, Eventually(b)))),
    # keywords versus identifiers
    ("Found", Atom("Found")),
    ("F a", Eventually(a)),
    ("F(a)", Eventually(a)),
    ("Found U Gripper", Until(Atom("Found"), Atom("Gripper"))),
    ("lastly", Atom("lastly")),
    ("true_or_false", Atom("true_or_false")),
    ("WXab", Atom("WXab")),
    ("last", Last()),
    ("true", TRUE),
    ("false", FALSE),
    # next operators: X is strong by default, X[!] always strong, N and WX weak
    ("X a", Next(a)),
    ("X[!] a", Next(a)),
    ("X[!]a", Next(a)),
    ("WX a", WeakNext(a)),
    ("N a", WeakNext(a)),
    ("X WX N a", Next(WeakNext(WeakNext(a)))),
    # alternative spellings
    ("<> a", Eventually(a)),
    ("[] a", Always(a)),
    ("[]<>a", Always(Eventually(a))),
    ("a V b", Release(a, b)),
    ("a && b || c", Or(And(a, b), c)),
    ("a => b <=> c", Equiv(Implies(a, b), c)),
    ("~a", Not(a)),
    # comments and line breaks are ignored
    ("G(a  # first\n -> F b)  # second", Always(Implies(a, Eventually(b)))),
    # predicate atoms
    ("at(black, top)", Atom("at", ("black", "top"))),
    ("at(white, 1)", Atom("at", ("white", "1"))),
    ("at( black,top )", Atom("at", ("black", "top"))),
    ("on(b1, b2, table)", Atom("on", ("b1", "b2", "table"))),
    ("F at(black, top) & !at(white, 1)",
     And(Eventually(Atom("at", ("black", "top"))), Not(Atom("at", ("white", "1"))))),
])
def test_parses_to(text, expected):
    assert parse_ltlf(text) == expected


def test_predicate_atom_key_is_its_canonical_text():
    formula = parse_ltlf("at( black ,top) U at(white,1)")
    assert [x.key for x in atoms(formula)] == ["at(black, top)", "at(white, 1)"]
    assert to_string(formula) == "at(black, top) U at(white, 1)"


def test_plain_x_is_weak_next_under_the_weak_convention():
    assert parse_ltlf("X a", next_semantics="weak") == WeakNext(a)
    assert parse_ltlf("X X[!] a", next_semantics="weak") == WeakNext(Next(a))
    assert parse_ltlf("X[!] a", next_semantics="weak") == Next(a)
    assert parse_ltlf("WX a", next_semantics="weak") == WeakNext(a)
    assert parse_ltlf("X a", next_semantics="strong") == Next(a)


def test_unknown_next_convention_is_rejected():
    with pytest.raises(ValueError):
        parse_ltlf("X a", next_semantics="medium")


def test_printer_uses_the_fewest_parentheses():
    assert to_string(And(a, Until(b, c))) == "a & b U c"
    assert to_string(Until(And(a, b), c)) == "(a & b) U c"
    assert to_string(Implies(a, Implies(b, c))) == "a -> b -> c"
    assert to_string(Implies(Implies(a, b), c)) == "(a -> b) -> c"
    assert to_string(And(a, And(b, c))) == "a & (b & c)"
    assert to_string(Not(Until(a, b))) == "!(a U b)"
    assert to_string(Eventually(Next(WeakNext(a)))) == "F X WX a"


@pytest.mark.parametrize("text", ["X", "F", "G", "N", "WX", "U", "a U U", "W W W", "!R", "F V"])
def test_keywords_that_look_like_identifiers_are_reserved(text):
    # grammars/ltlf.lark: "Operator keywords that look like identifiers (X, F,
    # G, U, R, V, W, N, WX, true, false, last) are reserved" -- so none of
    # them may be read as an atom, wherever it stands.
    with pytest.raises(LTLfSyntaxError):
        parse_ltlf(text)


# ---------------------------------------------------------------- mistakes


def _caret_column(message: str, source_line: str) -> int:
    """The 1-based column the caret under `source_line` points at, read off the message."""
    lines = message.splitlines()
    for i, line in enumerate(lines[:-1]):
        if line.endswith(source_line) and lines[i + 1].strip() == "^":
            indent = len(line) - len(source_line)
            return lines[i + 1].index("^") - indent + 1
    raise AssertionError(f"no caret under {source_line!r} in:\n{message}")


MISTAKES = [
    # (text, line, column) -- the column of the offending character, or one
    # past the last non-blank character when the input ends too early
    ("(a & b", 1, 7),               # missing closing parenthesis
    ("G(a -> F b", 1, 11),          # missing closing parenthesis after a unary operator
    ("a ^ b", 1, 3),                # unknown operator
    ("a $ b", 1, 3),                # unknown character
    ("a <- b", 1, 3),               # reversed arrow
    ("a &", 1, 4),                  # dangling binary operator
    ("a -> ", 1, 5),                # dangling binary operator, trailing blank
    ("& a", 1, 1),                  # binary operator without a left side
    ("a & & b", 1, 5),              # doubled binary operator
    ("X[ a", 1, 2),                 # X[ without !]
    ("a b", 1, 3),                  # two atoms side by side
    ("GF a", 1, 4),                 # glued operators form one identifier
    ("Fa", 1, 1),                   # an operator glued to a short atom: refused with a hint
    ("a U\n  GFb", 2, 3),           # ... on line 2
    ("Xpos -> G pos", 1, 1),        # ... to an atom of the formula
    ("at(black, top", 1, 14),       # unclosed predicate atom
    ("at(a,)", 1, 6),               # missing argument
    ("a)", 1, 2),                   # unbalanced closing parenthesis
    ("()", 1, 2),                   # empty parentheses
    ("F", 1, 2),                    # unary operator without argument
    ("a\n& (b |\n c", 3, 3),        # unclosed parenthesis, reported on the last line
    ("G(a ->\n  F b c)", 2, 7),     # two atoms side by side on line 2
]


@pytest.mark.parametrize(("text", "line", "column"), MISTAKES)
def test_syntax_error_names_line_and_column_with_a_caret(text, line, column):
    with pytest.raises(LTLfSyntaxError) as info:
        parse_ltlf(text, source="spec.ltlf")
    error = info.value
    assert (error.line, error.column) == (line, column)
    message = str(error)
    assert message.startswith(f"spec.ltlf:{line}:{column}:")
    source_line = text.split("\n")[line - 1]
    assert _caret_column(message, source_line) == column


@pytest.mark.parametrize("text", ["", "   ", "\n\t\n"])
def test_empty_input_is_a_syntax_error_at_the_start(text):
    with pytest.raises(LTLfSyntaxError) as info:
        parse_ltlf(text)
    assert (info.value.line, info.value.column) == (1, 1)
    assert "empty" in str(info.value)
    assert str(info.value).startswith("<formula>:1:1:")


def test_messages_explain_the_mistake():
    def message(text):
        with pytest.raises(LTLfSyntaxError) as info:
            parse_ltlf(text)
        return str(info.value)

    assert "X[!]" in message("X[ a")
    assert "'G F'" in message("GF a")
    assert "')'" in message("(a & b")
    assert "'^'" in message("a ^ b")
