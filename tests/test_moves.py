"""moves.py: a DFA's transitions as one BDD per state over the atoms and
the successor's bits, and the product and minimization made on them,
against the reference DFA (tests/support/reference.py: no BDDs, Moore's
rounds over explicit letters) and against the guard-based constructions."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import distinguishing_trace, minimal_num_states, reference_dfa
from support.strategies import formulas
from test_prefix_product import KEYS, Runner, bounded
from symsynth.automata import moves
from symsynth.automata.prefix import prefix_product_moves
from symsynth.automata.products import explicit_product, moves_product, reject_at_start
from symsynth.automata.normal import nnf
from symsynth.automata.progression import GuardedDFA, Progression, minimize
from symsynth.logic import ast, to_string

OPS = {"and": ast.And, "or": ast.Or, "implies": ast.Implies, "equiv": ast.Equiv}


def moves_only(dfa: GuardedDFA) -> GuardedDFA:
    """The same DFA given by its moves alone (its edges made from them when asked)."""
    return GuardedDFA(dfa.bdd, dfa.initial, list(dfa.accepting), moves=moves.encode_all(dfa.bdd, dfa.edges))


@settings(max_examples=150, deadline=None)
@given(formulas(max_depth=3))
def test_edges_come_back_from_the_moves(formula):
    progression = Progression(KEYS)
    dfa = progression.dfa(nnf(formula))  # not minimized: some states equivalent
    back = moves.decode_all(dfa.bdd, moves.encode_all(dfa.bdd, dfa.edges))
    assert back == dfa.edges, to_string(formula)
    again = moves_only(dfa)
    assert again.degrees() == [len(out) for out in dfa.edges]
    assert [sorted(x) for x in again.successor_lists()] == [sorted(out) for out in dfa.edges]


@settings(max_examples=200, deadline=None)
@given(formulas(max_depth=3), formulas(max_depth=3), st.sampled_from(sorted(OPS)))
def test_the_product_of_moves_is_the_minimal_dfa_of_the_combination(f, g, op):
    progression = Progression(KEYS)
    a, b = minimize(progression.dfa(nnf(f))), minimize(progression.dfa(nnf(g)))
    whole = OPS[op](f, g)
    text = to_string(whole)
    got = moves_product(a, b, op, None)
    assert not got.has_edges(), text  # made and minimized on moves alone
    assert not got.accepting[got.initial], text  # traces are non-empty
    assert got.num_states == minimal_num_states(whole), text
    assert distinguishing_trace(Runner(got), reference_dfa(whole), KEYS) is None, text
    by_guards = explicit_product(a, b, op, moves_pairs=float("inf"))
    assert by_guards.has_edges() and by_guards.num_states == got.num_states, text
    assert got.num_edges == by_guards.num_edges, text


@settings(max_examples=150, deadline=None)
@given(formulas(max_depth=3))
def test_minimizing_moves_agrees_with_minimizing_guards(formula):
    progression = Progression(KEYS)
    dfa = progression.dfa(nnf(formula))
    by_guards = minimize(dfa)
    by_moves = minimize(moves_only(dfa))
    text = to_string(formula)
    assert by_moves.num_states == by_guards.num_states == minimal_num_states(formula), text
    assert by_moves.initial == 0 and not by_moves.accepting[0], text
    assert distinguishing_trace(Runner(by_moves), Runner(by_guards), KEYS) is None, text


def _two_states(bdd) -> GuardedDFA:
    """Over the atom `a`: the start accepts and comes back to itself on `a`;
    `!a` leads to a rejecting sink.  Its language over all traces: `a*`."""
    a = bdd.var("a")
    return GuardedDFA(bdd, 0, [True, False], [{0: a, 1: ~a}, {1: bdd.true}])


def test_an_accepting_start_entered_again_gets_a_fresh_start_one_bit_wider():
    """By hand: `a*` without the empty trace is `a+`, three states (the
    fresh start, 'a+ read', the sink); two states take one bit, three two:
    the moves gain a bit that is 0 in every successor."""
    bdd = Progression(KEYS).bdd
    guards = reject_at_start(_two_states(bdd))
    with_moves = reject_at_start(moves_only(_two_states(bdd)))
    assert not with_moves.has_edges()
    assert with_moves.num_states == guards.num_states == 3
    assert with_moves.initial == 2 and with_moves.accepting == [True, False, False]
    assert with_moves.edges == guards.edges == [{0: bdd.var("a"), 1: ~bdd.var("a")}, {1: bdd.true},
                                                {0: bdd.var("a"), 1: ~bdd.var("a")}]
    smallest = minimize(with_moves)
    plus = ast.Until(ast.Atom("a"), ast.And(ast.Atom("a"), ast.Last()))  # a U (a & last): a+
    assert smallest.num_states == minimal_num_states(plus) == 3
    assert distinguishing_trace(Runner(smallest), reference_dfa(plus), KEYS) is None


def test_numbers_lists_every_member_of_a_set_with_absent_bits():
    """A set given by a BDD that skips some of its bits (both values)."""
    bdd = Progression(KEYS).bdd
    names = moves.bits(bdd, "c", 4)
    x0, x2 = bdd.var(names[0]), bdd.var(names[2])
    got = sorted(moves.numbers(bdd, x0 & ~x2, names))  # bit 0 set, bit 2 clear, bits 1 and 3 free
    assert got == sorted(n for n in range(16) if n & 1 and not n & 4)
    assert moves.numbers(bdd, bdd.false, names) == []


@given(st.integers(1, 7), st.integers(0, 130))
def test_cubes_are_the_cube_of_each_number(width, count):
    """moves.cubes, made from the cubes of the numbers halved, against the
    conjunction of every bit's literal (a wrong literal or a number left
    out fails here)."""
    bdd = Progression(KEYS).bdd
    names = moves.bits(bdd, "z", width)
    count = min(count, 1 << width)
    assert moves.cubes(bdd, names, count) == [moves.cube(bdd, names, value) for value in range(count)]


@settings(max_examples=200, deadline=None)
@given(formulas(max_depth=3), bounded(), st.sampled_from(["and", "or"]))
def test_the_prefix_product_of_moves_is_the_minimal_dfa_of_the_combination(big_formula, small_formula, op):
    """As tests/test_prefix_product.py's, with the large operand given by its
    moves only (a dense product's or an invariant's)."""
    progression = Progression(KEYS)
    big = moves_only(minimize(progression.dfa(nnf(big_formula))))
    small = minimize(progression.dfa(nnf(small_formula)))
    whole = (ast.And if op == "and" else ast.Or)(big_formula, small_formula)
    text = to_string(whole)
    got = prefix_product_moves(big, small, op)
    if got is None:  # only when the small operand decides the product from the start
        assert small.num_states <= 2 and len(small.edges[small.initial]) == 1, text
        return
    assert not got.has_edges(), text
    assert not got.accepting[got.initial], text  # (anywhere: kept in place when every state is reached)
    assert got.num_states == minimal_num_states(whole), text
    assert got.degrees() == [len(out) for out in got.edges], text
    assert distinguishing_trace(Runner(got), reference_dfa(whole), KEYS) is None, text
