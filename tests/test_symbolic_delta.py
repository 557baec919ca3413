"""symbolic.py's transition functions of one explicit DFA (`product` of a
single component): for random complete DFAs, given by their guards or by
their moves (moves.py), each bit's function read at every state code and
letter is that bit of the successor, and false on the codes past the last
state.  The moves take one relational product per bit over the transition
relation, the guards a disjunction per state and bit: both are checked
against the DFA itself, not against each other."""

from __future__ import annotations

from itertools import product as assignments

from hypothesis import given, settings
from hypothesis import strategies as st

from symsynth.automata import moves
from symsynth.automata.bdd import cofactor, new_manager
from symsynth.automata.progression import GuardedDFA
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
        for i, letter in enumerate(LETTERS):
            values = state | dict(zip(ATOMS, letter))
            for j, bit in enumerate(dfa.bits):
                expected = code < len(table) and bool(table[code][i] >> j & 1)
                assert (cofactor(bdd, values, dfa.delta[bit]) == bdd.true) == expected, (form, code, letter, bit)
