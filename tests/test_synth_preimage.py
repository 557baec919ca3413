"""The game's preimage as a clustered relational product
(symsynth/synthesis/preimage.py) and the fixpoint that takes it of the new
states only (symsynth/synthesis/game.py), against state-by-state
computations on random small DFAs: the successor of every state code and
letter by `SymbolicDFA.step`, and the rounds W_1, W_2, ... of the game
worked out one reachable state at a time.  Each cluster size is forced in
turn: 0 (one conjunct per state bit), a few nodes (some conjuncts
together), and the default (the whole relation, on these DFAs); and the
relation from the first call, after a few substitutions, after the default
budget of them, or never."""

from __future__ import annotations

import itertools

from hypothesis import given, settings
from hypothesis import strategies as st

from support.strategies import formulas
from symsynth.automata import compile_ltlf
from symsynth.logic import parse_ltlf
from symsynth.synthesis import Partition, solve_realizability
from symsynth.synthesis.preimage import CLUSTER_NODES, SUBSTITUTION_STEPS, Preimage
from symsynth.automata.bdd import cofactor

ATOMS = ("a", "b", "c")
CLUSTERS = (0, 12, 60, CLUSTER_NODES)
#: the DFA compiler's paths (tests/test_compose.py): the default, and every
#: product symbolic (several components, the manager's own variable order)
PATHS = {"default": None, "symbolic": {"single": 0, "product_limit": 0, "edge_limit": 0, "merged_edges": 0}}

partitions = st.lists(st.booleans(), min_size=3, max_size=3).map(
    lambda owners: Partition(tuple(a for a, o in zip(ATOMS, owners) if not o),
                             tuple(a for a, o in zip(ATOMS, owners) if o)))


def codes(dfa):
    """Every assignment to the state bits, reachable or not."""
    return [tuple(v) for v in itertools.product((False, True), repeat=len(dfa.bits))]


def letters(atoms):
    return [frozenset(a for a, v in zip(atoms, values) if v)
            for values in itertools.product((False, True), repeat=len(atoms))]


def holds_at(dfa, f, values) -> bool:
    support = dfa.bdd.support(f)
    return cofactor(dfa.bdd, {v: values[v] for v in support}, f) == dfa.bdd.true


@settings(max_examples=80, deadline=None)
@given(formula=formulas(max_depth=3), path=st.sampled_from(sorted(PATHS)), limit=st.sampled_from(CLUSTERS),
       steps=st.sampled_from([0, 10**18]), chosen=st.integers(min_value=0, max_value=2**256))
def test_the_preimage_is_the_set_of_letters_into_the_target(formula, path, limit, steps, chosen):
    """preimage(G) holds at (q, letter) iff step(q, letter) is in G, for a
    random G (bit k of `chosen`: the k-th state code is in G), by the
    relation (`steps` 0) and by substitution."""
    dfa = compile_ltlf(formula, limits=PATHS[path])
    bdd, states = dfa.bdd, codes(dfa)
    target = bdd.false
    for k, state in enumerate(states):
        if chosen >> k & 1:
            target |= dfa.state_cube(state)
    got = Preimage(dfa, limit, steps)(target)
    inside = {s for k, s in enumerate(states) if chosen >> k & 1}
    for state in states:
        for letter in letters(dfa.atoms):
            values = dict(zip(dfa.bits, state)) | {a: a in letter for a in dfa.atoms}
            assert holds_at(dfa, got, values) == (dfa.step(state, letter) in inside)


def test_the_cluster_size_decides_the_clusters():
    """One cluster per bit at 0, one for the whole relation by default, and
    in between for a size between (a counter of a's in a row: 16 states, 4 bits)."""
    text = "F(" + " & X(".join(["a"] * 15) + ")" * 15  # F(a & X(a & ... X(a))): 15 a's in a row
    dfa = compile_ltlf(parse_ltlf(text))
    assert len(dfa.bits) == 4
    assert len(Preimage(dfa, 0).clusters) == 4
    assert len(Preimage(dfa, CLUSTER_NODES).clusters) == 1
    whole = Preimage(dfa, CLUSTER_NODES).nodes
    middle = Preimage(dfa, whole - 1)
    assert 1 < len(middle.clusters) < 4
    # every primed bit is quantified in exactly one cluster
    assert sorted(v for _, qvars in middle.clusters for v in qvars) == sorted(b + "'" for b in dfa.bits)


def brute_rounds(dfa, partition, agent_first):
    """W_1, W_2, ... on the reachable states, one state at a time."""
    start = dfa.initial
    reachable, stack = {start}, [start]
    all_letters = letters(dfa.atoms)
    while stack:
        state = stack.pop()
        for letter in all_letters:
            after = dfa.step(state, letter)
            if after not in reachable:
                reachable.add(after)
                stack.append(after)
    xs = letters([a for a in dfa.atoms if a in partition.inputs])
    ys = letters([a for a in dfa.atoms if a in partition.outputs])
    rounds, win = [], set()
    while True:
        def lands(q, x, y):
            after = dfa.step(q, x | y)
            return dfa.is_accepting(after) or after in win
        if agent_first:
            new = {q for q in reachable if any(all(lands(q, x, y) for x in xs) for y in ys)}
        else:
            new = {q for q in reachable if all(any(lands(q, x, y) for y in ys) for x in xs)}
        if new <= win:
            return reachable, rounds
        win = win | new
        rounds.append(set(win))


@settings(max_examples=120, deadline=None)
@given(formula=formulas(max_depth=3), path=st.sampled_from(sorted(PATHS)), partition=partitions,
       agent_first=st.booleans(), limit=st.sampled_from(CLUSTERS),
       steps=st.sampled_from([0, 2000, SUBSTITUTION_STEPS, 10**18]))
def test_the_rounds_are_the_state_by_state_rounds(formula, path, partition, agent_first, limit, steps):
    """The fixpoint that adds the new states' preimage and quantifies at
    the states that moved only gives the same W_i on every reachable state
    as the game played naively (and so the same ranks for the strategies)."""
    dfa = compile_ltlf(formula, limits=PATHS[path])
    game = solve_realizability(dfa, partition, agent_first=agent_first, preimage=Preimage(dfa, limit, steps))
    reachable, expected = brute_rounds(dfa, partition, agent_first)
    got = [{q for q in reachable if holds_at(dfa, won, dict(zip(dfa.bits, q)))} for won in game.rounds]
    assert got == expected  # as many rounds: none only unreachable codes gain
    assert game.realizable == (dfa.initial in (expected[-1] if expected else set()))

