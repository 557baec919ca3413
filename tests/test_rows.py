"""rows.py: many BDDs as one stack under row bits above the atoms, and the
constructions that work on stacks (moves.py's product and minimization,
prefix.py's renumbering, the single component's transition functions).

`each` must give exactly what the operation gives row by row (BDDs are
canonical: the same functions are the same nodes); the product made in
chunks of pairs must be the product made one pair at a time; and a leaf
built by progression after the row bits went in above the atoms must be
the automaton of its formula (the atom levels are found, not counted)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import distinguishing_trace, minimal_num_states, reference_dfa
from support.strategies import formulas
from test_prefix_product import KEYS, Runner
from symsynth.automata import moves, rows
from symsynth.automata.bdd import and_exists, exists, swap
from symsynth.automata.normal import nnf
from symsynth.automata.products import OPS
from symsynth.automata.progression import Progression, minimize
from symsynth.logic import to_string

Z_BITS = 3


def _function(bdd, names: list[str], table: int):
    """The function over `names` whose truth table (minterm i: bit i) is `table`."""
    result = bdd.false
    for i in range(1 << len(names)):
        if table >> i & 1:
            result |= bdd.cube({name: bool(i >> k & 1) for k, name in enumerate(names)})
    return result


tables = st.integers(min_value=0, max_value=(1 << (1 << (len(KEYS) + Z_BITS))) - 1)


@settings(max_examples=150, deadline=None)
@given(st.lists(tables, min_size=1, max_size=70), st.lists(tables, min_size=70, max_size=70),
       st.sampled_from(["and", "exists", "swap", "and_exists"]))
def test_each_is_the_operation_row_by_row(left, right, op):
    """Row counts from 1 to 70 (powers of two and not), equal rows, the
    constants, over atoms and successor bits; the result of `each` is the
    list of the operation's results, node for node."""
    bdd = Progression(KEYS).bdd
    zs = moves.bits(bdd, "z", Z_BITS)
    cs = moves.bits(bdd, "c", Z_BITS)
    names = KEYS + zs
    xs = [_function(bdd, names, t) for t in left]
    ys = [_function(bdd, names, t) for t in right[:len(xs)]]
    relation = _function(bdd, zs + cs[:1], right[0])  # (a relation between z and one class bit)
    operations = {
        "and": lambda u, v: u & v,
        "exists": lambda u, v: exists(bdd, u, ["a", zs[1]]),
        "swap": lambda u, v: swap(bdd, u, dict(zip(zs, cs))),
        "and_exists": lambda u, v: and_exists(bdd, u, relation, zs),
    }
    operation = operations[op]
    assert rows.each(bdd, operation, xs, ys) == [operation(u, v) for u, v in zip(xs, ys)]
    assert rows.unstack(bdd, rows.stack(bdd, xs), len(xs)) == xs


@settings(max_examples=100, deadline=None)
@given(formulas(max_depth=3), formulas(max_depth=3), st.sampled_from(["and", "or", "implies", "equiv"]))
def test_a_product_made_in_chunks_is_the_product_made_pair_by_pair(f, g, op):
    """moves.product makes the pairs found and not yet made together, at
    most CHUNK at once: with chunks of one pair, two, or all of them, the
    same states in the same order, the same moves."""
    progression = Progression(KEYS)
    bdd = progression.bdd
    a, b = minimize(progression.dfa(nnf(f))), minimize(progression.dfa(nnf(g)))
    made = []
    saved = moves.CHUNK
    try:
        for chunk in (1, 2, saved):
            moves.CHUNK = chunk
            made.append(moves.product(bdd, a.moves, a.initial, a.accepting, b.moves, b.initial, b.accepting,
                                      OPS[op]))
    finally:
        moves.CHUNK = saved
    first = made[0]
    for other in made[1:]:
        assert (other.codes, other.accepting, other.moves, other.after, other.degrees) == \
            (first.codes, first.accepting, first.moves, first.after, first.degrees), (to_string(f), op, to_string(g))


@settings(max_examples=100, deadline=None)
@given(formulas(max_depth=3), formulas(max_depth=3))
def test_progression_after_the_row_bits_went_in_above_the_atoms(before, after):
    """A leaf made before the row bits exist and one made after (their
    insertion moves the atoms down the order): each is the minimal DFA of its
    formula."""
    progression = Progression(KEYS)
    first = minimize(progression.dfa(nnf(before)))
    rows.row_bits(progression.bdd, 2)
    assert progression.bdd.level_of_var(KEYS[0]) == rows.WIDTH  # (the atoms moved down)
    second = minimize(progression.dfa(nnf(after)))
    for formula, dfa in ((before, first), (after, second)):
        assert dfa.num_states == minimal_num_states(formula), to_string(formula)
        assert distinguishing_trace(Runner(dfa), reference_dfa(formula), KEYS) is None, to_string(formula)
