"""`prefix_product`: the product of a DFA with one that looks a bounded
number of letters ahead, made without partition refinement, against the
reference DFA of the conjunction / disjunction (tests/support/reference.py:
no BDDs, Moore's rounds over explicit letters) and against the general
explicit product."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import distinguishing_trace, minimal_num_states, reference_dfa
from support.strategies import formulas
from symsynth.automata.prefix import prefix_product
from symsynth.automata.products import explicit_product
from symsynth.automata.normal import nnf
from symsynth.automata.progression import GuardedDFA, Progression, minimize
from symsynth.logic import ast, to_string
from symsynth.automata.bdd import cofactor

ATOMS = ("a", "b", "c")
KEYS = list(ATOMS)


def bounded(max_depth: int = 3) -> st.SearchStrategy[ast.Formula]:
    """Formulas without `U`, `R`, `W`, `F`, `G`: each looks at most
    `max_depth` letters ahead."""
    leaf = st.sampled_from([ast.Atom(x) for x in ATOMS] + [ast.TRUE, ast.FALSE, ast.Last()])
    level = leaf
    for _ in range(max_depth):
        level = st.one_of(
            leaf,
            st.builds(lambda op, f: op(f), st.sampled_from([ast.Not, ast.Next, ast.WeakNext]), level),
            st.builds(lambda op, f, g: op(f, g), st.sampled_from([ast.And, ast.Or, ast.Implies]), level, level))
    return level


class Runner:
    def __init__(self, dfa: GuardedDFA):
        self.dfa, self.initial = dfa, dfa.initial

    def step(self, state, letter):
        bdd = self.dfa.bdd
        values = {x: x in letter for x in KEYS}
        (hit,) = [t for t, g in self.dfa.edges[state].items() if cofactor(bdd, values, g) == bdd.true]
        return hit

    def is_accepting(self, state):
        return self.dfa.accepting[state]


def leaf_dfa(progression: Progression, formula: ast.Formula) -> GuardedDFA:
    return minimize(progression.dfa(nnf(formula)))


@settings(max_examples=300, deadline=None)
@given(formulas(max_depth=3), bounded(), st.sampled_from(["and", "or"]))
def test_the_prefix_product_is_the_minimal_dfa_of_the_combination(big_formula, small_formula, op):
    progression = Progression(KEYS)
    big, small = leaf_dfa(progression, big_formula), leaf_dfa(progression, small_formula)
    got = prefix_product(big, small, op)
    assert got is not None, to_string(small_formula)  # a bounded formula's DFA is acyclic but for sinks
    whole = (ast.And if op == "and" else ast.Or)(big_formula, small_formula)
    text = to_string(whole)
    assert not got.accepting[got.initial], text  # traces are non-empty
    assert got.num_states == minimal_num_states(whole), text
    assert distinguishing_trace(Runner(got), reference_dfa(whole), KEYS) is None, text
    general = explicit_product(big, small, op, max_edges=None)
    assert general.num_states == got.num_states


def test_an_operand_with_a_cycle_is_left_to_the_general_product():
    progression = Progression(KEYS)
    big = leaf_dfa(progression, ast.Eventually(ast.Atom("a")))
    cyclic = leaf_dfa(progression, ast.Always(ast.Atom("b")))
    assert prefix_product(big, cyclic, "and") is None


def test_an_initial_value_by_hand():
    """F a & !b: the second operand (start; `!b` read: accepting sink;
    `b` read: rejecting sink) only restricts the first letter.  The minimal
    DFA: the start (on a & !b to 'a seen', on !a & !b to 'waiting', on b to
    the rejecting sink), 'waiting' (F a's own start, re-entered: it must
    not be the initial state, which rejects `b` where 'waiting' does not),
    'a seen' (accepting sink) and the rejecting sink: 4 states, where F a
    alone has 2."""
    a, b = ast.Atom("a"), ast.Atom("b")
    progression = Progression(KEYS)
    big = leaf_dfa(progression, ast.Eventually(a))
    small = leaf_dfa(progression, ast.Not(b))
    assert big.num_states == 2 and small.num_states == 3
    got = prefix_product(big, small, "and")
    assert got.num_states == 4
    run = Runner(got)
    state = run.step(got.initial, frozenset())
    assert not got.accepting[state] and got.accepting[run.step(state, frozenset({"a", "b"}))]
    assert not got.accepting[run.step(got.initial, frozenset({"a", "b"}))]
