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
from symsynth.errors import InputError
from symsynth.automata.normal import nnf, split_conjuncts
from symsynth.automata.progression import Progression, minimize
from symsynth.automata.symbolic import SymbolicDFA, product
from symsynth.logic import ast
from symsynth.logic.parser import NextSemantics, parse_ltlf


#: Limits past which a formula is refused with a message (each part's state
#: bits and each atom is a BDD variable; the product's state count is
#: counted in a double, which ends at 2^1024).
MAX_ATOMS = 1000
MAX_STATE_BITS = 1000


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
    if len(atom_keys) > MAX_ATOMS:
        raise InputError(f"{source}: the formula has {len(atom_keys)} atoms; symsynth compiles formulas "
                         f"of at most {MAX_ATOMS}")
    parts = _merge_duplicates(split_conjuncts(nnf(formula)))
    progression = Progression(atom_keys)
    components = [minimize(progression.dfa(part)) for part in parts]
    bits = sum(max(1, (c.num_states - 1).bit_length()) for c in components)
    if bits > MAX_STATE_BITS:
        raise InputError(f"{source}: the DFA's {len(components)} parts need {bits} state bits together; "
                         f"symsynth composes at most {MAX_STATE_BITS} (2^{MAX_STATE_BITS} states)")
    if bdd is None:
        bdd = new_manager(reordering=False)
    dfa = product(bdd, atom_keys, components, prefix=prefix)
    return dfa.minimize() if len(components) > 1 else dfa


def _merge_duplicates(parts: list[ast.Formula]) -> list[ast.Formula]:
    unique = list(dict.fromkeys(parts))
    return unique or [ast.TRUE]
