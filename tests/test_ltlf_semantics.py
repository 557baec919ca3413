"""The reference evaluator `holds` on hand-checked LTLf cases (non-empty finite traces)."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.strategies import formulas, traces
from symsynth.logic import holds, parse_ltlf
from symsynth.logic.ast import (
    FALSE, TRUE, Always, And, Eventually, Last, Next, Not, Or, Release, Until, WeakNext,
    WeakUntil,
)

E = frozenset()          # the letter where nothing holds
A = frozenset({"a"})
B = frozenset({"b"})
C = frozenset({"c"})
AB = frozenset({"a", "b"})


def all_traces(max_length, alphabet=(E, A, B, AB)):
    for n in range(1, max_length + 1):
        yield from (list(t) for t in itertools.product(alphabet, repeat=n))


def test_last_holds_exactly_at_the_final_position():
    for n in range(1, 5):
        trace = [E] * n
        assert [holds(Last(), trace, i) for i in range(n)] == [False] * (n - 1) + [True]


def test_weak_next_false_holds_exactly_at_the_final_position():
    for n in range(1, 5):
        trace = [A] * n
        assert [holds(parse_ltlf("WX false"), trace, i) for i in range(n)] \
            == [False] * (n - 1) + [True]


def test_strong_next_true_means_length_at_least_two():
    for trace in all_traces(4):
        assert holds(parse_ltlf("X true"), trace) == (len(trace) >= 2)
        assert holds(parse_ltlf("X[!] true"), trace) == (len(trace) >= 2)


def test_always_false_has_no_model():
    # G false fails already at the first position of every non-empty trace
    assert not any(holds(parse_ltlf("G false"), t) for t in all_traces(4))
    assert all(holds(parse_ltlf("F true"), t) for t in all_traces(4))


def test_strong_and_weak_next_differ_only_at_the_last_position():
    assert not holds(parse_ltlf("X a"), [A])
    assert holds(parse_ltlf("WX a"), [A])
    assert holds(parse_ltlf("WX a"), [E])          # vacuous: no next position
    assert holds(parse_ltlf("WX false"), [A])
    assert not holds(parse_ltlf("WX a"), [A, E])
    assert holds(parse_ltlf("X a"), [E, A])
    assert holds(parse_ltlf("X a", next_semantics="weak"), [E])


def test_until_at_the_last_position_needs_its_right_side_there():
    until = parse_ltlf("a U b")
    assert not holds(until, [A])
    assert holds(until, [B])
    assert not holds(until, [A, A], 1)
    assert holds(until, [A, AB], 1)
    assert holds(until, [E, B], 1)
    # from the start: a until b, and b may come at once
    assert holds(until, [A, A, B])
    assert holds(until, [B, E, E])
    assert not holds(until, [A, E, B])      # a breaks before b
    assert not holds(until, [A, A, A])      # b never comes: U is strong


def test_release():
    release = parse_ltlf("a R b")
    assert holds(release, [B, B, B])        # b forever
    assert holds(release, [B, AB, E])       # released at 1, b held up to and including it
    assert not holds(release, [B, A, E])    # a at 1 but b fails there
    assert not holds(release, [E])
    assert holds(release, [AB])
    assert parse_ltlf("a V b") == release


def test_weak_until():
    weak = parse_ltlf("a W b")
    assert holds(weak, [A, A, A])           # b never comes: allowed
    assert holds(weak, [A, B])
    assert holds(weak, [B])
    assert not holds(weak, [A, E, B])
    assert not holds(weak, [E])
    assert not holds(parse_ltlf("a U b"), [A, A, A])


def test_nested_until_and_release():
    # (a U b) U c: c at 2, and a U b at positions 0 and 1
    nested = parse_ltlf("(a U b) U c")
    assert holds(nested, [A, B, C])
    assert not holds(nested, [A, E, C])     # a U b fails at 0: {} before any b
    assert holds(nested, [C])
    # a U (b R c): b R c must hold somewhere, a before it
    a_until_release = parse_ltlf("a U (b R c)")
    assert holds(a_until_release, [A, C, C])                    # c forever from 1
    assert not holds(a_until_release, [A, C, E])                # c stops before b
    assert holds(a_until_release, [A, C, frozenset({"b", "c"}), E])
    # (a R b) U c at the last position: c there
    assert holds(parse_ltlf("(a R b) U c"), [E, C], 1)
    # G(a -> X b) with strong and weak next at the last position
    assert holds(parse_ltlf("G(a -> X b)"), [A, B])
    assert not holds(parse_ltlf("G(a -> X b)"), [A, AB])
    assert holds(parse_ltlf("G(a -> WX b)"), [A, AB])


def test_eventually_always_and_always_eventually_look_at_the_last_letter():
    for trace in all_traces(3):
        assert holds(parse_ltlf("F G a"), trace) == ("a" in trace[-1])
        assert holds(parse_ltlf("G F a"), trace) == ("a" in trace[-1])


def test_predicate_atoms_are_looked_up_by_key():
    formula = parse_ltlf("F at(black, top)")
    assert holds(formula, [frozenset(), frozenset({"at(black, top)"})])
    assert not holds(formula, [frozenset({"at(black,top)"})])


def test_empty_trace_and_bad_position_are_refused():
    with pytest.raises(ValueError):
        holds(TRUE, [])
    with pytest.raises(ValueError):
        holds(TRUE, [A], 1)


# Dualities and expansion laws, each a hand-proved identity of LTLf on
# non-empty finite traces; `holds` implements every operator directly, so
# these compare independent definitions.
f_and_g = st.tuples(formulas(max_depth=2), formulas(max_depth=2))


@settings(max_examples=150, deadline=None)
@given(f_and_g, traces())
def test_identities(fg, trace):
    f, g = fg
    same = [
        (Not(Next(f)), WeakNext(Not(f))),
        (Not(Until(f, g)), Release(Not(f), Not(g))),
        (WeakUntil(f, g), Release(g, Or(f, g))),
        (WeakUntil(f, g), Or(Until(f, g), Always(f))),
        (Eventually(f), Until(TRUE, f)),
        (Always(f), Release(FALSE, f)),
        (Last(), WeakNext(FALSE)),
        (Until(f, g), Or(g, And(f, Next(Until(f, g))))),
        (Release(f, g), And(g, Or(f, WeakNext(Release(f, g))))),
    ]
    for i in range(len(trace)):
        for left, right in same:
            assert holds(left, trace, i) == holds(right, trace, i), (left, right, trace, i)
