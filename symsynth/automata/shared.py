"""One DFA per parsed task.

The application layer parses a task once and hands the same formula object
to everything that reads it: the position graph of the explicit and forward
solvers, the compiled solver's tables, strategy files, the simulator.  Each
of them needs the task's DFA; `dfa_of` compiles it on the first request and
returns that same `SymbolicDFA` to the later ones.  Requests are matched by
the formula object itself (not by equality: hashing a formula nested
100,000 deep would recurse that deep), and the few most recent formulas are
kept alive with their DFAs, so an id is never reused while it is cached.

The symbolic solver compiles its own copy into the game's BDD manager
(`compile_ltlf(formula, bdd=...)`): its relations and the DFA must share
one manager.
"""

from __future__ import annotations

from collections import OrderedDict

from symsynth.automata.compose import compile_ltlf
from symsynth.automata.symbolic import SymbolicDFA
from symsynth.logic import ast

#: How many formulas keep their DFA (a run reads one task; tests a few).
KEPT = 8
_kept: OrderedDict[int, tuple[ast.Formula, SymbolicDFA]] = OrderedDict()


def dfa_of(formula: ast.Formula) -> SymbolicDFA:
    """The minimal DFA of `formula` (`compile_ltlf` with its defaults),
    compiled once per formula object."""
    hit = _kept.get(id(formula))
    if hit is not None and hit[0] is formula:
        _kept.move_to_end(id(formula))
        return hit[1]
    dfa = compile_ltlf(formula)
    _kept[id(formula)] = (formula, dfa)
    while len(_kept) > KEPT:
        _kept.popitem(last=False)
    return dfa
