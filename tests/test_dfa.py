"""LTLf -> minimal DFA, checked against the reference semantics and tests/support/reference.py.

Expected values come from `holds` (the semantics), from the explicit
progression DFA of tests/support/reference.py (no BDDs) and from hand derivations
of Myhill-Nerode classes written next to each case.
"""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import (
    JsonDFA, all_traces, distinguishing_trace, letters, minimal_num_states, minimize, reference_dfa,
)
from support.strategies import formulas, traces, weaken
from symsynth.automata import ExplicitDFA, SymbolicDFA, compile_ltlf
from symsynth.logic import ast, atoms, holds, parse_ltlf, to_string

SETTINGS = settings(max_examples=150, deadline=None)
FEW = settings(max_examples=60, deadline=None)


def keys(formula: ast.Formula) -> set[str]:
    return {x.key for x in atoms(formula)}


# ------------------------------------------------------- language = holds


@SETTINGS
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=5))
def test_accepts_agrees_with_the_semantics(formula, trace_list):
    dfa = compile_ltlf(formula)
    for trace in trace_list:
        assert dfa.accepts(trace) == holds(formula, trace), (to_string(formula), trace)


@SETTINGS
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=5))
def test_weak_next_convention_reads_plain_x_as_weak_next(formula, trace_list):
    # to_string writes strong next as `X` and weak next as `WX`; under the weak
    # convention both mean weak next, which `weaken` spells out on the AST.
    dfa = compile_ltlf(to_string(formula), next_semantics="weak")
    expected = weaken(formula)
    for trace in trace_list:
        assert dfa.accepts(trace) == holds(expected, trace), (to_string(formula), trace)


@FEW
@given(formulas(max_depth=4), traces())
def test_text_and_tree_give_the_same_automaton(formula, trace):
    from_text = compile_ltlf(to_string(formula), next_semantics="strong")
    from_tree = compile_ltlf(formula)
    assert from_text.num_states == from_tree.num_states
    assert from_text.accepts(trace) == from_tree.accepts(trace)


@FEW
@given(formulas(max_depth=3), traces())
def test_step_and_is_accepting_agree_with_accepts(formula, trace):
    dfa = compile_ltlf(formula)
    state = dfa.initial
    assert not dfa.is_accepting(state)
    for letter in trace:
        state = dfa.step(state, letter)
    assert dfa.is_accepting(state) == dfa.accepts(trace) == holds(formula, trace)


@FEW
@given(formulas(max_depth=3))
def test_empty_trace_is_never_accepted(formula):
    dfa = compile_ltlf(formula)
    assert not dfa.accepts([])
    assert not dfa.to_explicit().accepts([])


@FEW
@given(formulas(max_depth=3))
def test_atoms_are_the_formula_atoms(formula):
    dfa = compile_ltlf(formula)
    assert isinstance(dfa, SymbolicDFA)
    assert set(dfa.atoms) == keys(formula)
    assert len(dfa.atoms) == len(set(dfa.atoms))


# -------------------------------------------------- minimality, explicit form


def test_reference_oracle_agrees_with_the_semantics():
    """The oracle itself, on every trace up to length 4 of a few formulas."""
    for text in ["G(a -> F b)", "a U (b R c)", "!(a W X b)", "WX last <-> F(a & last)",
                 "(a <-> X b) U G c", "F a & F b", "X(a R WX b)"]:
        formula = parse_ltlf(text)
        dfa = reference_dfa(formula)
        for trace in all_traces(keys(formula), 4):
            assert dfa.accepts(trace) == holds(formula, trace), (text, trace)
        assert distinguishing_trace(dfa, minimize(dfa), keys(formula)) is None


@SETTINGS
@given(formulas(max_depth=4))
def test_num_states_is_the_myhill_nerode_index(formula):
    dfa = compile_ltlf(formula)
    assert dfa.num_states == minimal_num_states(formula), to_string(formula)


def check_explicit(explicit: ExplicitDFA, formula: ast.Formula) -> None:
    """Complete, deterministic, minimal and language-equal to the reference DFA."""
    assert set(explicit.atoms) == keys(formula)
    states = range(explicit.num_states)
    assert explicit.initial in states
    assert explicit.initial not in explicit.accepting
    assert explicit.accepting <= set(states)
    for src, _, dst in explicit.transitions:
        assert src in states and dst in states
    guards = {s: [] for s in states}
    for src, guard, dst in explicit.transitions:
        guards[src].append((parse_ltlf(guard), dst, guard))
    for s in states:
        for letter in letters(explicit.atoms):
            enabled = [(text, dst) for g, dst, text in guards[s] if holds(g, [letter])]
            # pairwise disjoint and covering: exactly one guard per letter
            assert len(enabled) == 1, (s, sorted(letter), enabled)
            assert explicit.step(s, letter) == enabled[0][1]
    assert explicit.num_states == minimal_num_states(formula)
    reference = reference_dfa(formula)
    assert distinguishing_trace(explicit, reference, keys(formula)) is None


@SETTINGS
@given(formulas(max_depth=4))
def test_explicit_form_is_complete_minimal_and_equivalent(formula):
    dfa = compile_ltlf(formula)
    explicit = dfa.to_explicit()
    assert explicit.num_states == dfa.num_states
    check_explicit(explicit, formula)


@FEW
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=5))
def test_explicit_form_accepts_like_the_symbolic_one(formula, trace_list):
    dfa = compile_ltlf(formula)
    explicit = dfa.to_explicit()
    for trace in trace_list:
        assert explicit.accepts(trace) == dfa.accepts(trace) == holds(formula, trace)


@SETTINGS
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=5))
def test_json_form_simulated_through_its_guard_texts(formula, trace_list):
    data = json.loads(json.dumps(compile_ltlf(formula).to_explicit().to_json()))
    assert set(data) >= {"atoms", "initial", "accepting", "transitions"}
    assert set(data["atoms"]) == keys(formula)
    assert data["initial"] not in data["accepting"]
    for t in data["transitions"]:
        assert set(t) == {"from", "to", "guard"}
        assert keys(parse_ltlf(t["guard"])) <= set(data["atoms"])
    simulated = JsonDFA(data)
    for trace in trace_list:
        assert simulated.accepts(trace) == holds(formula, trace), (to_string(formula), trace)
    assert distinguishing_trace(simulated, reference_dfa(formula), keys(formula)) is None
    assert len(simulated.states) == minimal_num_states(formula)


# ----------------------------------------------------- hand-checked cases

# Each count is the Myhill-Nerode index of L(phi) in Sigma+, derived by hand:
# the class of the empty word (never accepting) plus the classes of non-empty
# prefixes; a class is fixed by "is the prefix accepted" and "which
# continuations are accepted".
HAND_CASES = {
    # initial, satisfied (accepting; continuations like the initial state),
    # pending (a seen, b owed).  Initial != satisfied (acceptance); initial !=
    # pending (the continuation {} is accepted from initial only).  No sink.
    "G(a -> F b)": 3,
    # length 0, length 1 (rejecting, any letter accepts), length >= 2 (accepting)
    "X true": 3,
    # the empty language: one rejecting state with a self-loop
    "G false": 1,
    "false": 1,
    "X X false": 1,
    # length 0, length 1 (accepting), length >= 2 (rejecting sink)
    "last": 3,
    "WX false": 3,
    # all non-empty traces: initial (rejecting) and everything else (accepting)
    "true": 2,
    "F last": 2,
    # {none seen} (= initial: rejecting, same continuations), {a}, {b}, {a, b}
    "F a & F b": 4,
    # initial, a-at-0 (accepting forever), not-a-at-0 (sink)
    "a": 3,
    # initial; a seen (accepting forever); initial is "not yet" too
    "F a": 2,
    # initial, all-a-so-far (accepting), sink
    "G a": 3,
    # initial = a-so-far-no-b (rejecting, same continuations), done, sink
    "a U b": 3,
    # initial; a-so-far (accepting: G a; same continuations as initial);
    # done (b seen; differs from a-so-far on the continuation {}); sink
    "a W b": 4,
    # initial = last-letter-without-a; last-letter-with-a (accepting)
    "G(last -> a)": 2,
    # length 0, length 1 (any), then a at 1 (accepting forever) or not (sink)
    "X a": 4,
    # length 0, length 1 (accepting: no next), accepting forever, sink;
    # length 1 != forever: the continuation {} is accepted only from forever
    "WX a": 4,
    # length 0, 1, 2 accepting (1 != 2: one more letter is fine only after 1), sink
    "WX WX false": 4,
}


@pytest.mark.parametrize(("text", "states"), sorted(HAND_CASES.items()))
def test_hand_checked_state_counts(text, states):
    formula = parse_ltlf(text)
    assert minimal_num_states(formula) == states  # the oracle agrees with the hand count
    dfa = compile_ltlf(text)
    assert dfa.num_states == states
    check_explicit(dfa.to_explicit(), formula)


def test_strong_and_weak_x_differ_on_a_trace_of_length_one():
    assert not compile_ltlf("X a").accepts([{"a"}])
    assert compile_ltlf("X a", next_semantics="weak").accepts([{"a"}])
    assert compile_ltlf("X a", next_semantics="weak").accepts([set()])
    assert not compile_ltlf("X[!] a", next_semantics="weak").accepts([{"a"}])
    assert compile_ltlf("X a").accepts([set(), {"a"}])


def test_always_eventually_trace_examples():
    dfa = compile_ltlf("G(a -> F b)")
    assert dfa.accepts([set()])
    assert not dfa.accepts([{"a"}])
    assert dfa.accepts([{"a", "b"}])
    assert dfa.accepts([{"a"}, set(), {"b"}])
    assert not dfa.accepts([{"a"}, {"b"}, {"a"}])


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_response_family_has_two_to_the_n_plus_one_states(n):
    """G(a_i -> F b_i) for i < n: the pending set P (2^n values) plus the initial state.

    P = {} (accepting) and the initial state differ by acceptance; P != {} and
    the initial state differ on the continuation {}; P != P' differ on a letter
    that answers every request except one in P \\ P'.
    """
    text = " & ".join(f"G(a{i} -> F b{i})" for i in range(n))
    dfa = compile_ltlf(text)
    assert dfa.num_states == 2 ** n + 1
    assert minimal_num_states(parse_ltlf(text)) == 2 ** n + 1
    assert set(dfa.atoms) == {f"{p}{i}" for p in "ab" for i in range(n)}
    if n <= 3:
        check_explicit(dfa.to_explicit(), parse_ltlf(text))


PREDICATE_FORMULA = "F(at(black, top)) & G(occupied(l3) -> at(white, l1))"


def test_predicate_atoms():
    """p = at(black, top), q = occupied(l3), r = at(white, l1); L = F p & G(q -> r).

    States: waiting (initial; p not yet, invariant kept -- the empty prefix has
    the same continuations and is rejecting too), done (accepting), sink
    (invariant broken).  So 3.
    """
    formula = parse_ltlf(PREDICATE_FORMULA)
    dfa = compile_ltlf(PREDICATE_FORMULA)
    assert set(dfa.atoms) == {"at(black, top)", "occupied(l3)", "at(white, l1)"}
    assert dfa.num_states == 3
    p, q, r = "at(black, top)", "occupied(l3)", "at(white, l1)"
    assert dfa.accepts([{p}])
    assert dfa.accepts([{q, r}, {p}])
    assert not dfa.accepts([{q}, {p}])
    assert not dfa.accepts([{q, r}])
    check_explicit(dfa.to_explicit(), formula)
    simulated = JsonDFA(json.loads(json.dumps(dfa.to_explicit().to_json())))
    assert distinguishing_trace(simulated, reference_dfa(formula), keys(formula)) is None


def test_accepts_a_formula_object_and_a_string_alike():
    tree = ast.Always(ast.Implies(ast.Atom("a"), ast.Eventually(ast.Atom("b"))))
    assert compile_ltlf(tree).num_states == compile_ltlf("G(a -> F b)").num_states == 3
    assert distinguishing_trace(compile_ltlf(tree).to_explicit(),
                                compile_ltlf("G(a -> F b)").to_explicit(), {"a", "b"}) is None


@pytest.mark.parametrize("text", [
    "F q0_0",
    "q0_0 U q0_1",
    "X q0_0 & X q0_1",
    "G(a -> F b) & F q0_0",
    "G(q0_0 -> F q1_0) & G(q1_1 -> F q0_1)",
])
def test_atom_names_do_not_clash_with_internal_variable_names(text):
    """Atoms are user names; any spelling the grammar allows must work, even `q0_0`."""
    formula = parse_ltlf(text)
    dfa = compile_ltlf(formula)
    for trace in all_traces(keys(formula), 2):
        assert dfa.accepts(trace) == holds(formula, trace), (text, trace)
    assert dfa.num_states == minimal_num_states(formula)
    assert distinguishing_trace(dfa.to_explicit(), reference_dfa(formula), keys(formula)) is None


def test_an_until_chain_progresses_in_linear_states():
    """p1 U (p2 U (... U p10)): progression's states were disjunctions of the
    chain's obligations, 513 before minimization (2^9 + 1); a disjunction of
    obligations that imply each other (X psi | X(phi U psi)) is now the
    weaker one, which leaves 56 (quadratic, not exponential, in n).  The
    minimal DFA has 11 states: which link holds so far, the win, the sink."""
    from symsynth.automata.normal import nnf
    from symsynth.automata.progression import Progression

    n = 10
    formula = nnf(parse_ltlf(" U (".join(f"p{i}" for i in range(1, n + 1)) + ")" * (n - 1)))
    raw = Progression([a.key for a in ast.atoms(formula)]).dfa(formula)
    assert compile_ltlf(formula).num_states == n + 1
    assert raw.num_states <= n * n // 2 + n


@pytest.mark.parametrize("text", ["G(a -> F b)", "a U (b U (c U d))", "G(a -> X b) & F c",
                                  "F(a & X(b & X(c & X d)))"])
def test_state_bits_lie_above_the_atoms(text):
    """Whatever manager the DFA ends in (a single explicit part is turned
    into bits in the manager it was built in, with no copy), each state
    bit and its primed copy lie above every atom, so a transition function
    is a case split on the state over small guards."""
    dfa = compile_ltlf(text)
    levels = {v: dfa.bdd.level_of_var(v) for v in dfa.bdd.vars}
    bits = [b for bit in dfa.bits for b in (bit, bit + "'")]
    assert bits and max(levels[b] for b in bits) < min(levels[a] for a in dfa.atoms)
    assert dfa.num_states == minimal_num_states(parse_ltlf(text))
