"""One DFA per parsed task.

The application layer parses a task once and hands the same formula object
to everything that reads it: the position graph of the explicit and forward
solvers, the compiled solver's tables, strategy files, the simulator.  Each
of them needs the task's DFA; `dfa_of` compiles it on the first request and
returns that same `SymbolicDFA` to the later ones.  Requests are matched by
the formula object itself (not by equality: hashing a formula nested
100,000 deep would recurse that deep), and the few most recent formulas are
kept alive with their DFAs, so an id is never reused while it is cached.

The symbolic solver needs the DFA in the game's BDD manager (its relations
and the DFA must share one manager), a new one for every horizon it tries
(`game.horizon`): `dfa_into(formula, bdd)` compiles the DFA once per formula
in a manager of its own, with the declared order kept (as
`compile_ltlf(formula, bdd=...)` builds it in a game's manager), and copies
it into each game's manager.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable

from symsynth.automata.bdd import BDD, new_manager
from symsynth.automata.compiler import compile_ltlf
from symsynth.automata.symbolic import SymbolicDFA
from symsynth.logic import ast

#: How many formulas keep their DFA (a run reads one task; tests a few).
KEPT = 8
_kept: OrderedDict[int, tuple[ast.Formula, SymbolicDFA]] = OrderedDict()


_ordered: OrderedDict[int, tuple[ast.Formula, SymbolicDFA]] = OrderedDict()


def dfa_of(formula: ast.Formula) -> SymbolicDFA:
    """The minimal DFA of `formula` (`compile_ltlf` with its defaults),
    compiled once per formula object."""
    return _once(_kept, formula, lambda: compile_ltlf(formula))


def dfa_into(formula: ast.Formula, bdd: BDD) -> SymbolicDFA:
    """The minimal DFA of `formula` in the manager `bdd`, as
    `compile_ltlf(formula, bdd=bdd)` makes it (the same variables in the
    same order, below those `bdd` has), compiled once per formula object."""
    made = _once(_ordered, formula, lambda: compile_ltlf(formula, bdd=new_manager(reordering=False)))
    return made.copy_to(bdd)


def _once(kept: OrderedDict[int, tuple[ast.Formula, SymbolicDFA]], formula: ast.Formula,
          make: Callable[[], SymbolicDFA]) -> SymbolicDFA:
    """`kept`'s DFA for this formula object, else `make()`'s, then kept."""
    hit = kept.get(id(formula))
    if hit is not None and hit[0] is formula:
        kept.move_to_end(id(formula))
        return hit[1]
    dfa = make()
    kept[id(formula)] = (formula, dfa)
    while len(kept) > KEPT:
        kept.popitem(last=False)
    return dfa
