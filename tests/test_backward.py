"""The backward construction (symsynth/automata/backward.py: the formula
evaluated backwards, its reverse determinized) against the references of
tests/support/reference.py (no BDDs), the semantics (`holds`) and the
other constructions.  It makes the minimal DFA with no minimization step,
so a state too many (a set of vectors that differ only outside the
reachable ones) or a wrong value at the end of the trace fails here."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import all_traces, distinguishing_trace, minimal_num_states, reference_dfa
from support.strategies import formulas, traces
from symsynth.automata import compile_ltlf
from symsynth.automata.backward import Backward, backward_dfa
from symsynth.automata.bdd import cofactor, exits
from symsynth.automata.normal import nnf
from symsynth.automata.numbered import Listing
from symsynth.automata.progression import Progression, TooLarge
from symsynth.logic import ast, atoms, holds, parse_ltlf, to_string
from symsynth.logic.ast import depth

SETTINGS = settings(max_examples=150, deadline=None)


def keys(formula: ast.Formula) -> list[str]:
    return [x.key for x in atoms(formula)]


@SETTINGS
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=4))
def test_the_backward_construction_gives_the_minimal_dfa(formula, trace_list):
    dfa = compile_ltlf(formula, construction="backward")
    for trace in trace_list:
        assert dfa.accepts(trace) == holds(formula, trace), (to_string(formula), trace)
    assert not dfa.accepts([])
    assert dfa.num_states == minimal_num_states(formula), to_string(formula)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None, to_string(formula)


@settings(max_examples=60, deadline=None)
@given(formulas(max_depth=4))
def test_the_same_automaton_as_progression_and_the_default(formula):
    """As built, before any product: the explicit DFA has the state count
    of progression's minimized one."""
    built = backward_dfa(Progression(keys(formula)), nnf(formula))
    progressed = compile_ltlf(formula, construction="progression")
    assert built.num_states == progressed.num_states, to_string(formula)
    backward = compile_ltlf(formula, construction="backward")
    for other in (progressed, compile_ltlf(formula)):
        assert distinguishing_trace(backward, other, keys(formula)) is None, to_string(formula)


@pytest.mark.parametrize(("text", "one_letter", "states"), [
    # strong next: a trace of one letter has no next position
    ("X[!] a", False, 4),  # start, "a next", accept sink, reject sink
    # weak next: it holds at the last position
    ("WX a", True, 4),  # start, "a next or the end" (accepting), accept sink, reject sink
    ("WX false", True, 3),  # `last` at the start: exactly the traces of one letter
    ("X[!] true", False, 3),  # at least two letters
    ("G(a -> X[!] a)", False, 3),  # an a asks for an a after it, forever: no a at all (G !a)
])
def test_next_and_weak_next_at_the_end_of_the_trace(text, one_letter, states):
    formula = parse_ltlf(text)
    dfa = compile_ltlf(formula, construction="backward")
    assert dfa.accepts([frozenset({"a"})]) == one_letter
    assert dfa.num_states == states == minimal_num_states(formula)
    for trace in all_traces(keys(formula), 4):
        if trace:
            assert dfa.accepts(trace) == holds(formula, trace), (text, trace)


def test_a_hand_solved_until_of_a_release():
    """a U (b R c), by residuals (non-empty traces; eps the empty one):
    q0 = L, start, rejects; on c & b -> TOP (b R c met); on c & !b & a ->
    q1 = eps | L (b R c may go on, or the until does: q0's moves, accepting);
    on c & !b & !a -> q2 = eps | b R c; on !c & a -> q0; on !c & !a -> BOT.
    q2: on c & b -> TOP, c & !b -> q2, !c -> BOT.  Five states."""
    formula = parse_ltlf("a U (b R c)")
    dfa = backward_dfa(Progression(keys(formula)), nnf(formula))
    a, b, c = "abc"
    edges = dfa.edges

    def after(state, letter):
        [succ] = [t for t, guard in edges[state].items()
                  if cofactor(dfa.bdd, {x: x in letter for x in "abc"}, guard) == dfa.bdd.true]
        return succ

    q0 = dfa.initial
    top, q1, q2, q0_again, bot = (after(q0, s) for s in ({b, c}, {a, c}, {c}, {a}, set()))
    assert q0_again == q0
    assert len({q0, top, q1, q2, bot}) == 5 == dfa.num_states
    assert [dfa.accepting[q] for q in (q0, top, q1, q2, bot)] == [False, True, True, True, False]
    assert [after(q1, s) for s in ({b, c}, {a, c}, {c}, {a}, set())] == [top, q1, q2, q0, bot]
    assert [after(q2, s) for s in ({b, c}, {c}, {a, b})] == [top, q2, bot]
    assert {after(top, s) for s in ({a}, set())} == {top} and {after(bot, s) for s in ({a}, set())} == {bot}


def test_urright_at_eight_has_the_known_minimal_size():
    """p1 U (p2 R (... U p8)): 110 states (MONA's and progression's, docs/benchmarks.md)."""
    text = "p1 U (p2 R (p3 U (p4 R (p5 U (p6 R (p7 U (p8)))))))"
    assert compile_ltlf(text, construction="backward").num_states == 110


def test_past_the_state_budget_it_stops():
    formula = nnf(parse_ltlf("p1 U (p2 R (p3 U (p4 R p5)))"))
    with pytest.raises(TooLarge):
        backward_dfa(Progression(keys(formula)), formula, max_states=5)


def test_the_obligations_on_the_least_nested_operands_come_first():
    """The order `Backward` puts its obligations in (the successors' cost
    depends on it, not the result): least nested operand highest, `X phi`
    lowest, the atoms left on the levels above them."""
    formula = nnf(parse_ltlf("p1 U (p2 R (p3 U (p4 R (p5 U p6))))"))
    progression = Progression(keys(formula))
    automaton = Backward(progression, formula)
    bdd = progression.bdd
    names = sorted(automaton.step, key=bdd.level_of_var)
    depths = [depth(progression.meaning(name)[1]) for name in names]
    assert depths == sorted(depths) and len(set(depths)) == len(depths) == 5
    assert names[-1] == bdd.support(automaton.start).pop()  # X phi, phi the whole formula
    assert [bdd.level_of_var(key) for key in keys(formula)] == list(range(6))


@settings(max_examples=60, deadline=None)
@given(formulas(max_depth=4))
def test_the_listing_meets_the_successors_as_exits_does_and_lists_nodes_children_first(formula):
    """`Listing.walk` numbers the states (the order it gives the
    successors in) and lists the nodes the moves are made from: the same
    successors in the same order as `exits`, every listed node once and
    after its children (a state, or a node listed before it), and the
    same listing whether its codes move to the sorted arrays after every
    walk or stay in the dict."""
    progression = Progression(keys(formula))
    automaton = Backward(progression, nnf(formula))
    bdd, top = progression.bdd, len(progression.atom_keys)
    order = [automaton.initial()]
    listings = [Listing(bdd, top, order[0], recent) for recent in (1, 1 << 20)]
    seen: set = set()
    tops = []
    for state in itertools.islice(order, 40):  # the first 40 states met: the list grows as it is walked
        tops.append(automaton.successors(state))  # (alive: the listings hold their nodes' ids)
        met = [node for node in exits(bdd, tops[-1], top, seen) if node not in order]
        for listing in listings:
            assert list(listing.walk(tops[-1])) == met, to_string(formula)
        order += met
    aged, kept = listings
    assert aged.old is not None and kept.old is None
    assert (aged.order, aged.var, aged.low, aged.high, aged.roots) == (kept.order, kept.var, kept.low, kept.high, kept.roots)
    assert len(set(zip(kept.var, kept.low, kept.high))) == len(kept.var)  # (a reduced BDD: one node, one triple)
    for k, (level, low, high) in enumerate(zip(kept.var, kept.low, kept.high)):
        assert level < top and all(0 <= code < len(order) or 0 <= -1 - code < k for code in (low, high))


def test_the_bits_are_made_on_first_use_with_the_cyclic_collector_paused(monkeypatch):
    """The transition bits of a backward DFA are made when first read, not
    by the compilation, and, as in the compilation, with Python's cyclic
    collector paused (its full walks cost urright14's bits 30 %), restored
    after."""
    import gc

    import symsynth.automata.symbolic as symbolic

    collecting: list[bool] = []
    original = symbolic.bit_functions

    def watched(*args):
        collecting.append(gc.isenabled())
        return original(*args)

    monkeypatch.setattr(symbolic, "bit_functions", watched)
    formula = parse_ltlf("a U (b R c)")
    dfa = compile_ltlf(formula, construction="backward")
    assert collecting == [] and not dfa.delta_made and dfa.diagram is not None
    assert gc.isenabled()
    for trace in ([{"a"}, {"b", "c"}], [{"c"}], [{"a"}, {"a"}]):
        assert dfa.accepts(trace) == holds(formula, trace), trace
    assert collecting == [False] and dfa.delta_made and gc.isenabled()
