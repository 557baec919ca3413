"""How `compile_ltlf` numbers DFA states is part of the strategy file format.

A strategy file stores DFA states as the codes of the state bits, and
records the numbering they come from (`symsynth.automata.NUMBERING`); a
reader refuses a file of another numbering.  That only protects users if
the number changes whenever the codes do.  This test keeps, for a set of
formulas, the code of every state in an order fixed by the language alone
(breadth-first from the initial state, letters in binary counting order over
the sorted atoms), in `tests/data/dfa-numbering.json`.  When a change to the
compiler renumbers states, it fails: bump `NUMBERING` and rewrite the file
with `python tests/test_dfa_numbering.py --write`.

The minimal DFA is unique up to renaming its states, so the canonical order
below is the same for every correct compiler; only the codes can differ.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import sys
from pathlib import Path

import pytest

from symsynth.automata import NUMBERING, compile_ltlf
from symsynth.errors import InputError
from symsynth.game.strategy import StrategyFile, check_header
from symsynth.logic import parse_ltlf
from symsynth.scene import load_scene

DATA = Path(__file__).parent / "data" / "dfa-numbering.json"
ROOT = Path(__file__).parent.parent

FORMULAS = [
    "F(at(b, goal))",
    "F(at(black, top) & at(white, support1) & at(white, support2))"
    " & G(holding(block) & !at(block, top) & X(at(block, top) & !holding(block))"
    " -> at(block, support1) & at(block, support2))",
    "F(at(black, center) & ((at(white, l1) & at(white, l3)) | (at(white, l2) & at(white, l4))))",
    "G(a -> F b) & F c",
    "a U (b U c)",
    "(G F a) -> G(b -> X c)",
    "!(a R b) | X X c",
    "p1 U (p2 R (p3 U (p4 R (p5 U (p6 R (p7 U p8))))))",  # auto: the backward construction
]


def codes_in_canonical_order(text: str, **options) -> list[str]:
    """The code of each reachable state, in breadth-first order from the
    initial state with letters tried in binary counting order."""
    dfa = compile_ltlf(text, **options)
    atoms = sorted(dfa.atoms)
    letters = [{a for a, on in zip(atoms, bits) if on}
               for bits in itertools.product((False, True), repeat=len(atoms))]
    order, seen = [dfa.initial], {dfa.initial}
    for state in order:
        for letter in letters:
            succ = dfa.step(state, letter)
            if succ not in seen:
                seen.add(succ)
                order.append(succ)
    return ["".join("01"[b] for b in state) for state in order]


def current() -> dict:
    return {"numbering": NUMBERING, "formulas": {f: codes_in_canonical_order(f) for f in FORMULAS}}


@pytest.mark.parametrize("formula", FORMULAS)
def test_codes_unchanged_within_a_numbering(formula):
    recorded = json.loads(DATA.read_text())
    assert recorded["numbering"] == NUMBERING, (
        "NUMBERING changed: rewrite tests/data/dfa-numbering.json with "
        "`python tests/test_dfa_numbering.py --write`")
    assert formula in recorded["formulas"], "a new formula: rewrite the data file (--write)"
    assert codes_in_canonical_order(formula) == recorded["formulas"][formula], (
        "compile_ltlf numbers this formula's states differently from the recorded numbering "
        f"{NUMBERING}: strategy files written before would be misread, so bump "
        "symsynth.automata.NUMBERING and rewrite the data file (--write)")


def test_the_numbering_before_composition_differs():
    """Numbering 1 (per-conjunct progression, still `compositional=False`)
    codes some recorded formula differently, so this test would have caught
    the change that made numbering 2."""
    assert any(codes_in_canonical_order(f, compositional=False) != codes_in_canonical_order(f)
               for f in FORMULAS)


def test_a_strategy_of_another_numbering_is_refused_with_the_reason():
    scene = load_scene(ROOT / "scenes" / "shelf.yaml")
    formula = parse_ltlf(scene.task)
    dfa = compile_ltlf(scene.task)
    table = StrategyFile(scene=scene.name, task=scene.task, k=scene.k, resolution=1.0, units=None,
                         cost_bound=None, objects=scene.object_names, dfa_bits=tuple(dfa.bits),
                         dfa_initial=tuple(dfa.initial), positions={}, budgets={})
    assert check_header(scene, table) == formula
    for old in (1, NUMBERING + 1):
        with pytest.raises(InputError, match=f"numbering {old}.*solve again"):
            check_header(scene, dataclasses.replace(table, dfa_numbering=old))


if __name__ == "__main__" and sys.argv[1:] == ["--write"]:
    DATA.write_text(json.dumps(current(), indent=1).replace("\n   ", " ").replace("\n  ]", " ]") + "\n")
    print(f"wrote {DATA}")
