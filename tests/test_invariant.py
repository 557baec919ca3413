"""The DFA of one-step invariants `P G f` (symsynth/automata/invariant.py)
and the partition refinement of explicit DFAs (progression.minimize),
against independent references: the semantics (`holds`) and the explicit
reference DFA of tests/support/reference.py (no BDDs, Moore's rounds over
explicit letters)."""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import ReferenceDFA, distinguishing_trace, letters, minimal_num_states, reference_dfa
from support.reference import minimize as reference_minimize
from support.strategies import traces
from symsynth.automata import compile_ltlf, invariant
from symsynth.automata.invariant import Invariants, invariant_shape
from symsynth.automata.normal import nnf
from symsynth.automata.progression import GuardedDFA, Progression, minimize
from symsynth.logic import ast, atoms, holds, parse_ltlf, to_string
from symsynth.automata.bdd import cofactor
from symsynth.automata.moves import decode_all

SETTINGS = settings(max_examples=150, deadline=None)
ATOMS = ("a", "b", "c")


def boolean(leaf: st.SearchStrategy[ast.Formula], max_depth: int) -> st.SearchStrategy[ast.Formula]:
    """Boolean combinations of `leaf`, nested up to `max_depth`."""
    level = leaf
    for _ in range(max_depth):
        level = st.one_of(
            leaf,
            st.builds(ast.Not, level),
            st.builds(lambda op, f, g: op(f, g), st.sampled_from([ast.And, ast.Or, ast.Implies, ast.Equiv]),
                      level, level))
    return level


def propositional(max_depth: int = 2) -> st.SearchStrategy[ast.Formula]:
    return boolean(st.sampled_from([ast.Atom(x) for x in ATOMS] + [ast.TRUE, ast.FALSE]), max_depth)


def one_step(max_depth: int = 3) -> st.SearchStrategy[ast.Formula]:
    """Boolean combinations of propositions, `X p`, `WX p` and `last`: the
    bodies the invariant construction takes (after NNF)."""
    leaf = st.one_of(
        propositional(),
        st.builds(ast.Next, propositional()),
        st.builds(ast.WeakNext, propositional()),
        st.just(ast.Last()))
    return boolean(leaf, max_depth)


prefixes = st.lists(st.sampled_from([ast.Next, ast.WeakNext]), max_size=2)


def prefixed(prefix, f):
    for kind in reversed(prefix):
        f = kind(f)
    return f


invariants = st.builds(lambda p, body: prefixed(p, ast.Always(body)), prefixes, one_step())


def keys(formula: ast.Formula) -> list[str]:
    return [x.key for x in atoms(formula)]


class Runner:
    """Runs a `GuardedDFA`: the successor is the edge whose guard the letter satisfies."""

    def __init__(self, dfa: GuardedDFA, atom_keys):
        self.dfa, self.atom_keys = dfa, list(atom_keys)
        self.initial = dfa.initial

    def step(self, state, letter):
        values = {x: x in letter for x in self.atom_keys}
        bdd = self.dfa.bdd
        hits = [succ for succ, guard in self.dfa.edges[state].items() if cofactor(bdd, values, guard) == bdd.true]
        assert len(hits) == 1, (state, letter, hits)
        return hits[0]

    def is_accepting(self, state):
        return self.dfa.accepting[state]


@SETTINGS
@given(invariants)
def test_the_direct_construction_accepts_the_language(formula):
    """Both ways to a sparse invariant's edges: read off H (within
    SPLIT_TARGETS), and decoded from the moves (a bound of 0 leaves every
    invariant with a restricted state to that)."""
    shape = invariant_shape(nnf(formula))
    assert shape is not None, to_string(formula)
    default = invariant.SPLIT_TARGETS
    for bound in (default, 0):
        invariant.SPLIT_TARGETS = bound
        try:
            made = Invariants(Progression(keys(formula))).dfa(*shape)
        finally:
            invariant.SPLIT_TARGETS = default
        if made.has_edges():  # sparse: the edges were read off H, and must be what its moves say
            assert made.edges == decode_all(made.bdd, made.moves), to_string(formula)
        dfa = minimize(made)
        assert dfa.num_states == minimal_num_states(formula), to_string(formula)
        assert distinguishing_trace(Runner(dfa, keys(formula)), reference_dfa(formula), keys(formula)) is None


def test_edges_are_read_off_h_only_within_the_bound():
    """`G(a -> X b)`: the state after `a` allows only letters with `b`, so
    its edges cost a conjunction per target of H; with a bound of 0 they are
    left to the moves (a counter's thousands of states made that quadratic)."""
    formula = parse_ltlf("G(a -> X b)")
    shape = invariant_shape(nnf(formula))
    default = invariant.SPLIT_TARGETS
    assert Invariants(Progression(keys(formula))).dfa(*shape).has_edges()
    invariant.SPLIT_TARGETS = 0
    try:
        assert not Invariants(Progression(keys(formula))).dfa(*shape).has_edges()
    finally:
        invariant.SPLIT_TARGETS = default


@SETTINGS
@given(st.lists(invariants, min_size=1, max_size=4), st.lists(traces(), min_size=1, max_size=3))
def test_conjunctions_of_invariants_compile_to_the_minimal_dfa(parts, trace_list):
    """Conjunctions are grouped (same prefix, shared atoms) and built as one
    leaf, or part by part when the edge limit is tiny."""
    formula = parts[0]
    for part in parts[1:]:
        formula = ast.And(formula, part)
    for limits in (None, {"merged_edges": 1}):
        dfa = compile_ltlf(formula, limits=limits)
        for trace in trace_list:
            assert dfa.accepts(trace) == holds(formula, trace), (to_string(formula), trace)
        assert dfa.num_states == minimal_num_states(formula), to_string(formula)
        assert distinguishing_trace(dfa, reference_dfa(formula), keys(formula)) is None


def test_an_alternating_bit_by_hand():
    """G(c <-> X !c): c alternates.  At the last position X !c is false, so
    the trace ends with !c.  States: the start; 'read c' (rejecting: the
    next letter must come, with !c); 'read !c' (accepting; a next letter
    must have c); the sink: 4.  With WX the end makes WX !c true, so the
    trace ends with c instead: again 4 states, acceptance swapped."""
    c = ast.Atom("c")
    strong = compile_ltlf(ast.Always(ast.Equiv(c, ast.Next(ast.Not(c)))))
    weak = compile_ltlf(ast.Always(ast.Equiv(c, ast.WeakNext(ast.Not(c)))))
    assert strong.num_states == weak.num_states == 4
    assert strong.accepts([{"c"}, set()]) and not strong.accepts([{"c"}])
    assert weak.accepts([{"c"}, set(), {"c"}]) and not weak.accepts([{"c"}, set()])
    assert not strong.accepts([{"c"}, {"c"}, set()]) and not weak.accepts([{"c"}, {"c"}])


# ----------------------------------------------------- partition refinement


@st.composite
def explicit_dfas(draw):
    """A random complete DFA over the letters of two atoms, every state
    reachable: (transition table over `letters(("a", "b"))`, accepting)."""
    alphabet = letters(("a", "b"))
    n = draw(st.integers(1, 9))
    table = [[draw(st.integers(0, n - 1)) for _ in alphabet] for _ in range(n)]
    accepting = [draw(st.booleans()) for _ in range(n)]
    reached, order = {0}, [0]
    for s in order:
        for t in table[s]:
            if t not in reached:
                reached.add(t)
                order.append(t)
    rename = {s: i for i, s in enumerate(order)}
    return ([[rename[t] for t in table[s]] for s in order], [accepting[s] for s in order])


@settings(max_examples=300, deadline=None)
@given(explicit_dfas())
def test_partition_refinement_gives_the_myhill_nerode_quotient(case):
    table, accepting = case
    alphabet = letters(("a", "b"))
    progression = Progression(["a", "b"])
    bdd = progression.bdd
    cubes = [bdd.cube({x: x in letter for x in ("a", "b")}) for letter in alphabet]
    edges = []
    for row in table:
        out = {}
        for cube, target in zip(cubes, row):
            out[target] = out[target] | cube if target in out else cube
        edges.append(out)
    got = minimize(GuardedDFA(bdd, 0, accepting, edges))
    reference = ReferenceDFA(("a", "b"), tuple(alphabet), 0,
                             frozenset(s for s, acc in enumerate(accepting) if acc),
                             tuple(tuple(row) for row in table))
    assert got.num_states == reference_minimize(reference).num_states
    runner = Runner(got, ("a", "b"))
    # same language from the start, and the same acceptance on every trace up to length 4
    assert distinguishing_trace(runner, reference, ("a", "b")) is None
    for length in range(1, 5):
        for trace in itertools.product(alphabet, repeat=length):
            state = 0
            for letter in trace:
                state = runner.step(state, letter)
            assert got.accepting[state] == reference.accepts(list(trace))
