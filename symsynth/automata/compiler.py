"""LTLf -> minimal symbolic DFA: the entry point (`compile_ltlf`), which
chooses the construction -- the whole formula by progression
(progression.py), backwards (backward.py) or compositionally over its
Boolean skeleton (compose.py) -- and makes the chosen parts one symbolic
DFA (symbolic.py's product, minimized when it has several parts).
"""

from __future__ import annotations

from typing import Any, Literal, get_args

from symsynth.automata import choice
from symsynth.automata.backward import backward_dfa
from symsynth.automata.bdd import BACKEND, BDD, Function, new_manager, without_cyclic_gc
from symsynth.automata.compose import Composer
from symsynth.automata.normal import nnf, split_conjuncts
from symsynth.automata.products import OPS, fold, started
from symsynth.automata.progression import GuardedDFA, Progression, TooLarge, minimize
from symsynth.automata.symbolic import SymbolicDFA, atoms_read, is_local, product
from symsynth.errors import InputError
from symsynth.logic import ast
from symsynth.logic.parser import NextSemantics, parse_ltlf

#: How `compile_ltlf` builds the DFA (its docstring).
Construction = Literal["auto", "compositional", "progression", "backward"]

#: Limits past which a formula is refused with a message (each part's state
#: bits and each atom is a BDD variable; the product's state count is
#: counted in a double, which ends at 2^1024).
MAX_ATOMS = 1000
MAX_STATE_BITS = 1000


def compile_ltlf(formula: str | ast.Formula, *, next_semantics: NextSemantics = "strong",
                 source: str = "<formula>", bdd: BDD | None = None,
                 prefix: str = "#q", compositional: bool = True,
                 limits: dict[str, Any] | None = None, construction: Construction = "auto") -> SymbolicDFA:
    """The minimal complete DFA of an LTLf formula over non-empty traces.

    `formula` is text (parsed with `next_semantics`, errors naming `source`)
    or an AST.  The DFA's variables are declared in `bdd` (a new manager
    when omitted): one per atom, named by `Atom.key`, and state bits
    `{prefix}{c}_{j}` with primed copies.  The prefix must not be an atom
    name; the default `#q` cannot be one (`#` is not in the grammar).

    `compositional=False` is the earlier construction (top-level conjuncts
    by progression, one symbolic product), kept as a reference; `limits`
    overrides `Composer`'s size limits (tests use it to force each path).

    `construction="progression"` builds the whole formula by progression
    instead, from its start: only the states reachable there are made.  It
    wins where the parts of the formula are large alone and small together
    (SYNTCOMP's chomp: `PRESET && (G REQUIRE -> G ASSERT && ...)`, whose
    ASSERT alone tracks every subset of the board, 2^(N*M), and the whole
    the boards that legal moves reach) and loses where a part's
    progression is exponential (the counters' `counter_i <-> X carry_i`).
    `construction="backward"` evaluates the formula backwards and
    determinizes the reverse (backward.py): the minimal DFA with no
    minimization step, and no guard per edge.
    `"auto"` (the default) chooses between the two by `choice.py`'s rule
    and budget; `limits` or `compositional=False` make it compositional
    (they are about that construction).
    """
    if construction not in get_args(Construction):
        raise ValueError(f"construction must be one of {', '.join(get_args(Construction))}, not {construction!r}")
    if construction == "auto" and (limits is not None or not compositional):
        construction = "compositional"
    with without_cyclic_gc():
        return _compile(formula, next_semantics, source, bdd, prefix,
                        construction if compositional else False, limits)


def _compile(formula: str | ast.Formula, next_semantics: NextSemantics, source: str, bdd: BDD | None,
             prefix: str, construction: Construction | Literal[False], limits: dict[str, Any] | None) -> SymbolicDFA:
    if isinstance(formula, str):
        formula = parse_ltlf(formula, source=source, next_semantics=next_semantics)
    atom_keys = [a.key for a in ast.atoms(formula)]
    if len(atom_keys) > MAX_ATOMS:
        raise InputError(f"{source}: the formula has {len(atom_keys)} atoms; symsynth compiles formulas "
                         f"of at most {MAX_ATOMS}")
    progression = Progression(atom_keys)
    acceptance: tuple | None
    whole = None
    if construction == "progression":
        whole = minimize(progression.dfa(nnf(formula)))
    elif construction == "backward":
        whole = backward_dfa(progression, nnf(formula))  # minimal as built
    elif construction == "auto":
        whole = _backward_by_rule(formula, progression) or _progressed_within_budget(formula, progression)
        if whole is None:
            progression = Progression(atom_keys)  # (the attempt's obligations and nodes left behind)
    if whole is not None:
        components, acceptance = [whole], None
    elif construction:
        composer = Composer(progression, **(limits or {}))
        result = composer.finish(composer.compose(formula))
        if isinstance(result, GuardedDFA):
            components, acceptance = [result], None
        else:
            components, acceptance = result.components, result.acceptance
    else:
        parts = list(dict.fromkeys(split_conjuncts(nnf(formula)))) or [ast.TRUE]
        components = [minimize(progression.dfa(part)) for part in parts]
        acceptance = ("and", [("c", c) for c in components]) if len(components) > 1 else None
    if acceptance is not None and _holds_initially(acceptance):
        components = components + [started(progression.bdd)]  # the start state must reject
        acceptance = ("and", [acceptance, ("c", components[-1])])
    bits = sum(max(1, (c.num_states - 1).bit_length()) for c in components)
    if bits > MAX_STATE_BITS:
        raise InputError(f"{source}: the DFA's {len(components)} parts need {bits} state bits together; "
                         f"symsynth composes at most {MAX_STATE_BITS} (2^{MAX_STATE_BITS} states)")
    own = bdd is None
    if bdd is None:  # dynamic reordering while the product is built and minimized, unless
        # its many parts read disjoint atoms: then their declared order is kept throughout
        # (symbolic.is_local), set here once: switching reordering off and on again in the
        # middle of the work has left CUDD's dead-node count wrong ("cuddGarbageCollect:
        # problem in table") on Random/Syft syft_4/003
        if len(components) == 1 and BACKEND == "cudd":
            # its own manager, the state bits put above the atoms: no guard copied
            bdd = components[0].bdd
        else:
            local = len(components) > 1 and is_local(atoms_read(components, atom_keys))
            bdd = new_manager(reordering=len(components) > 1 and not local)
    manager = bdd
    index = {id(c): i for i, c in enumerate(components)}
    combine = None if acceptance is None else (lambda accs: _evaluate(acceptance, accs, index, bdd))
    dfa = product(bdd, atom_keys, components, prefix=prefix, combine=combine)
    if len(components) > 1 or (acceptance is not None and acceptance[0] != "c"):
        dfa = dfa.minimize()  # (one component read through a Boolean combination: `!(X c -> X c)`)
    if own:
        manager.configure(reordering=False)  # a stable order for whoever uses the DFA
    return dfa


def _backward_by_rule(formula: ast.Formula, progression: Progression) -> GuardedDFA | None:
    """`construction="auto"`: the minimal DFA by the backward construction
    when `choice` says so (deep until / release alternation, few
    obligations), else None."""
    if choice.rule(formula) is not None:
        return None
    normal = nnf(formula)
    if choice.alternation(normal) < choice.AUTO_ALTERNATION:
        return None
    try:
        return backward_dfa(progression, normal, max_obligations=choice.AUTO_OBLIGATIONS)
    except TooLarge:
        return None


def _progressed_within_budget(formula: ast.Formula, progression: Progression) -> GuardedDFA | None:
    """`construction="auto"`: the minimal DFA of the whole formula by
    progression, unless `choice.rule` sends it to the compositional
    construction or it passes `choice`'s budget (None then)."""
    if choice.rule(formula) is not None:
        return None
    try:
        return minimize(progression.dfa(nnf(formula), choice.AUTO_EDGES,
                                        (choice.AUTO_DENSE_AFTER, choice.AUTO_DEGREE)))
    except TooLarge:  # (TooDense too)
        return None


def _holds_initially(acceptance: tuple) -> bool:
    """Whether the combination accepts when every component is at its
    (rejecting) initial state."""
    return fold(acceptance, lambda d: False, lambda op, xs: OPS[op](xs))


def _evaluate(acceptance: tuple, accs: list[Function], index: dict[int, int], bdd: BDD) -> Function:
    def apply(op, xs):
        if op == "not":
            return ~xs[0]
        if op == "implies":
            return ~xs[0] | xs[1]
        if op == "equiv":
            return bdd.apply("<=>", xs[0], xs[1])
        result = bdd.true if op == "and" else bdd.false
        for x in xs:
            result = (result & x) if op == "and" else (result | x)
        return result
    return fold(acceptance, lambda d: accs[index[id(d)]], apply)
