"""The compositional DFA construction (symsynth/automata/compose.py) against
independent references: the semantics (`holds`), the explicit reference DFA
of tests/support/reference.py (no BDDs) and the earlier non-compositional
construction (`compositional=False`: top-level conjuncts by progression).

Minimal DFAs are unique up to isomorphism, so two constructions of one
formula must give the same state count and no distinguishing trace.  Each
path of the composition is forced in turn with `limits`: every product
explicit, every product symbolic, and merged invariants split.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import all_traces, distinguishing_trace, minimal_num_states, reference_dfa
from support.strategies import formulas, traces
from symsynth.automata import compile_ltlf
from symsynth.automata.normal import expose
from symsynth.errors import LTLfSyntaxError
from symsynth.logic import ast, atoms, holds, parse_ltlf, to_string

SETTINGS = settings(max_examples=120, deadline=None)

#: every product explicit / ... and made from the operands' moves (moves.py) /
#: every product symbolic / invariants part by part / explicit products made,
#: then every one taken apart again for the final symbolic product
#: (`Composer._factored`)
PATHS = {
    "explicit": {"single": 10**9, "product_limit": 10**9, "edge_limit": None, "merged_edges": 10**9},
    "moves": {"single": 10**9, "product_limit": 10**9, "edge_limit": None, "merged_edges": 10**9,
              "moves_pairs": 0},
    "symbolic": {"single": 0, "product_limit": 0, "edge_limit": 0, "merged_edges": 0},
    "factored": {"factor_states": 0, "factor_degree": 0, "final_explicit": False},
    "default": None,
}


def keys(formula: ast.Formula) -> list[str]:
    return [x.key for x in atoms(formula)]


@SETTINGS
@given(formulas(max_depth=4), st.sampled_from(sorted(PATHS)), st.lists(traces(), min_size=1, max_size=4))
def test_every_path_gives_the_minimal_dfa_of_the_language(formula, path, trace_list):
    dfa = compile_ltlf(formula, limits=PATHS[path])
    for trace in trace_list:
        assert dfa.accepts(trace) == holds(formula, trace), (to_string(formula), path, trace)
    assert not dfa.accepts([])
    assert dfa.num_states == minimal_num_states(formula), (to_string(formula), path)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None


@SETTINGS
@given(formulas(max_depth=4))
def test_same_automaton_as_the_non_compositional_construction(formula):
    new = compile_ltlf(formula)
    old = compile_ltlf(formula, compositional=False)
    assert new.num_states == old.num_states, to_string(formula)
    assert distinguishing_trace(new, old, keys(formula)) is None, to_string(formula)


@settings(max_examples=40, deadline=None)
@given(formulas(max_depth=4))
def test_progression_of_the_whole_formula_gives_the_minimal_dfa(formula):
    whole = compile_ltlf(formula, construction="progression")
    assert whole.num_states == minimal_num_states(formula), to_string(formula)
    assert distinguishing_trace(whole, reference_dfa(formula), keys(formula)) is None, to_string(formula)


def assume_guarantee(n: int, m: int) -> str:
    """(A1 & ... & An) -> (G1 & ... & Gm) in the shape of the Syft family:
    fairness assumptions G F e_i, guarantees G(r_j -> X g_j) and mutual
    exclusion of the g's (bounded-lookahead invariants that get merged)."""
    assumptions = " & ".join(f"G F e{i}" for i in range(n))
    guarantees = [f"G(r{j} -> X[!] g{j})" for j in range(m)]
    guarantees += [f"G(!g{j} | !g{k})" for j in range(m) for k in range(j + 1, m)]
    return f"({assumptions}) -> ({' & '.join(guarantees)})"


@pytest.mark.parametrize("path", sorted(PATHS))
@pytest.mark.parametrize(("n", "m"), [(1, 1), (1, 2), (2, 1)])
def test_assume_guarantee_shape(path, n, m):
    formula = parse_ltlf(assume_guarantee(n, m))
    dfa = compile_ltlf(formula, limits=PATHS[path])
    assert dfa.num_states == minimal_num_states(formula)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None


@pytest.mark.parametrize(("text", "states"), [
    # !F a = G !a: start (rejecting), "no a so far" (accepting), sink.  The
    # minimal DFA of F a comes back to its start state after !a, so the
    # complement needs a fresh rejecting start: 3 states, not 2.
    ("!F a", 3),
    # a -> a accepts every non-empty trace: start, then an accepting sink.
    ("a -> a", 2),
    # (F a) <-> (F a): the same; an equivalence of two rejecting starts
    # must not accept the empty trace.
    ("F a <-> F a", 2),
    # !(X[!] true): exactly the traces of length 1: start, accept, sink.
    ("!(X[!] true)", 3),
])
def test_complement_and_implication_reject_the_empty_trace(text, states):
    formula = parse_ltlf(text)
    for path in PATHS.values():
        dfa = compile_ltlf(formula, limits=path)
        assert not dfa.accepts([])
        assert dfa.num_states == states == minimal_num_states(formula)
        for trace in all_traces(keys(formula), 3):
            if trace:
                assert dfa.accepts(trace) == holds(formula, trace), (text, trace)


@SETTINGS
@given(formulas(max_depth=4), st.lists(traces(), min_size=1, max_size=6))
def test_exposed_operands_recombine_to_the_formula(formula, trace_list):
    """`expose`'s rewriting (G through &, F through |, X and WX through
    & | -> !) keeps the meaning: the operator applied to the operands'
    truth values is the formula's truth value on every trace."""
    shape = expose(formula)
    if shape is None:
        return
    op, operands = shape
    for trace in trace_list:
        values = [holds(f, trace) for f in operands]
        expected = {"and": lambda v: v[0] and v[1], "or": lambda v: v[0] or v[1],
                    "implies": lambda v: (not v[0]) or v[1], "equiv": lambda v: v[0] == v[1],
                    "not": lambda v: not v[0]}[op](values)
        assert holds(formula, trace) == expected, (to_string(formula), op, trace)


def test_until_chain_stays_linear():
    """p1 U (p2 U (... U p16)): one leaf, n + 1 states (MONA's too)."""
    n = 16
    dfa = compile_ltlf(" U (".join(f"p{i}" for i in range(1, n + 1)) + ")" * (n - 1))
    assert dfa.num_states == n + 1


def test_many_independent_invariants_are_not_merged_into_one_state_space():
    """G(a_i -> X[!] b_i) for 12 disjoint pairs: the conjunction has 2^12
    combinations of pending obligations plus start and sink, which the
    composition reaches without progressing the conjunction as one formula."""
    n = 12
    text = " & ".join(f"G(a{i} -> X[!] b{i})" for i in range(n))
    dfa = compile_ltlf(text)
    # states: start, sink, and one per set of pending b_i (2^n)
    assert dfa.num_states == 2 ** n + 2


@pytest.mark.parametrize("path", sorted(PATHS))
@pytest.mark.parametrize("text", ["!(X c -> X c)", "!(F a -> F a)", "(G a -> G a) & F b"])
def test_one_component_read_through_a_boolean_combination_is_minimized(path, text):
    """Both sides of `->` are one DFA: a single component whose acceptance
    is a Boolean combination of its own (`!(X c -> X c)` is empty: 1 state)."""
    formula = parse_ltlf(text)
    dfa = compile_ltlf(formula, limits=PATHS[path])
    assert dfa.num_states == minimal_num_states(formula)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None


SETTLED = {  # an operand that decides its operator: `g & !g` is empty, `g | !g` universal
    "and empty": lambda f, g: ast.And(ast.And(g, ast.Not(g)), f),
    "or universal": lambda f, g: ast.Or(ast.Or(g, ast.Not(g)), f),
    "implies from empty": lambda f, g: ast.Implies(ast.And(g, ast.Not(g)), f),
    "implies to universal": lambda f, g: ast.Implies(f, ast.Or(g, ast.Not(g))),
    "implies from universal": lambda f, g: ast.Implies(ast.Or(g, ast.Not(g)), f),
    "and universal": lambda f, g: ast.And(ast.Or(g, ast.Not(g)), f),
}


@SETTINGS
@given(formulas(max_depth=3), formulas(max_depth=2), st.sampled_from(sorted(SETTLED)),
       st.sampled_from(sorted(PATHS)))
def test_an_operand_that_decides_its_operator_gives_the_language(f, g, shape, path):
    """The composer stops evaluating an `&` at an empty operand, an `|` at a
    universal one, an implication at an empty premise or a universal
    conclusion (`Composer._settled`); the last two shapes must not stop."""
    formula = SETTLED[shape](f, g)
    dfa = compile_ltlf(formula, limits=PATHS[path])
    assert dfa.num_states == minimal_num_states(formula), (to_string(formula), path)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None, (to_string(formula), path)


#: first-letter conditions: Boolean combinations of atoms (no temporal operator)
conditions = st.builds(lambda op, f, g: op(f, g), st.sampled_from([ast.And, ast.Or, ast.Implies]),
                       formulas(max_depth=1, leaf_strategy=st.sampled_from([ast.Atom(n) for n in "abc"])),
                       st.sampled_from([ast.Atom("a"), ast.Not(ast.Atom("b")), ast.Atom("c")]))
BOOLEAN = [ast.Implies, ast.Or, ast.Equiv, lambda f, g: ast.Not(ast.And(f, g))]


@SETTINGS
@given(conditions, st.sampled_from(BOOLEAN), formulas(max_depth=3), formulas(max_depth=3),
       st.sampled_from(sorted(PATHS)))
def test_a_first_letter_condition_beside_a_boolean_operator(condition, op, left, right, path):
    """`P & (A op B)` with P propositional (P is conjoined to an
    implication's consequent, `Composer._pushed`): the minimal DFA is the
    language's, on every path."""
    formula = ast.And(condition, op(left, right))
    dfa = compile_ltlf(formula, limits=PATHS[path])
    assert dfa.num_states == minimal_num_states(formula), (to_string(formula), path)
    assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None


def test_the_condition_is_pushed_where_the_products_are():
    """`a & (F(a & b) -> G(a | c))`: the consequent becomes `a & G(a | c)`;
    `a & (F a -> G b)`: unchanged (the consequent reads no `a`);
    `a & X(F a -> G a)`: unchanged (`expose` makes it `!WX F a | X G a`,
    no implication)."""
    from symsynth.automata.compose import Composer
    from symsynth.automata.progression import Progression

    def pushed(text):
        formula = parse_ltlf(text)
        composer = Composer(Progression(keys(formula)))
        composer.compose(formula)  # (sets up the composer's sets of subformulas)
        op, operands = composer.shape(formula)
        assert op == "and" and operands[0] == a
        return operands[1]

    a, f = ast.Atom("a"), parse_ltlf
    assert pushed("a & (F(a & b) -> G(a | c))") == ast.Implies(f("F(a & b)"), ast.And(a, f("G(a | c)")))
    assert pushed("a & (F a -> G b)") == f("F a -> G b")
    assert pushed("a & X(F a -> G a)") == f("X(F a -> G a)")


@settings(max_examples=40, deadline=None)
@given(formulas(max_depth=4), st.sampled_from(sorted(PATHS)))
def test_a_compilation_leaves_no_reference_cycles(formula, path):
    """compile_ltlf pauses Python's cyclic collector (its full walks cost a
    third of a 0.05 s compilation): safe only while compiling makes no
    cycles, which this checks (a cycle left would show as collected
    objects), and the collector's state is restored, also on an error."""
    import gc
    gc.collect()
    gc.freeze()  # what the process held before is not walked again: only what compiling made
    gc.disable()
    try:
        compile_ltlf(formula, limits=PATHS[path])
        assert gc.collect() == 0, to_string(formula)
    finally:
        gc.enable()
        gc.unfreeze()
    compile_ltlf(formula)
    assert gc.isenabled()
    with pytest.raises(LTLfSyntaxError):
        compile_ltlf("a &", source="bad")
    assert gc.isenabled()
    gc.disable()
    try:
        compile_ltlf(formula)
        assert not gc.isenabled()
    finally:
        gc.enable()
