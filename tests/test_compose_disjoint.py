"""Small operands over disjoint atoms are multiplied explicitly when the
product shrinks (issue 31's assume-guarantee family: 8 pairs took 6.3 s
through a symbolic product of 2^n codes, 1.4 s now), and kept apart when
it does not (GFand's `F q_i`)."""

from __future__ import annotations

from support.reference import minimal_num_states
from symsynth.automata import compile_ltlf
from symsynth.automata.compose import Composer
from symsynth.automata.progression import GuardedDFA, Progression
from symsynth.logic import ast, parse_ltlf


def composed(text: str):
    formula = parse_ltlf(text)
    composer = Composer(Progression([a.key for a in ast.atoms(formula)]))
    return composer.compose(formula)


def test_assumptions_over_disjoint_atoms_collapse_into_one_explicit_dfa():
    # each says "the trace does not end with r_i": together, "the last letter has no r_i"
    result = composed(" & ".join(f"G(r{i} -> F !r{i})" for i in range(1, 7)))
    assert isinstance(result, GuardedDFA)
    assert result.num_states == 2  # "no letter yet, or the last one had an r_i", and its opposite


def test_independent_parts_that_do_not_shrink_stay_symbolic():
    result = composed(" & ".join(f"F q{i}" for i in range(1, 7)))
    assert not isinstance(result, GuardedDFA)
    assert len(result.components) == 6


def test_assume_guarantee_is_the_reference_language():
    text = ("(G(r1 -> F !r1) & G(r2 -> F !r2) & G(r3 -> F !r3)) -> "
            "(G(r1 -> F g1) & G(r2 -> F g2) & G(!(g1 & g2)))")
    assert compile_ltlf(text).num_states == minimal_num_states(parse_ltlf(text))
