"""LTLf -> minimal symbolic DFA, compositionally.

1. The formula is put in negation normal form and split into conjuncts
   (with `G` pushed through `&`).
2. Each conjunct becomes an explicit DFA by formula progression and is
   minimized (Moore) while it is small.
3. The minimal components are encoded in state bits and composed as a
   synchronous product in one BDD manager; the product is minimized
   symbolically (coarsest bisimulation), since a product of minimal DFAs
   need not be minimal.

Conjunctions of many small patterns, the common case in robot tasks, thus
never build an explicit product: only the BDDs of the parts.
"""

from __future__ import annotations

from symsynth.automata.bdd import BDD, new_manager
from symsynth.automata.normal import nnf, split_conjuncts
from symsynth.automata.progression import Progression, minimize
from symsynth.automata.symbolic import SymbolicDFA, product
from symsynth.logic import ast
from symsynth.logic.parser import NextSemantics, parse_ltlf


def compile_ltlf(formula: str | ast.Formula, *, next_semantics: NextSemantics = "strong",
                 source: str = "<formula>", bdd: BDD | None = None,
                 prefix: str = "#q") -> SymbolicDFA:
    """The minimal complete DFA of an LTLf formula over non-empty traces.

    `formula` is text (parsed with `next_semantics`, errors naming `source`)
    or an AST.  The DFA's variables are declared in `bdd` (a new manager
    when omitted): one per atom, named by `Atom.key`, and state bits
    `{prefix}{c}_{j}` with primed copies.  The prefix must not be an atom
    name; the default `#q` cannot be one (`#` is not in the grammar).
    """
    if isinstance(formula, str):
        formula = parse_ltlf(formula, source=source, next_semantics=next_semantics)
    atom_keys = [a.key for a in ast.atoms(formula)]
    parts = _merge_duplicates(split_conjuncts(nnf(formula)))
    progression = Progression(atom_keys)
    components = [minimize(progression.dfa(part)) for part in parts]
    if bdd is None:
        bdd = new_manager(reordering=False)
    dfa = product(bdd, atom_keys, components, prefix=prefix)
    return dfa.minimize() if len(components) > 1 else dfa


def _merge_duplicates(parts: list[ast.Formula]) -> list[ast.Formula]:
    unique = list(dict.fromkeys(parts))
    return unique or [ast.TRUE]
