"""symbolic.py's transition functions of one explicit DFA (`product` of a
single component): for random complete DFAs, given by their guards or by
their moves (moves.py), each bit's function read at every state code and
letter is that bit of the successor (any value on the codes past the last
state, which no state has), and the reachable set is the codes of the
states.  The moves take one relational product per bit over the transition
relation, the guards a disjunction per state and bit: both are checked
against the DFA itself, not against each other."""

from __future__ import annotations

from itertools import product as assignments

from hypothesis import given, settings
from hypothesis import strategies as st

from symsynth.automata import moves
from symsynth.automata.bdd import cofactor, new_manager, shared_size
from symsynth.automata.progression import GuardedDFA
from symsynth.automata.single import by_state
from symsynth.automata.symbolic import product

ATOMS = ["a", "b", "c"]
LETTERS = list(assignments((False, True), repeat=len(ATOMS)))


@st.composite
def tables(draw) -> list[list[int]]:
    """successor[s][letter index] of a complete DFA of 1 to 12 states."""
    n = draw(st.integers(1, 12))
    return [draw(st.lists(st.integers(0, n - 1), min_size=len(LETTERS), max_size=len(LETTERS)))
            for _ in range(n)]


def guarded(table: list[list[int]], form: str) -> GuardedDFA:
    bdd = new_manager()
    bdd.declare(*ATOMS)
    edges: list[dict[int, object]] = []
    for row in table:
        out: dict = {}
        for letter, succ in zip(LETTERS, row):
            minterm = bdd.cube(dict(zip(ATOMS, letter)))
            out[succ] = out[succ] | minterm if succ in out else minterm
        edges.append(out)
    accepting = [s % 2 == 0 for s in range(len(table))]
    if form == "edges":
        return GuardedDFA(bdd, 0, accepting, edges)
    return GuardedDFA(bdd, 0, accepting, moves=moves.encode_all(bdd, edges))


@settings(max_examples=60, deadline=None)
@given(tables(), st.sampled_from(["edges", "moves"]))
def test_each_bit_is_the_successors_bit(table, form):
    comp = guarded(table, form)
    bdd = comp.bdd
    dfa = product(bdd, ATOMS, [comp])
    width = len(dfa.bits)
    assert width == (len(table) - 1).bit_length()
    for code in range(1 << width):
        state = {bit: bool(code >> j & 1) for j, bit in enumerate(dfa.bits)}
        assert (cofactor(bdd, state, dfa.reachable) == bdd.true) == (code < len(table)), (form, code)
        if code >= len(table):
            continue
        for i, letter in enumerate(LETTERS):
            values = state | dict(zip(ATOMS, letter))
            for j, bit in enumerate(dfa.bits):
                expected = bool(table[code][i] >> j & 1)
                assert (cofactor(bdd, values, dfa.delta[bit]) == bdd.true) == expected, (form, code, letter, bit)


@given(st.integers(1, 16))
def test_the_tree_spends_no_node_on_codes_without_a_state(count):
    """single.by_state: each state's value at its code; past the last
    state false, or with `unreached` no split whose high side has no
    state (one node less for each such split)."""
    bdd = new_manager()
    width = (count - 1).bit_length()
    names = [f"q{j}" for j in range(width)]
    bdd.declare(*names, *[f"v{s}" for s in range(count)])
    values = [bdd.var(f"v{s}") for s in range(count)]  # below the bits, all different
    exact, loose = by_state(bdd, names, values), by_state(bdd, names, values, unreached=True)
    for code in range(1 << width):
        state = {name: bool(code >> j & 1) for j, name in enumerate(names)}
        assert cofactor(bdd, state, exact) == (values[code] if code < count else bdd.false)
        if code < count:
            assert cofactor(bdd, state, loose) == values[code]
    splits = sum(1 for j in range(width) for m in range(1 << j) if m < count and m + (1 << j) >= count)
    # each split on a bit above a side without states: a node in the exact tree (with false), none in the other
    assert shared_size(bdd, [loose]) + splits == shared_size(bdd, [exact])
