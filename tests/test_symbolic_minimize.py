"""The symbolic minimization (`SymbolicDFA.minimize`, symsynth/automata/symbolic.py)
against explicit references that use no BDDs.

- Random small products of random complete DFAs, over pairwise disjoint atoms
  (a `local` product: built and minimized in the declared order; LOCAL_PARTS
  lowered to 2 so that small products take that path) and over
  shared atoms (the manager's reordering kept): the product is enumerated
  letter by letter and minimized by Moore's rounds (tests/support/reference.py);
  the symbolic minimum must have as many states and no distinguishing trace.
- `_least_member` (one pass over the BDD's nodes) against the least member
  of each class found by enumerating assignments, in random variable orders.
- The independent one-step invariants of issue 17, whose state count is
  worked out by hand below.
"""

from __future__ import annotations

import itertools
import random
from collections import deque

import pytest

from support.reference import ReferenceDFA, all_traces, distinguishing_trace, letters
from support.reference import minimize as moore
from symsynth.automata import compile_ltlf
from symsynth.automata.bdd import cofactor, new_manager
from symsynth.automata.progression import GuardedDFA
from symsynth.automata import symbolic
from symsynth.automata.symbolic import _least_member, product
from symsynth.logic import holds, parse_ltlf

Table = tuple[int, list[bool], list[dict[frozenset[str], int]]]  # initial, accepting, successor per letter


def random_component(rng: random.Random, atoms: list[str]) -> Table:
    states = rng.randint(1, 4)
    alphabet = letters(atoms)
    rows = [{letter: rng.randrange(states) for letter in alphabet} for _ in range(states)]
    accepting = [rng.random() < 0.5 for _ in range(states)]
    return rng.randrange(states), accepting, rows


def guarded(bdd, atoms: list[str], table: Table) -> GuardedDFA:
    """The component as the composer hands it over: guards are BDDs over its atoms."""
    initial, accepting, rows = table
    edges: list[dict[int, object]] = []
    for row in rows:
        out: dict[int, object] = {}
        for letter, succ in row.items():
            cube = bdd.cube({a: a in letter for a in atoms}) if atoms else bdd.true
            out[succ] = out.get(succ, bdd.false) | cube
        edges.append(out)
    return GuardedDFA(bdd, initial, accepting, edges)


def explicit_product(atoms: list[str], parts: list[tuple[list[str], Table]], accept) -> ReferenceDFA:
    """The reachable product, letter by letter (no BDDs)."""
    alphabet = tuple(letters(atoms))
    start = tuple(table[0] for _, table in parts)
    index, order, rows = {start: 0}, [start], []
    queue = deque([start])
    while queue:
        state = queue.popleft()
        row = []
        for letter in alphabet:
            succ = tuple(table[2][s][letter & frozenset(own)] for s, (own, table) in zip(state, parts))
            if succ not in index:
                index[succ] = len(order)
                order.append(succ)
                queue.append(succ)
            row.append(index[succ])
        rows.append(tuple(row))
    accepting = frozenset(i for i, state in enumerate(order)
                          if accept([table[1][s] for s, (_, table) in zip(state, parts)]))
    return ReferenceDFA(tuple(sorted(atoms)), alphabet, 0, accepting, tuple(rows))


def random_parts(rng: random.Random, shared: bool) -> tuple[list[str], list[tuple[list[str], Table]]]:
    count = rng.randint(2, 4)
    if shared:
        atoms = [f"p{i}" for i in range(rng.randint(1, 4))]
        owns = [sorted(rng.sample(atoms, rng.randint(1, min(2, len(atoms))))) for _ in range(count)]
    else:
        owns = [[f"p{c}_{i}" for i in range(rng.randint(0, 2))] for c in range(count)]
        atoms = [a for own in owns for a in own]
    return atoms, [(own, random_component(rng, own)) for own in owns]


@pytest.mark.parametrize("shared", [False, True], ids=["disjoint", "shared"])
@pytest.mark.parametrize("combination", ["and", "or"])
@pytest.mark.parametrize("seed", range(25))
def test_minimize_matches_explicit_minimization(seed, shared, combination, monkeypatch):
    if not shared:  # the local path (declared order) from two parts on, not LOCAL_PARTS
        monkeypatch.setattr(symbolic, "LOCAL_PARTS", 2)
    rng = random.Random(seed * 7 + shared)
    atoms, parts = random_parts(rng, shared)
    accept = all if combination == "and" else any
    reference = moore(explicit_product(atoms, parts, accept))

    bdd = new_manager()  # the components' manager (the compiler's: progression's)
    for a in atoms:
        bdd.declare(a)
    components = [guarded(bdd, own, table) for own, table in parts]
    manager = new_manager(reordering=True)  # as compile_ltlf's for several components
    combine = None
    if combination == "or":
        def combine(accs):
            result = manager.false
            for acc in accs:
                result |= acc
            return result
    dfa = product(manager, atoms, components, combine=combine)
    if not shared:
        assert dfa.local  # the path under test: declared order, no reordering
    minimal = dfa.minimize()
    assert minimal.num_states == reference.num_states
    assert minimal.to_explicit().num_states == reference.num_states
    assert distinguishing_trace(minimal, reference, atoms) is None
    again = minimal.minimize()  # a minimal DFA is its own quotient
    assert again is minimal


def least_by_enumeration(bdd, relation, sources: list[str], targets: list[str]):
    """For each assignment of `sources`, keep only its least target (first most significant)."""
    result = bdd.false
    for values in itertools.product((False, True), repeat=len(sources)):
        here = cofactor(bdd, dict(zip(sources, values)), relation)
        for t_values in itertools.product((False, True), repeat=len(targets)):
            point = dict(zip(targets, t_values))
            if cofactor(bdd, point, here) == bdd.true:
                result |= bdd.cube(dict(zip(sources, values)) | point)
                break
    return result


@pytest.mark.parametrize("seed", range(60))
def test_least_member_matches_enumeration(seed):
    rng = random.Random(seed)
    k = rng.randint(1, 4)
    sources = [f"q{i}" for i in range(k)]
    targets = [f"q{i}'" for i in range(k)]
    order = sources + targets
    if seed % 3 == 0:
        rng.shuffle(order)  # targets out of significance order: the bit-by-bit fallback
    elif seed % 3 == 1:
        order = [v for pair in zip(sources, targets) for v in pair]
    bdd = new_manager()
    bdd.declare(*order)
    relation = bdd.false
    for _ in range(rng.randint(0, 10)):
        relation |= bdd.cube({v: rng.random() < 0.5 for v in order if rng.random() < 0.7})
    assert _least_member(bdd, relation, targets) == least_by_enumeration(bdd, relation, sources, targets)


def invariants(n: int) -> str:
    return " & ".join(f"G(a{i} -> X b{i})" for i in range(n))


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 30])
def test_independent_invariants_state_count(n):
    """`G(a1 -> X b1) & ... & G(an -> X bn)` (strong X) has 2^n + 2 states.

    One conjunct `G(a -> X b)` over non-empty traces has four: the start
    (nothing read, rejecting), `ok` (the last letter had no `a`: accepting),
    `wait` (it had `a`: rejecting, the next letter must have `b`) and the
    sink.  Reachable in the conjunction: the start, the sink (`{a1}` then
    `{}`), and every vector of `ok`/`wait` (one letter with `a_i` for the
    waiting i), 2^n of them.  They are pairwise distinct:
    - two vectors differing at i (`wait` in v, `ok` in w): the letter
      with every `b` but `b_i` and no `a` leads v to the sink, w to all-`ok`
      (accepting);
    - a vector and the sink: the letter with every `b` and no `a` accepts;
    - the start and the sink: `{}` accepts from the start;
    - the start and a vector: all-`ok` accepts and the start does not; any
      other vector waits somewhere, and `{}` leads it to the sink but the
      start to all-`ok`.
    Hence 2^n + 2 (the product has 3^n + 1 reachable tuples: every tuple
    with a sink component is the one sink).
    """
    dfa = compile_ltlf(invariants(n))
    assert dfa.num_states == 2 ** n + 2


def test_independent_invariants_language():
    """The minimized product against the semantics on every trace up to length 3."""
    formula = parse_ltlf(invariants(2))
    dfa = compile_ltlf(formula)
    keys = ["a0", "a1", "b0", "b1"]
    for trace in all_traces(keys, 3):
        assert dfa.accepts(trace) == holds(formula, trace), trace


def test_many_independent_parts_in_a_boolean_combination(monkeypatch):
    """17 invariants or `F c` or `G d & X e`: a product of LOCAL_PARTS or more
    parts over disjoint atoms (the declared-order path) whose acceptance is
    not a plain conjunction, against the semantics on random traces; as many
    states as through sifting (both are minimal)."""
    text = f"({invariants(17)}) | F c | (G d & X e)"
    formula = parse_ltlf(text)
    dfa = compile_ltlf(formula)
    assert dfa.local
    monkeypatch.setattr(symbolic, "LOCAL_PARTS", 10**6)
    sifted = compile_ltlf(formula)
    assert not sifted.local and sifted.num_states == dfa.num_states
    keys = [f"a{i}" for i in range(17)] + [f"b{i}" for i in range(17)] + ["c", "d", "e"]
    rng = random.Random(17)
    for _ in range(400):
        trace = [frozenset(k for k in keys if rng.random() < 0.15) for _ in range(rng.randint(1, 6))]
        assert dfa.accepts(trace) == holds(formula, trace), trace
