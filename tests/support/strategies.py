"""Hypothesis strategies for LTLf: formulas (as ASTs and as text) and traces.

`formulas()` builds ASTs directly from `symsynth.logic.ast`, one level of
nesting at a time, so the depth bound is exact.  `formula_texts()` renders
such an AST with the grammar's alternative spellings (`<>`, `[]`, `V`, `N`,
`X[!]`, `&&`, `=>`, `~`, ...), random spacing and redundant parentheses, and
returns the text together with the AST it must parse to -- an expected value
that does not come from the parser under test.
"""

from __future__ import annotations

from hypothesis import strategies as st

from symsynth.logic import ast

ATOMS = ("a", "b", "c")

UNARY = (ast.Not, ast.Next, ast.WeakNext, ast.Eventually, ast.Always)
BINARY = (ast.And, ast.Or, ast.Implies, ast.Equiv, ast.Until, ast.Release, ast.WeakUntil)


def leaves(atom_names=ATOMS) -> st.SearchStrategy[ast.Formula]:
    return st.one_of(
        st.sampled_from([ast.Atom(name) for name in atom_names]),
        st.sampled_from([ast.TRUE, ast.FALSE, ast.Last()]),
    )


def formulas(max_depth: int = 4, atom_names=ATOMS,
             leaf_strategy: st.SearchStrategy[ast.Formula] | None = None,
             ) -> st.SearchStrategy[ast.Formula]:
    """Formulas of nesting depth at most `max_depth` over every LTLf operator."""
    leaf = leaf_strategy if leaf_strategy is not None else leaves(atom_names)
    level = leaf
    for _ in range(max_depth):
        level = st.one_of(
            leaf,
            st.builds(lambda op, f: op(f), st.sampled_from(UNARY), level),
            st.builds(lambda op, f, g: op(f, g), st.sampled_from(BINARY), level, level),
        )
    return level


def letters(atom_names=ATOMS) -> st.SearchStrategy[frozenset[str]]:
    return st.frozensets(st.sampled_from(atom_names))


def traces(atom_names=ATOMS, max_length: int = 6) -> st.SearchStrategy[list[frozenset[str]]]:
    """Non-empty finite traces; a letter is the set of atoms that are true."""
    return st.lists(letters(atom_names), min_size=1, max_size=max_length)


def weaken(f: ast.Formula) -> ast.Formula:
    """`f` with every strong next replaced by weak next."""
    match f:
        case ast.Next(g):
            return ast.WeakNext(weaken(g))
        case ast.Not(g) | ast.WeakNext(g) | ast.Eventually(g) | ast.Always(g):
            return type(f)(weaken(g))
        case ast.And(g, h) | ast.Or(g, h) | ast.Implies(g, h) | ast.Equiv(g, h) \
                | ast.Until(g, h) | ast.Release(g, h) | ast.WeakUntil(g, h):
            return type(f)(weaken(g), weaken(h))
    return f


# --------------------------------------------------------- formula texts

# Identifiers that start like keywords but are not keywords.
TRICKY_NAMES = ("a", "b", "Found", "Xbox", "GF", "WXcc", "Nope", "last1", "true_", "Un", "_x", "X1")
PREDICATES = (
    ast.Atom("at", ("black", "top")),
    ast.Atom("at", ("white", "1")),
    ast.Atom("on", ("b1", "b2", "table")),
    ast.Atom("occupied", ("l3",)),
)

_SPELLINGS = {
    ast.Not: ("!", "~"),
    ast.Eventually: ("F", "<>"),
    ast.Always: ("G", "[]"),
    ast.And: ("&", "&&"),
    ast.Or: ("|", "||"),
    ast.Implies: ("->", "=>"),
    ast.Equiv: ("<->", "<=>"),
    ast.Until: ("U",),
    ast.Release: ("R", "V"),
    ast.WeakUntil: ("W",),
}


def parser_formulas(max_depth: int = 4) -> st.SearchStrategy[ast.Formula]:
    """Formulas whose atoms include keyword-like names and predicate atoms."""
    leaf = st.one_of(
        st.sampled_from([ast.Atom(n) for n in TRICKY_NAMES]),
        st.sampled_from(PREDICATES),
        st.sampled_from([ast.TRUE, ast.FALSE, ast.Last()]),
    )
    return formulas(max_depth, leaf_strategy=leaf)


@st.composite
def formula_texts(draw, next_semantics: str = "strong", max_depth: int = 4):
    """(text, expected AST) for `parse_ltlf(text, next_semantics=...)`."""
    formula = draw(parser_formulas(max_depth))
    return _render(draw, formula, next_semantics), formula


def _space(draw) -> str:
    return draw(st.sampled_from(["", " ", "  ", "\n", "\t"]))


def _render(draw, f: ast.Formula, next_semantics: str) -> str:
    text = _render_bare(draw, f, next_semantics)
    if draw(st.booleans()):
        text = f"({_space(draw)}{text}{_space(draw)})"
    return text


def _render_bare(draw, f: ast.Formula, next_semantics: str) -> str:
    match f:
        case ast.Const(value):
            return "true" if value else "false"
        case ast.Last():
            return "last"
        case ast.Atom(name, args):
            if not args:
                return name
            sep = [f"{_space(draw)},{_space(draw)}" for _ in args[1:]]
            inner = args[0] + "".join(s + a for s, a in zip(sep, args[1:]))
            return f"{name}({_space(draw)}{inner}{_space(draw)})"
    if isinstance(f, UNARY):
        if isinstance(f, ast.Next):
            options = ("X[!]",) if next_semantics == "weak" else ("X", "X[!]")
        elif isinstance(f, ast.WeakNext):
            options = ("WX", "N", "X") if next_semantics == "weak" else ("WX", "N")
        else:
            options = _SPELLINGS[type(f)]
        op = draw(st.sampled_from(options))
        return f"{op}{_separator(draw, op)}{_operand(draw, f.arg, next_semantics)}"
    op = draw(st.sampled_from(_SPELLINGS[type(f)]))
    left = _operand(draw, f.left, next_semantics)
    right = _operand(draw, f.right, next_semantics)
    return f"{left}{_separator(draw, op)}{op}{_separator(draw, op)}{right}"


def _separator(draw, op: str) -> str:
    """Space around an operator; a word operator (F, U, WX, ...) must not touch a name."""
    space = _space(draw)
    return " " + space if op[-1].isalpha() else space


def _operand(draw, f: ast.Formula, next_semantics: str) -> str:
    """An operand of a unary or binary operator: parenthesized unless it binds tighter."""
    tight = isinstance(f, (ast.Const, ast.Last, ast.Atom, *UNARY))
    if tight and draw(st.booleans()):
        return _render(draw, f, next_semantics)
    return f"({_space(draw)}{_render(draw, f, next_semantics)}{_space(draw)})"
