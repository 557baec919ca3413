"""Right-nested chains of binary temporal operators by progression: the
states are kept canonical by the implications among their obligations, so
the unminimized DFA has about as many states as the minimal one (issue 31:
a release chain of length 12 took 5.5 s, its progression listing 2^11
states that minimize to 14)."""

from __future__ import annotations

import pytest

from support.reference import minimal_num_states
from symsynth.automata.normal import nnf
from symsynth.automata.progression import Progression, minimize
from symsynth.logic import ast, parse_ltlf


def chain(ops: str) -> str:
    n = len(ops) + 1
    text = f"p{n}"
    for i in range(n - 1, 0, -1):
        text = f"p{i} {ops[i - 1]} ({text})"
    return text


def progressed(text: str):
    formula = nnf(parse_ltlf(text))
    return Progression([a.key for a in ast.atoms(formula)]).dfa(formula)


@pytest.mark.parametrize("ops", ["R" * 9, "U" * 9, "W" * 9])
def test_a_chain_is_progressed_without_the_subsets_of_its_links(ops):
    dfa = progressed(chain(ops))
    n = len(ops) + 1
    assert dfa.num_states <= n * n  # at most about a state per pair of links: not 2^(n-1)
    assert minimize(dfa).num_states in (n + 1, n + 2)  # the links, the start, a sink (U: none accepting)


@pytest.mark.parametrize("ops", ["RRR", "URUR", "RWG"[:2] + "R", "RUU"])
def test_short_chains_are_the_reference_language(ops):
    text = chain(ops)
    assert minimize(progressed(text)).num_states == minimal_num_states(parse_ltlf(text))
