"""numbered.py: the backward construction's DFA as one diagram with state
numbers at its leaves.  Its transition bits, reduced in arrays, are the
very BDDs (the same nodes) that one relational product per bit gives over
the transition relation made from its moves (the moves, made from the
diagram too, are checked by tests/test_backward.py's languages).  A wrong complement (CUDD never
complements a then-edge) or a split on a code past the last state fails
here.  (A node kept where its children are equal does not: `ite(x, a, a)`
is `a`, so it costs time, not a wrong function.)"""

from __future__ import annotations

from hypothesis import given, settings

from support.strategies import formulas
from symsynth.automata import moves
from symsynth.automata.backward import backward_dfa
from symsynth.automata.bdd import and_exists
from symsynth.automata.normal import nnf
from symsynth.automata.progression import GuardedDFA, Progression
from symsynth.automata.single import bit_functions, by_state
from symsynth.logic import atoms, parse_ltlf, to_string


def built(formula) -> GuardedDFA:
    return backward_dfa(Progression([x.key for x in atoms(formula)]), nnf(formula))


def state_bits(dfa: GuardedDFA) -> list[str]:
    """State bits above the atoms, as symbolic.product puts them."""
    names = [f"#t_{j}" for j in range(moves.width(dfa.num_states))]
    for j, name in enumerate(names):
        if name not in dfa.bdd.vars:
            dfa.bdd.insert_var(name, j)
    return names


def by_products(dfa: GuardedDFA, names: list[str]) -> dict:
    """\\E z: R /\\ z_j for each bit, R the moves merged over the states."""
    bdd = dfa.bdd
    zs = moves.bits(bdd, "z", len(names))
    relation = by_state(bdd, names, dfa.moves, unreached=True)
    return {n: and_exists(bdd, relation, bdd.var(z), zs) for n, z in zip(names, zs)}


def check(dfa: GuardedDFA, text: str) -> None:
    names = state_bits(dfa)
    assert dfa.numbered is not None
    got = dfa.numbered.bit_functions(dfa.bdd, names)
    assert got == by_products(dfa, names), text


@settings(max_examples=80, deadline=None)
@given(formulas(max_depth=4))
def test_the_bits_are_the_relational_products(formula):
    check(built(formula), to_string(formula))


def urright(n: int) -> str:
    """p1 U (p2 R (p3 U ... pn)) (bench/ltlf_generated.py's URright)."""
    text = f"p{n}"
    for i in reversed(range(1, n)):
        text = f"p{i} {'U' if i % 2 else 'R'} ({text})"
    return text


def test_the_bits_of_urright_up_to_ten():
    for n in (4, 6, 8, 10):
        check(built(parse_ltlf(urright(n))), f"urright{n}")


def test_single_takes_the_arrays_past_their_threshold(monkeypatch):
    import symsynth.automata.single as single
    dfa = built(parse_ltlf(urright(6)))
    names = state_bits(dfa)
    expected = by_products(dfa, names)
    monkeypatch.setattr(single, "ARRAYS_FROM", 0)
    assert bit_functions(dfa.bdd, dfa, names) == expected
