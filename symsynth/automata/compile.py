"""LTLf -> minimal symbolic DFA, compositionally over the Boolean structure.

1. The formula's Boolean skeleton (`&`, `|`, `->`, `<->`, `!`) is taken
   apart down to its *leaves*: subformulas without temporal operators, and
   subformulas whose top operator is temporal.  Boolean structure hidden
   under a temporal operator is pulled out where the logic allows it
   (`normal.expose`): `G(f & g) = G f & G g`, `F(f | g) = F f | F g`,
   `X` and `WX` through `&` / `|` / `->`, and `X !f = !WX f`.
2. Each leaf becomes a minimal explicit DFA by formula progression
   (progression.py): leaves are small temporal patterns.
3. The skeleton is evaluated bottom-up.  `!` complements a DFA; `&` and `|`
   (flattened to n-ary nodes), `->` and `<->` take products.  Products stay
   explicit (and are minimized, so the next product starts small) while
   they are small: as in Lisa (Bansal, Li, Tabajara, Vardi, AAAI 2020), the
   two smallest operands of an n-ary node are combined first, explicitly
   while each has fewer than `EXPLICIT_SINGLE` states and their product
   fewer than `EXPLICIT_PRODUCT`; past that the remaining operands become
   components of one *symbolic* product, whose acceptance is the Boolean
   combination of theirs.
4. The symbolic product is built in one BDD manager and minimized
   symbolically (coarsest bisimulation), since a product of minimal DFAs
   need not be minimal.

Traces are non-empty: every explicit DFA here has a non-accepting initial
state, and a combination that would accept at the start (the complement, an
implication, an equivalence) gets a fresh initial state (explicitly) or a
"started" component (symbolically).  Every pass is iterative or bounded by
the parser's nesting limit.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

from symsynth.automata.bdd import BACKEND, BDD, Function, and_exists, exists, new_manager, swap
from symsynth.automata.growth import grew
from symsynth.automata.invariant import Invariants, invariant_shape
from symsynth.automata.normal import expose, nnf, split_conjuncts
from symsynth.automata import moves as moves_
from symsynth.automata.progression import GuardedDFA, Progression, TooDense, TooLarge, minimize
from symsynth.automata.symbolic import SymbolicDFA, atoms_read, is_local, product
from symsynth.errors import InputError
from symsynth.logic import ast
from symsynth.logic.parser import NextSemantics, parse_ltlf

#: Limits past which a formula is refused with a message (each part's state
#: bits and each atom is a BDD variable; the product's state count is
#: counted in a double, which ends at 2^1024).
MAX_ATOMS = 1000
MAX_STATE_BITS = 1000

#: Explicit products while both operands have fewer states than this and
#: the product of their state counts is under EXPLICIT_PRODUCT, and while
#: the product has at most EXPLICIT_EDGES edges (an explicit state lists one
#: guard per successor: past that, the attempt is dropped and the operands
#: go symbolic).  Lisa's defaults are 800 and 2,500; ours are larger since an
#: explicit product and its minimization (partition refinement, below) cost
#: little next to a symbolic product's minimization, which works on pairs of
#: states (the counters: 1,025 x 5 states explicit in 0.1 s; symbolic, over
#: a minute).  The edge limit bounds a failed attempt to about a second, and
#: after one, no pair at least as large is tried (see `merge`).
EXPLICIT_SINGLE = 100_000
EXPLICIT_PRODUCT = 1_000_000
EXPLICIT_EDGES = 200_000

#: An explicit product made from guards turns to the operands' moves
#: (`_moves_product`) when its states have more than this many successors
#: on average (found early, cheaply): a guard per edge costs what a moves
#: BDD per state does not.  (Before the moves, such a product was dropped
#: for the symbolic product: Nim nim_03_03 then timed out; its 258 x 252
#: states of 256 x 99 successors take 0.64 s on moves.)
EXPLICIT_DEGREE = 100
DENSE_AFTER = 100

#: An explicit product whose operands' successors per state multiply to
#: more than this on average is made from their moves (moves.py: a few BDD
#: operations per product state, where guards cost one per pair of edges).
#: Measured on the products of Nim, Random/Syft and Random/Lydia, both ways
#: (CPU, product and minimization): the moves cost 1.7-13x less from 2,400
#: (Nim nim_03_03's 258 x 252 states of 256 x 99 successors: 0.64 s against
#: 7.5 s), 0.5-1.7x between 90 and 470, and up to 25x more on sparse DFAs
#: (a BDD operation on a state's moves costs 10-100 us in all).
MOVES_PAIRS = 1000
#: ... or when an operand given by its moves only (a dense product's, an
#: invariant's) has more than this many successors per state on average:
#: its edges would have to be split off its moves first, one guard per edge
#: (Nim nim_04_01: 3.0 s that way, 1.2 s on the moves; 16, 32 and 64 gave
#: nim_03_01 0.16, 0.12, 0.12 s and nim_03_02 0.63, 0.69, 0.89 s).
MOVES_DEGREE = moves_.SPARSE_DEGREE

#: An explicit `&` / `|` with an operand of at most this many states that
#: looks a bounded number of letters ahead and a larger one is made by
#: `prefix_product` (cost: one pass over the larger operand's edges).
PREFIX_STATES = 256

#: Two operands over disjoint atoms whose state counts multiply to at most
#: DISJOINT_PAIRS are tried as an explicit product (`Composer._related`),
#: kept when it has at most 1 / SHRINK of the pairs' states: independent
#: parts whose product does not shrink stay apart (GFand's `F q_i`: 2^n).
DISJOINT_PAIRS = 16
SHRINK = 2
#: ... and no more are tried in one `merge` after this many did not shrink.
DISJOINT_TRIES = 4

#: The edge limit of a product grows to this many times the edges of its
#: larger operand (a 16,000-state counter times a 4-state initial condition:
#: 300,000 edges, against a symbolic product of 2^48 codes).
GROWTH = 8

#: ... and to SPARSE_EDGES when the operands' average successors per state
#: multiply to at most SPARSE_DEGREE: a product of sparse DFAs has about as
#: many edges per state as they do, where a symbolic product must find its
#: equivalent pairs by a bisimulation over pairs of states (Double-Counter
#: counters_07: 259 x 259 states of 4 and 5 successors, 65,000 states
#: explicitly; symbolically, over 5 minutes).
SPARSE_DEGREE = 32
SPARSE_EDGES = 2_000_000

#: The components left at the end are multiplied explicitly while the
#: product of their state counts is under this (`Composer.finish`): they
#: read disjoint atoms, and only a product that shrinks when minimized
#: pays (a Syft specification: 536 pairs, 2 states); independent parts
#: whose product does not shrink stay symbolic (GFand: 3 x 2^(n-1) pairs,
#: as many states).
FINAL_PRODUCT = 4096
#: ... and while that times the product of their largest out-degrees (a
#: bound on the explicit product's edges) is under this: independent parts
#: multiply their successors (GFand: 2^n per state).
FINAL_EDGES = 25_000

#: A component of the final symbolic product with at least FACTOR_STATES
#: states and FACTOR_DEGREE successors per state on average is replaced by
#: the operands of its explicit product (`Composer._factored`).
FACTOR_STATES = 64
FACTOR_DEGREE = 16

#: A conjunction of bounded-lookahead invariants is one leaf while its DFA
#: has at most MERGED_EDGES edges (built by progression) or, when it looks
#: one step ahead (invariant.py, which costs per state), at most
#: MERGED_INVARIANT_EDGES edges and MERGED_DEGREE successors per state on
#: average (plus a small slack); past that, part by part.  The degree bound
#: tells the counters and Nim (4 and 40 successors per state: one leaf) from
#: the random Syft guarantees (`G(!X p | q)` and mutual exclusions: a state
#: remembers the last letter and reaches most others, 256 successors per
#: state), whose parts a symbolic product keeps small.
MERGED_EDGES = 2000
MERGED_INVARIANT_EDGES = 100_000
MERGED_DEGREE = 64

#: Boolean operators of the skeleton, as functions of the operands' acceptance.
_OPS = {
    "and": lambda xs: all(xs),
    "or": lambda xs: any(xs),
    "implies": lambda xs: (not xs[0]) or xs[1],
    "equiv": lambda xs: xs[0] == xs[1],
    "not": lambda xs: not xs[0],
}


def compile_ltlf(formula: str | ast.Formula, *, next_semantics: NextSemantics = "strong",
                 source: str = "<formula>", bdd: BDD | None = None,
                 prefix: str = "#q", compositional: bool = True,
                 limits: dict[str, Any] | None = None) -> SymbolicDFA:
    """The minimal complete DFA of an LTLf formula over non-empty traces.

    `formula` is text (parsed with `next_semantics`, errors naming `source`)
    or an AST.  The DFA's variables are declared in `bdd` (a new manager
    when omitted): one per atom, named by `Atom.key`, and state bits
    `{prefix}{c}_{j}` with primed copies.  The prefix must not be an atom
    name; the default `#q` cannot be one (`#` is not in the grammar).

    `compositional=False` is the earlier construction (top-level conjuncts
    by progression, one symbolic product), kept as a reference; `limits`
    overrides `Composer`'s size limits (tests use it to force each path).
    """
    with _without_cyclic_gc():
        return _compile(formula, next_semantics, source, bdd, prefix, compositional, limits)


@contextmanager
def _without_cyclic_gc() -> Iterator[None]:
    """Python's cyclic garbage collector paused, restored after.  A
    compilation makes no reference cycles (tests/test_compose.py checks
    that none is left), but its allocations trigger full collections,
    each a walk over every object of the process (lark's, numpy's, ...:
    16-21 ms here): a third of nim_03_01's 0.05 s when one falls inside."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _compile(formula: str | ast.Formula, next_semantics: NextSemantics, source: str, bdd: BDD | None,
             prefix: str, compositional: bool, limits: dict[str, Any] | None) -> SymbolicDFA:
    if isinstance(formula, str):
        formula = parse_ltlf(formula, source=source, next_semantics=next_semantics)
    atom_keys = [a.key for a in ast.atoms(formula)]
    if len(atom_keys) > MAX_ATOMS:
        raise InputError(f"{source}: the formula has {len(atom_keys)} atoms; symsynth compiles formulas "
                         f"of at most {MAX_ATOMS}")
    progression = Progression(atom_keys)
    if compositional:
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
        components = components + [_started(progression.bdd)]  # the start state must reject
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


# --------------------------------------------------------------- composition


@dataclass
class Symbolic:
    """Components to be composed symbolically and the Boolean combination of
    their acceptance: `("c", dfa)`, `("not", e)`, `(op, [e, ...])`."""

    components: list[GuardedDFA] = field(default_factory=list)
    acceptance: tuple = ()


Result = GuardedDFA | Symbolic


class Composer:
    """Evaluates the Boolean skeleton of formulas bottom-up (no recursion)."""

    def __init__(self, progression: Progression, *, single: int = EXPLICIT_SINGLE,
                 product_limit: int = EXPLICIT_PRODUCT, edge_limit: int = EXPLICIT_EDGES,
                 merged_edges: int = MERGED_EDGES, factor_states: int = FACTOR_STATES,
                 factor_degree: int = FACTOR_DEGREE, final_explicit: bool = True,
                 moves_pairs: float = MOVES_PAIRS):
        self.progression = progression
        self.invariants = Invariants(progression)
        self.single = single
        self.product_limit = product_limit
        self.edge_limit = edge_limit
        self.merged_edges = merged_edges
        self.factor_states, self.factor_degree = factor_states, factor_degree
        self.final_explicit = final_explicit
        self.moves_pairs = moves_pairs
        self.independent = False
        self._failed_bound: float = float("inf")  # a product this large (in state pairs) failed
        self._leaves: dict[ast.Formula, GuardedDFA] = {}
        self._support: dict[int, set[str]] = {}
        self._bounded_dfas: dict[int, bool] = {}  # (ids of DFAs in _alive)
        self._alive: list[GuardedDFA] = []  # keys of _support stay unique
        self._factors: dict[int, tuple[str, list[GuardedDFA]]] = {}  # explicit result -> (op, operands)

    def compose(self, formula: ast.Formula) -> Result:
        propositional, bounded = _plain_nodes(formula)
        self._propositional, self._bounded = propositional, bounded
        self._merged: dict[int, tuple[ast.Formula, list[ast.Formula]]] = {}
        self._made_nodes: list[ast.Formula] = []  # (formulas made by `_pushed`, whose ids the sets hold)
        # post-order over the skeleton: (op or None, children, results so far)
        stack: list[tuple[str, list, list, ast.Formula]] = []
        result: Result
        node = formula
        while True:
            shape = self.shape(node)
            if shape is None and id(node) in self._merged:
                try:  # a merged invariant, as one leaf while that stays small
                    result = self.leaf(node, merged=True)
                except TooLarge:
                    shape = "and", self._merged[id(node)][1]
            elif shape is None:
                result = self.leaf(node)
            if shape is not None:
                op, children = shape
                stack.append((op, children, [], node))
                node = children[0]
                continue
            while stack:
                op, children, done, _ = stack[-1]
                done.append(result)
                settled = self._settled(op, len(done) - 1, result)
                if settled is None and len(done) < len(children):
                    node = children[len(done)]
                    break
                stack.pop()
                result = settled if settled is not None else self.combine(op, done)
            else:
                return result

    def _settled(self, op: str, index: int, operand: Result) -> GuardedDFA | None:
        """The value of `op` once its operand number `index` is `operand`,
        when that decides it whatever the others are: an `&` with an empty
        operand, an `|` with a universal one, an implication from the
        empty language or to the universal one (a random Syft
        specification's assumptions are often unsatisfiable: its
        guarantees, a DFA of 132 states and 17,000 edges there, need not
        be built).  None otherwise."""
        if not isinstance(operand, GuardedDFA) or op not in ("and", "or", "implies"):
            return None
        if _is_empty(operand):
            if op == "and":
                return operand
            if op == "implies" and index == 0:
                return self._note(_started(operand.bdd), set())
        elif _is_universal(operand):
            if op == "or" or (op == "implies" and index == 1):
                return operand
        return None

    def finish(self, result: Result) -> Result:
        """The components left for the symbolic product, as one explicit
        product when they are few states together (FINAL_PRODUCT): the operands kept apart
        because they read disjoint atoms (a Syft specification's
        assumptions and guarantees: a few hundred states in all) cost less
        explicitly than a symbolic product and its minimization over pairs
        of states."""
        if isinstance(result, GuardedDFA):
            if self.final_explicit:
                return result
            result = Symbolic([result], ("c", result))  # (tests: every path taken apart)
        if len(result.components) < 2:
            return self._factored(result)
        bound = fanout = 1  # state tuples; successor tuples of one state, at most
        for c in result.components:
            bound *= c.num_states
            fanout *= max(c.degrees())
        if (self.final_explicit and bound < min(self.product_limit, FINAL_PRODUCT)
                and bound * fanout < FINAL_EDGES and bound < self._failed_bound):
            try:
                return explicit_product_many(result.components, result.acceptance, self.edge_limit,
                                             self._degree())
            except TooLarge:
                pass
        return self._factored(result)

    def _factored(self, result: Symbolic) -> Symbolic:
        """`result` with each large, dense explicit component (FACTOR_STATES,
        FACTOR_DEGREE) replaced by the operands it was made of, level by
        level: the symbolic product keeps their states in separate bits, and
        its bisimulation over pairs of states costs far less on them than on
        their explicit product (Random/Lydia case_05_50/01: 15 s for
        [48, 330] states, 0.5 s for [48, 18, 30]).  The language is the
        same: an explicit product accepts the non-empty traces its operands'
        acceptance, combined by its operator, accepts."""
        acceptance = result.acceptance
        while True:
            split = False

            def leaf(d):
                nonlocal split
                factors = self._factors.get(id(d))
                if (factors is None or d.num_states < self.factor_states
                        or d.num_edges < self.factor_degree * d.num_states):
                    return ("c", d)
                split = True
                return (factors[0], [("c", f) for f in factors[1]])

            acceptance = _fold(acceptance, leaf, lambda op, xs: (op, xs))
            if not split:
                break
        if acceptance is result.acceptance:
            return result
        found: dict[int, GuardedDFA] = {}
        _fold(acceptance, lambda d: found.setdefault(id(d), d), lambda op, xs: None)
        return Symbolic(list(found.values()), acceptance)

    def shape(self, node: ast.Formula) -> tuple[str, list[ast.Formula]] | None:
        """The skeleton operator at `node` and its operands (None: a leaf).

        `&` and `|` are flattened through the operators `expose` pulls up.
        Invariants `G f` of an `&` whose `f` looks at most a bounded number
        of steps ahead (no `U`, `R`, `W`, `F`, `G` inside) are progressed as
        one leaf `G(f1 & f2 & ...)`: their conjunction's states are what the
        next letters must satisfy, which progression keeps canonical, where
        a product of the parts would track each part's copy of it."""
        if self._kept(node) or id(node) in self._merged:
            return None
        shape = expose(node, self._kept)
        if shape is None or shape[0] not in ("and", "or"):
            return shape
        op = shape[0]
        unique: dict[ast.Formula, None] = {}  # the operands in order, each once
        todo = list(reversed(shape[1]))
        while todo:
            f = todo.pop()
            inner = None if self._kept(f) else expose(f, self._kept)
            if inner is not None and inner[0] == op:
                todo.extend(reversed(inner[1]))
            else:
                unique.setdefault(f, None)
        operands = list(unique)
        if op == "and":
            operands = self._pushed(self._group_invariants(operands))
        if len(operands) == 1:
            return self.shape(operands[0]) if id(operands[0]) not in self._propositional else None
        return op, operands

    def _kept(self, formula: ast.Formula) -> bool:
        """Whether `formula` is kept whole, a leaf of the skeleton: it has no
        temporal operator (one explicit DFA of a letter's condition)."""
        return id(formula) in self._propositional

    def _pushed(self, operands: list[ast.Formula]) -> list[ast.Formula]:
        """The operands of an `&`, its propositional ones `P` (the first
        letter's conditions) also conjoined to the consequent of the others'
        implications: `P & (A -> B)` is `P & (A -> (P & B))`, the language
        the same (P is read at the same position on both sides).  The
        product of A and P & B no longer pairs the states reached by first
        letters that P rules out (Nim nim_03_01: `Init & (G A -> (G B & U))`,
        whose product reached 194 pairs, 28 with Init in the consequent:
        0.084 -> 0.054 s).  Not into a consequent that reads none of P's
        atoms (`P & B` over disjoint atoms stays a symbolic product, and so
        would the implication), nor into bounded operands (the counters'
        `X[!] c -> init`: 37 s against 0.06 s), nor into the antecedent:
        `P & G A` joined the merge of G A's parts, whose pairing then took
        a product past the edge limit (nim_03_03: a timeout, 3.8 s
        without).  B is taken apart in turn."""
        first = [f for f in operands if self._kept(f) and not isinstance(f, ast.Const)]
        if not first or len(first) == len(operands):
            return operands
        condition = self._plain(_balanced(ast.And, first), propositional=True)
        reads = {x.key for x in ast.atoms(condition)}
        result = []
        for f in operands:
            inner = None if id(f) in self._bounded else expose(f, self._kept)
            if inner is None or inner[0] != "implies" or not reads & {x.key for x in ast.atoms(inner[1][1])}:
                result.append(f)
                continue
            left, right = inner[1]
            result.append(ast.Implies(left, self._plain(ast.And(condition, right), propositional=self._kept(right))))
        return result

    def _plain(self, node: ast.Formula, propositional: bool) -> ast.Formula:
        """`node`, made here, kept alive (the sets hold ids) and, when
        `propositional`, noted as propositional and bounded."""
        self._made_nodes.append(node)
        if propositional:
            self._propositional.add(id(node))
            self._bounded.add(id(node))
        return node

    def _group_invariants(self, operands: list[ast.Formula]) -> list[ast.Formula]:
        """The operands of an `&` with its bounded-lookahead invariants merged:
        `P G f` for a prefix `P` of `X` / `WX` (often none; the counters'
        guarantees are `WX G(...)`), grouped by prefix and then by the atoms
        they share, each group one operand `P G(f1 & f2 & ...)`
        (`WX G f & WX G g = WX G(f & g)`)."""
        by_prefix: dict[tuple[type, ...], list[ast.Formula]] = {}
        rest = []
        for f in operands:
            prefix, inner = [], f
            while isinstance(inner, (ast.Next, ast.WeakNext)):
                prefix.append(type(inner))
                inner = inner.arg
            if isinstance(inner, ast.Always) and id(inner.arg) in self._bounded:
                by_prefix.setdefault(tuple(prefix), []).append(inner.arg)
            else:
                rest.append(f)
        if not any(len(bodies) > 1 for bodies in by_prefix.values()):
            return operands

        def prefixed(prefix, f):
            for kind in reversed(prefix):
                f = kind(f)
            return f

        for kinds, bodies in by_prefix.items():
            for group in _connected(bodies):
                if len(group) == 1:
                    rest.append(prefixed(kinds, ast.Always(group[0])))
                    continue
                merged = prefixed(kinds, ast.Always(_balanced(ast.And, group)))
                rest.append(merged)
                # a leaf (kept alive: ids stay unique), or its parts if too large
                self._merged[id(merged)] = (merged, [prefixed(kinds, ast.Always(f)) for f in group])
        return rest

    def leaf(self, formula: ast.Formula, merged: bool = False) -> GuardedDFA:
        """The minimal DFA of a leaf; `TooLarge` for a merged invariant past
        its limits (MERGED_EDGES and the others)."""
        dfa = self._leaves.get(formula)
        if dfa is None:
            normal = nnf(formula)
            shape = invariant_shape(normal)
            if shape is not None:  # one-step invariants: states read off the letter
                edges = min(self.merged_edges * 50, MERGED_INVARIANT_EDGES) if merged else None
                dfa = minimize(self.invariants.dfa(*shape, edges, MERGED_DEGREE if merged else None))
            else:
                dfa = minimize(self.progression.dfa(normal, self.merged_edges if merged else None))
            self._leaves[formula] = dfa
            self._note(dfa, {a.key for a in ast.atoms(formula)})
        return dfa

    def combine(self, op: str, operands: list[Result]) -> Result:
        if op == "not":
            (arg,) = operands
            if isinstance(arg, GuardedDFA):
                return self._made(complement(arg), "not", [arg])
            return Symbolic(arg.components, ("not", [arg.acceptance]))
        explicit = [x for x in operands if isinstance(x, GuardedDFA)]
        if op in ("and", "or"):
            explicit = self.merge(list({id(d): d for d in explicit}.values()), op)
            symbolic = [x for x in operands if isinstance(x, Symbolic)]
            if not symbolic and len(explicit) == 1:
                return explicit[0]
        else:  # implies, equiv: two operands, in order
            left, right = operands
            if isinstance(left, GuardedDFA) and isinstance(right, GuardedDFA) and self._small(left, right):
                try:
                    return self._explicit(left, right, op)
                except TooLarge:
                    pass
            explicit, symbolic = [], []
        components: list[GuardedDFA] = []
        parts = []
        if op in ("and", "or"):
            for d in explicit:
                components.append(d)
                parts.append(("c", d))
            for s in symbolic:
                components += s.components
                parts.append(s.acceptance)
        else:
            for x in operands:
                if isinstance(x, GuardedDFA):
                    components.append(x)
                    parts.append(("c", x))
                else:
                    components += x.components
                    parts.append(x.acceptance)
        return Symbolic(list({id(c): c for c in components}.values()), (op, parts))

    def merge(self, dfas: list[GuardedDFA], op: str) -> list[GuardedDFA]:
        """Explicit products of the operands of an n-ary `&` / `|`, the pair
        with the fewest product states first (Lisa's order), among pairs
        that read a common atom: operands over disjoint atoms gain nothing
        from an explicit product (their symbolic product keeps each part's
        bits apart, where an explicit one numbers the pairs densely)."""
        failed: set[tuple[int, int]] = set()
        kept_apart = 0  # disjoint pairs tried that did not shrink
        while len(dfas) > 1:
            best = None
            for i, a in enumerate(dfas):
                for j in range(i + 1, len(dfas)):
                    b = dfas[j]
                    key = (id(a), id(b))
                    if key in failed or not self._small(a, b) or \
                            not self._related(a, b, tried=kept_apart < DISJOINT_TRIES):
                        continue
                    if best is None or a.num_states * b.num_states < best[0]:
                        best = (a.num_states * b.num_states, i, j)
            if best is None:
                break
            _, i, j = best
            try:
                merged = self._explicit(dfas[i], dfas[j], op)
            except TooLarge:
                failed.add((id(dfas[i]), id(dfas[j])))
                continue
            if not self._related(dfas[i], dfas[j], tried=False) and \
                    merged.num_states * SHRINK > dfas[i].num_states * dfas[j].num_states:
                failed.add((id(dfas[i]), id(dfas[j])))  # kept apart: it did not shrink
                kept_apart += 1
                continue
            dfas = [d for k, d in enumerate(dfas) if k not in (i, j)] + [merged]
        return dfas

    def _related(self, a: GuardedDFA, b: GuardedDFA, tried: bool = True) -> bool:
        """Whether an explicit product of `a` and `b` may pay: they read a
        common atom, or one of them reads none (a constant language, or one
        of trace lengths: the product is no larger than the other).
        (Conditions on the first letters over disjoint atoms are not joined
        first: a counter's start reaches thousands of states, and each
        state of the joined condition's prefix would copy their edges.)
        With `tried`, also two small operands over disjoint atoms (their
        state counts multiply to at most DISJOINT_PAIRS), whose product
        `merge` keeps only when it shrinks: `G(r1 -> F !r1) & G(r2 -> F !r2)
        & ...` says the last letter has no r_i, 2 states, where a symbolic
        product of the parts has 2^n codes to minimize (assume-guarantee
        formulas: 8 pairs, 6.3 s that way)."""
        reads_a, reads_b = self._reads(a), self._reads(b)
        if self.independent or not reads_a or not reads_b or bool(reads_a & reads_b):
            return True
        return tried and a.num_states * b.num_states <= DISJOINT_PAIRS

    def _is_bounded(self, dfa: GuardedDFA) -> bool:
        """Whether `dfa`'s states other than its sinks form no cycle."""
        found = self._bounded_dfas.get(id(dfa))
        if found is None:
            found = self._bounded_dfas[id(dfa)] = bounded_order(dfa) is not None
        return found

    def _reads(self, dfa: GuardedDFA) -> set[str]:
        """The atoms `dfa` may read: a superset of its guards' support, kept
        for each DFA the composer makes (products read what their operands
        read), so that no guard is looked at."""
        found = self._support.get(id(dfa))
        if found is None:  # (every DFA is noted when made; this is a fallback)
            found = set()
            for out in dfa.edges:
                for guard in out.values():
                    found |= dfa.bdd.support(guard)
            self._note(dfa, found)
        return found

    def _made(self, dfa: GuardedDFA, op: str, operands: list[GuardedDFA]) -> GuardedDFA:
        """Notes that `dfa` is `op` of `operands` (see `_factored`)."""
        reads: set[str] = set()
        for d in operands:
            reads |= self._reads(d)
        self._note(dfa, reads)
        self._factors.setdefault(id(dfa), (op, operands))
        return dfa

    def _note(self, dfa: GuardedDFA, reads: set[str]) -> GuardedDFA:
        if id(dfa) not in self._support:
            self._support[id(dfa)] = reads
            self._alive.append(dfa)
        return dfa

    def _small(self, a: GuardedDFA, b: GuardedDFA) -> bool:
        """Whether an explicit product of `a` and `b` is worth a try: both
        operands and the pairs of their states below the limits, or one of
        them looks a bounded number of letters ahead (`prefix_product`:
        the pairs after its few letters are the other's states)."""
        if a.num_states >= self.single or b.num_states >= self.single:
            return False
        small = min(a, b, key=lambda d: d.num_states)
        if small.num_states <= PREFIX_STATES and self._is_bounded(small):
            return True
        bound = a.num_states * b.num_states
        return bound < self.product_limit and bound < self._failed_bound

    def _explicit(self, a: GuardedDFA, b: GuardedDFA, op: str) -> GuardedDFA:
        """`explicit_product`; once it fails (`TooLarge`), products with as
        many state pairs are not tried again (each attempt costs up to the
        edge limit's worth of work)."""
        limit = self.edge_limit
        if limit is not None:  # a product with a small operand may grow with the large one
            sizes = [d.num_edges for d in (a, b)]
            limit = max(limit, GROWTH * max(sizes))
            if sizes[0] * sizes[1] <= SPARSE_DEGREE * a.num_states * b.num_states:
                limit = max(limit, SPARSE_EDGES)
        try:
            return self._made(explicit_product(a, b, op, limit, self._degree(), self.moves_pairs), op, [a, b])
        except TooDense:
            raise
        except TooLarge:
            self._failed_bound = min(self._failed_bound, a.num_states * b.num_states)
            raise

    def _degree(self) -> int | None:
        """EXPLICIT_DEGREE, unless the limits make every product explicit."""
        return None if self.edge_limit is None else EXPLICIT_DEGREE


def _plain_nodes(formula: ast.Formula) -> tuple[set[int], set[int]]:
    """ids of the subformulas (of this tree) without temporal operators, and
    of those whose only temporal operators are `X`, `WX` and `last` (they
    look a bounded number of steps ahead)."""
    unbounded = (ast.Eventually, ast.Always, ast.Until, ast.Release, ast.WeakUntil)
    temporal = (ast.Next, ast.WeakNext, ast.Last)
    propositional: set[int] = set()
    bounded: set[int] = set()
    stack = [(formula, False)]
    while stack:
        node, visited = stack.pop()
        children = ((node.arg,) if isinstance(node, ast.UNARY)
                    else (node.left, node.right) if isinstance(node, ast.BINARY) else ())
        if not visited and children:
            stack.append((node, True))
            stack.extend((c, False) for c in children)
            continue
        if isinstance(node, unbounded) or not all(id(c) in bounded for c in children):
            continue
        bounded.add(id(node))
        if not isinstance(node, temporal) and all(id(c) in propositional for c in children):
            propositional.add(id(node))
    return propositional, bounded


def _connected(formulas: list[ast.Formula]) -> list[list[ast.Formula]]:
    """`formulas` grouped by the atoms they share (connected components)."""
    parent = list(range(len(formulas)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    owner: dict[ast.Atom, int] = {}
    for i, f in enumerate(formulas):
        for atom in ast.atoms(f):
            j = owner.setdefault(atom, i)
            parent[find(i)] = find(j)
    groups: dict[int, list[ast.Formula]] = {}
    for i, f in enumerate(formulas):
        groups.setdefault(find(i), []).append(f)
    return list(groups.values())


def _balanced(op, items: list[ast.Formula]) -> ast.Formula:
    """`items` joined by the binary `op` in a balanced tree (no recursion)."""
    while len(items) > 1:
        items = [op(items[i], items[i + 1]) if i + 1 < len(items) else items[i]
                 for i in range(0, len(items), 2)]
    return items[0]


# ------------------------------------------------------------ explicit steps


def explicit_product(a: GuardedDFA, b: GuardedDFA, op: str, max_edges: int | None = None,
                     max_degree: int | None = None, moves_pairs: float = MOVES_PAIRS) -> GuardedDFA:
    """The minimal DFA of the product of `a` and `b` accepting by `op`;
    `TooLarge` once it has more than `max_edges` edges (when given), and
    `TooDense` once its states have more than `max_degree` successors on
    average (plus a slack of 2,000 edges) over its states after the first
    DENSE_AFTER (the first states of a counter reach thousands of others),
    checked from the 2 x DENSE_AFTER-th state on.  Made from the operands'
    moves (moves.py), with no limit on successors per state, when their
    successors per state multiply to more than `moves_pairs` on average,
    when one given by its moves only has more than MOVES_DEGREE successors
    per state, or when the product from their edges proves dense."""
    for big, small in ((a, b), (b, a)):
        if op in ("and", "or") and small.num_states <= min(PREFIX_STATES, big.num_states - 1) \
                and not big.has_edges():
            done = prefix_product_moves(big, small, op)
            if done is not None:
                return done
    if a.num_edges * b.num_edges > moves_pairs * a.num_states * b.num_states or \
            any(not d.has_edges() and d.num_edges > MOVES_DEGREE * d.num_states for d in (a, b)):
        return _moves_product(a, b, op, max_edges)
    for big, small in ((a, b), (b, a)):  # (`&` and `|` are symmetric)
        if op in ("and", "or") and small.num_states <= PREFIX_STATES < big.num_states:
            done = prefix_product(big, small, op, max_edges)
            if done is not None:
                return done
    bdd, accept = a.bdd, _OPS[op]
    false = bdd.false
    start = (a.initial, b.initial)
    index = {start: 0}
    order = [start]
    accepting: list[bool] = []
    edges: list[dict[int, Function]] = []
    count = early = 0
    for s, t in order:
        accepting.append(accept([a.accepting[s], b.accepting[t]]))
        out: dict[int, Function] = {}
        out_b = b.edges[t].items()
        for s2, g1 in a.edges[s].items():
            for t2, g2 in out_b:
                guard = g1 & g2
                if guard == false:
                    continue
                pair = (s2, t2)
                if pair not in index:
                    index[pair] = len(order)
                    order.append(pair)
                out[index[pair]] = guard
        edges.append(out)
        count += len(out)
        try:
            early = _check_growth(len(edges), count, early, max_edges, max_degree)
        except TooDense:  # each edge costs a guard: the moves cost per state
            return _moves_product(a, b, op, max_edges)
    return minimize(_reject_at_start(GuardedDFA(bdd, 0, accepting, edges)))


def _moves_product(a: GuardedDFA, b: GuardedDFA, op: str, max_edges: int | None) -> GuardedDFA:
    """`explicit_product` on the operands' moves (moves.product); no limit
    on successors per state (a state's moves are one BDD however many)."""

    def grown(states: int, edges: int) -> None:
        _check_growth(states, edges, 0, max_edges, None)

    bdd = a.bdd
    try:
        made = moves_.product(bdd, a.moves, a.initial, a.accepting, b.moves, b.initial, b.accepting,
                              _OPS[op], grown)
    except moves_.TooManyStates as error:
        raise TooLarge(str(error)) from None
    if made.accepting[0]:  # (an implication, a disjunction with a negation)
        start = moves_.cube(bdd, moves_.bits(bdd, "z", made.width), 0)
        if any(succ & start != bdd.false for succ in made.after):  # entered again: a fresh start
            return minimize(_reject_at_start(GuardedDFA(bdd, 0, made.accepting, moves=made.narrowed(bdd),
                                                        degrees=made.degrees)))
        made.accepting[0] = False
    found = moves_.minimize(bdd, made)
    if found is None:
        return GuardedDFA(bdd, 0, made.accepting, moves=made.narrowed(bdd), degrees=made.degrees)
    return GuardedDFA(bdd, 0, found.accepting, moves=found.moves, degrees=found.degrees)


def _sinks(dfa: GuardedDFA) -> tuple[int | None, int | None]:
    """The states of `dfa` whose only edge is a loop on every letter:
    (accepting, rejecting); None where there is none."""
    true = dfa.bdd.true
    found: list[int | None] = [None, None]
    if not dfa.has_edges():
        names = moves_.bits(dfa.bdd, "z", moves_.width(dfa.num_states))
        for state, t in enumerate(dfa.moves):
            if t == moves_.cube(dfa.bdd, names, state):
                found[0 if dfa.accepting[state] else 1] = state
        return found[0], found[1]
    for state, out in enumerate(dfa.edges):
        if len(out) == 1 and out.get(state) == true:
            found[0 if dfa.accepting[state] else 1] = state
    return found[0], found[1]


def bounded_order(dfa: GuardedDFA) -> list[int] | None:
    """The states of `dfa` other than its sinks (`_sinks`), each after its
    successors (a reverse topological order), or None when they form a
    cycle (the DFA does not look a bounded number of letters ahead)."""
    sinks = {s for s in _sinks(dfa) if s is not None}
    inside = [s for s in range(dfa.num_states) if s not in sinks]
    after = dfa.successor_lists()
    pending = {s: sum(1 for t in after[s] if t not in sinks) for s in inside}
    preds: dict[int, list[int]] = {s: [] for s in inside}
    for s in inside:
        for t in after[s]:
            if t not in sinks:
                preds[t].append(s)
    order = [s for s in inside if pending[s] == 0]
    for s in order:  # grows while walked
        for p in preds[s]:
            pending[p] -= 1
            if pending[p] == 0:
                order.append(p)
    return order if len(order) == len(inside) else None


def prefix_product(big: GuardedDFA, small: GuardedDFA, op: str,
                   max_edges: int | None = None) -> GuardedDFA | None:
    """The minimal DFA of `big` op `small` (op `and` / `or`) when `small`
    looks a bounded number of letters ahead (its states other than its
    sinks form no cycle: a condition on the first letters, such as a
    counter's initial value) and `big` is minimal; None when `small` is not
    of that shape.

    Once `small` is in a sink, the pair's language is `big`'s state's
    (`and` with the accepting sink, `or` with the rejecting one) or a
    constant (the empty or the universal language), so only the pairs
    before that are new: a prefix of at most `small`'s depth in letters.
    They are made from the last letters to the first, each pair's
    successors already canonical, and a pair is a state already made
    exactly when it agrees with it on acceptance and on the letters leading
    to each successor: `big`'s states are pairwise inequivalent (it is
    minimal), so two states with canonical successors are equivalent iff
    those agree.  Cost: one pass over `big`'s edges (the table of those
    agreements) where the product and its partition refinement pass over
    them several times with a BDD conjunction per edge (Double-Counter
    counters_06: 13 such products into a DFA of 16,263 states)."""
    order = bounded_order(small)
    if order is None:
        return None
    accept_sink, reject_sink = _sinks(small)
    sinks = {s for s in (accept_sink, reject_sink) if s is not None}
    bdd = big.bdd
    true, false = bdd.true, bdd.false
    n = big.num_states
    accepting = list(big.accepting)
    edges: list[dict[int, Function]] = list(big.edges)
    big_accept, big_reject = _sinks(big)
    made: dict[tuple, int] = {}  # (accepting, edges) of a state added -> the state
    preds: list[list[int]] | None = None  # of `big`'s states, made when first needed

    def constant(value: bool) -> int:
        nonlocal big_accept, big_reject
        found = big_accept if value else big_reject
        if found is None:
            found = len(accepting)
            accepting.append(value)
            edges.append({found: true})
            made[(value, frozenset(edges[found].items()))] = found
            if value:
                big_accept = found
            else:
                big_reject = found
        return found

    # the language of (q, sink): q's own, or a constant
    keeps = accept_sink if op == "and" else reject_sink
    other = reject_sink if op == "and" else accept_sink
    combine = all if op == "and" else any

    def existing(q: int, value: bool, out: dict[int, Function]) -> int | None:
        """A state of `big` (or a sink added) with acceptance `value` and
        edges `out`: one of the states with an edge into `out`'s first target."""
        nonlocal preds
        if q < n and accepting[q] == value and edges[q] == out:
            return q  # (most often: the condition met, the state goes on as `big`'s)
        first = next(iter(out))
        if first >= n:  # a state added: only those are its predecessors
            return None
        if preds is None:
            preds = [[] for _ in range(n)]
            for state in range(n):
                for succ in big.edges[state]:
                    preds[succ].append(state)
        for state in preds[first]:
            if accepting[state] == value and edges[state] == out:
                return state
        return None

    start = (big.initial, small.initial)
    if small.initial in sinks:
        initial = big.initial if small.initial == keeps else constant(op == "or")
        return _renumbered(bdd, initial, accepting, edges)
    # the pairs reachable from the start before `small` is in a sink, with
    # their edges: (successor pair, guard)
    steps: dict[tuple[int, int], list[tuple[int, int, Function]]] = {}
    todo = [start]
    count = 0
    while todo:
        q, s = pair = todo.pop()
        if pair in steps:
            continue
        out_pair = steps[pair] = []
        for s2, g2 in small.edges[s].items():
            for q2, g1 in big.edges[q].items():
                guard = g1 & g2
                if guard == false:
                    continue
                out_pair.append((q2, s2, guard))
                if s2 not in sinks and (q2, s2) not in steps:
                    todo.append((q2, s2))
        count += len(out_pair)
        if max_edges is not None and count > max_edges:
            raise TooLarge(f"more than {max_edges} edges")
    rank = {s: i for i, s in enumerate(order)}
    canonical: dict[tuple[int, int], int] = {}
    for q, s in sorted(steps, key=lambda pair: rank[pair[1]]):  # successors first
        out: dict[int, Function] = {}
        for q2, s2, guard in steps[(q, s)]:
            if s2 == keeps:
                target = q2
            elif s2 == other:
                target = constant(op == "or")
            else:
                target = canonical[(q2, s2)]
            out[target] = out[target] | guard if target in out else guard
        value = combine((big.accepting[q], small.accepting[s]))
        key = (value, frozenset(out.items()))
        state = made.get(key)
        if state is None:
            state = existing(q, value, out)
        if state is None:
            state = made[key] = len(accepting)
            accepting.append(value)
            edges.append(out)
        canonical[(q, s)] = state
    return _renumbered(bdd, canonical[start], accepting, edges)


def prefix_product_moves(big: GuardedDFA, small: GuardedDFA, op: str) -> GuardedDFA | None:
    """`prefix_product` for a `big` given by its moves: the same pairs, made
    from the last letters to the first, a pair being a state already made
    exactly when it agrees with it on acceptance and moves (its successors
    being canonical, the moves BDD is a canonical key: no guard is split
    off).  A pair whose `small` state is the sink that keeps `big`'s
    language moves by `big`'s moves; one into the other sink, to the
    constant.  Then the states reachable from the start, renumbered into
    the places of the others (one relational product per state)."""
    order = bounded_order(small)
    if order is None:
        return None
    accept_sink, reject_sink = _sinks(small)
    sinks = {s for s in (accept_sink, reject_sink) if s is not None}
    if small.initial in sinks:
        return None  # (an operand that decides the product: `Composer._settled`'s)
    keeps = accept_sink if op == "and" else reject_sink
    combine = all if op == "and" else any
    bdd = big.bdd
    false = bdd.false
    n, T = big.num_states, big.moves
    w = moves_.width(n)
    atoms = moves_.atom_vars(bdd)
    narrow = moves_.bits(bdd, "z", w)
    start = (big.initial, small.initial)
    steps: dict[tuple[int, int], list[tuple[int, Function, Function, list[int]]]] = {}
    todo = [start]
    while todo:
        q, s = pair = todo.pop()
        if pair in steps:
            continue
        out = steps[pair] = []
        for s2, g2 in small.edges[s].items():
            part = T[q] & g2
            if part == false:
                continue
            after = [] if s2 in sinks else moves_.numbers(bdd, exists(bdd, part, atoms), narrow)
            out.append((s2, g2, part, after))
            todo.extend((q2, s2) for q2 in after if (q2, s2) not in steps)
    # numbers: `big`'s states, the constant when `big` has no such sink, the pairs made
    value = op == "or"  # the constant language: universal for `or`, empty for `and`
    constant = _sinks(big)[0 if value else 1]
    width = moves_.width(n + 1 + len(steps))
    zs, cs = moves_.bits(bdd, "z", width), moves_.bits(bdd, "c", width)
    zero = bdd.true  # the bits `big`'s moves do not write
    for name in zs[w:]:
        zero &= ~bdd.var(name)
    accepting = list(big.accepting)
    moves = list(T)
    wide: dict[int, Function] = {}  # state -> its moves in `width` bits (the states made)
    known = {(big.accepting[q], T[q]): q for q in range(n)}  # pairwise inequivalent: `big` is minimal
    made: dict[tuple[bool, Function], int] = {}
    if constant is None:
        constant = n
        accepting.append(value)
        wide[n] = moves_.cube(bdd, zs, n)
        moves.append(wide[n])
        made[(value, wide[n])] = n
    rank = {s: i for i, s in enumerate(order)}
    canonical: dict[tuple[int, int], int] = {}
    rename = dict(zip(cs, zs))
    for q, s in sorted(steps, key=lambda pair: rank[pair[1]]):  # successors first
        t = false
        for s2, g2, part, after in steps[(q, s)]:
            if s2 == keeps:
                t |= part & zero
            elif s2 in sinks:
                t |= g2 & moves_.cube(bdd, zs, constant)
            else:
                table = false
                for q2 in after:
                    table |= moves_.cube(bdd, narrow, q2) & moves_.cube(bdd, cs, canonical[(q2, s2)])
                t |= swap(bdd, and_exists(bdd, part, table, narrow), rename)
        accept = combine((big.accepting[q], small.accepting[s]))
        state = made.get((accept, t))
        if state is None and width > w:
            own = exists(bdd, t, zs[w:])
            if own & zero == t:  # its successors are numbered in `big`'s width
                state = known.get((accept, own))
        elif state is None:
            state = known.get((accept, t))
        if state is None:
            state = made[(accept, t)] = len(moves)
            accepting.append(accept)
            moves.append(t)
            wide[state] = t
        canonical[(q, s)] = state
    return _renumbered_moves(big, canonical[start], accepting, moves, wide, width)


def _renumbered_moves(big: GuardedDFA, initial: int, accepting: list[bool], moves: list[Function],
                      wide: dict[int, Function], width: int) -> GuardedDFA:
    """The states reachable from `initial` of `big`'s states and the ones
    made after them (their moves in `width` bits, `wide`), numbered in
    breadth-first order from `initial` and written in their own width."""
    bdd = big.bdd
    atoms = moves_.atom_vars(bdd)
    zs = moves_.bits(bdd, "z", width)
    narrow = moves_.bits(bdd, "z", moves_.width(big.num_states))
    order, seen = [initial], {initial}
    degrees = []
    for state in order:  # grows while walked
        after = moves_.numbers(bdd, exists(bdd, wide[state], atoms), zs) if state in wide else \
            moves_.numbers(bdd, exists(bdd, moves[state], atoms), narrow)
        degrees.append(len(after))
        for succ in after:
            if succ not in seen:
                seen.add(succ)
                order.append(succ)
    fw = moves_.width(len(order))
    cs = moves_.bits(bdd, "c", fw)
    table = bdd.false
    for new, old in enumerate(order):
        table |= moves_.cube(bdd, zs, old) & moves_.cube(bdd, cs, new)
    zero = bdd.true
    for name in zs[moves_.width(big.num_states):]:
        zero &= ~bdd.var(name)
    rename = dict(zip(cs, moves_.bits(bdd, "z", fw)))
    result = [swap(bdd, and_exists(bdd, wide.get(old, moves[old] & zero), table, zs), rename)
              for old in order]
    return GuardedDFA(bdd, 0, [accepting[old] for old in order], moves=result, degrees=degrees)


def _renumbered(bdd: BDD, initial: int, accepting: list[bool],
                edges: list[dict[int, Function]]) -> GuardedDFA:
    """The states reachable from `initial`, numbered as they are but for
    the few past the end that fill the places of unreachable ones."""
    accepting_all, edges_all = accepting, edges
    seen = [False] * len(edges)
    seen[initial] = True
    order = [initial]
    for state in order:
        for succ in edges[state]:
            if not seen[succ]:
                seen[succ] = True
                order.append(succ)
    if len(order) == len(edges):
        return GuardedDFA(bdd, initial, accepting, edges)
    # the last states move into the places of the unreachable ones (a prefix
    # product leaves a few: the old start), so only the edges into those few
    # change; the rest keep their numbers and their dicts
    size = len(order)
    holes = [s for s in range(size) if not seen[s]]
    movers = [s for s in range(size, len(edges)) if seen[s]]
    moved = dict(zip(movers, holes))
    accepting, edges = accepting[:size], edges[:size]
    for old, new in moved.items():
        accepting[new] = accepting_all[old]
        edges[new] = edges_all[old]
    for state, out in enumerate(edges):
        if any(t in moved for t in out):
            edges[state] = {moved.get(t, t): g for t, g in out.items()}
    return GuardedDFA(bdd, moved.get(initial, initial), accepting, edges)


def _check_growth(states: int, count: int, early: int, max_edges: int | None,
                  max_degree: int | None) -> int:
    """After a product state's edges are added (`states` states, `count`
    edges so far): `TooLarge` past `max_edges`, `TooDense` when the states
    after the first DENSE_AFTER average more than `max_degree` successors.
    Returns `early`, the edges of the first DENSE_AFTER states (the first
    states may reach thousands: a counter's start)."""
    grew(states)
    if max_edges is not None and count > max_edges:
        raise TooLarge(f"more than {max_edges} edges")
    if states == DENSE_AFTER:
        early = count
    if max_degree is not None and states >= 2 * DENSE_AFTER and \
            count - early > max_degree * (states - DENSE_AFTER) + 2000:
        raise TooDense(f"more than {max_degree} successors per state")
    return early


def explicit_product_many(components: list[GuardedDFA], acceptance: tuple,
                          max_edges: int | None = None, max_degree: int | None = None) -> GuardedDFA:
    """The minimal DFA of the product of `components` accepting by the
    Boolean combination `acceptance` of theirs (`Symbolic.acceptance`);
    `TooLarge` / `TooDense` as for `explicit_product`.  A
    letter's successor tuple is found component by component, dropping a
    partial tuple as soon as its guard is empty."""
    bdd = components[0].bdd
    false = bdd.false
    position = {id(c): i for i, c in enumerate(components)}
    start = tuple(c.initial for c in components)
    index = {start: 0}
    order = [start]
    accepting: list[bool] = []
    edges: list[dict[int, Function]] = []
    count = early = 0
    for states in order:
        accepting.append(_fold(acceptance, lambda d: d.accepting[states[position[id(d)]]],
                               lambda op, xs: _OPS[op](xs)))
        partial: list[tuple[Function, tuple[int, ...]]] = [(bdd.true, ())]
        for c, s in zip(components, states):
            out_c = c.edges[s].items()
            partial = [(both, succs + (succ,)) for guard, succs in partial for succ, g in out_c
                       if (both := guard & g) != false]
        out: dict[int, Function] = {}
        for guard, succs in partial:
            target = index.get(succs)
            if target is None:
                target = index[succs] = len(order)
                order.append(succs)
            out[target] = guard
        edges.append(out)
        count += len(out)
        early = _check_growth(len(edges), count, early, max_edges, max_degree)
    return minimize(_reject_at_start(GuardedDFA(bdd, 0, accepting, edges)))


def complement(a: GuardedDFA) -> GuardedDFA:
    """The minimal DFA of the non-empty traces `a` rejects."""
    flipped = GuardedDFA(a.bdd, a.initial, [not x for x in a.accepting],
                         a.edges if a.has_edges() else None, moves=None if a.has_edges() else a.moves)
    return minimize(_reject_at_start(flipped))


def _reject_at_start(dfa: GuardedDFA) -> GuardedDFA:
    """The same language without the empty trace: an accepting initial state
    becomes rejecting, or, when a non-empty trace comes back to it, a fresh
    rejecting initial state takes its outgoing edges."""
    start = dfa.initial
    if not dfa.accepting[start]:
        return dfa
    if not dfa.has_edges():
        return _reject_at_start_moves(dfa)
    if not any(start in out for out in dfa.edges):
        accepting = list(dfa.accepting)
        accepting[start] = False
        return GuardedDFA(dfa.bdd, start, accepting, dfa.edges)
    return GuardedDFA(dfa.bdd, len(dfa.accepting), dfa.accepting + [False],
                      dfa.edges + [dict(dfa.edges[start])])


def _reject_at_start_moves(dfa: GuardedDFA) -> GuardedDFA:
    """`_reject_at_start` of a DFA given by its moves (no edges made)."""
    bdd, start, moves = dfa.bdd, dfa.initial, dfa.moves
    accepting = list(dfa.accepting)
    entered = moves_.successors(bdd, moves)
    names = moves_.bits(bdd, "z", moves_.width(len(moves)))
    if all(succ & moves_.cube(bdd, names, start) == bdd.false for succ in entered):
        accepting[start] = False
        return GuardedDFA(bdd, start, accepting, moves=moves)
    moves = list(moves) + [moves[start]]
    if moves_.width(len(moves)) > len(names):  # numbers one bit wider: its value is 0 in every move
        zero = ~bdd.var(moves_.bits(bdd, "z", len(names) + 1)[-1])
        moves = [t & zero for t in moves]
    return GuardedDFA(bdd, len(moves) - 1, accepting + [False], moves=moves)


def _is_empty(dfa: GuardedDFA) -> bool:
    """Whether the minimal `dfa` accepts no trace (one rejecting state)."""
    return dfa.num_states == 1 and not dfa.accepting[0]


def _is_universal(dfa: GuardedDFA) -> bool:
    """Whether the minimal `dfa` accepts every non-empty trace (`_started`)."""
    if dfa.num_states != 2:
        return False
    start, other = dfa.initial, 1 - dfa.initial
    true = dfa.bdd.true
    return (not dfa.accepting[start] and dfa.accepting[other]
            and dfa.edges[start] == {other: true} and dfa.edges[other] == {other: true})


def _started(bdd: BDD) -> GuardedDFA:
    """Two states: the start, and 'at least one letter read' (accepting)."""
    return GuardedDFA(bdd, 0, [False, True], [{1: bdd.true}, {1: bdd.true}])


# ----------------------------------------------------------- symbolic steps


def _holds_initially(acceptance: tuple) -> bool:
    """Whether the combination accepts when every component is at its
    (rejecting) initial state."""
    return _fold(acceptance, lambda d: False, lambda op, xs: _OPS[op](xs))


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
    return _fold(acceptance, lambda d: accs[index[id(d)]], apply)


def _fold(expr: tuple, leaf, apply):
    """Post-order evaluation of an acceptance expression, without recursion."""
    stack = [(expr, False)]
    values: list = []
    while stack:
        node, visited = stack.pop()
        if node[0] == "c":
            values.append(leaf(node[1]))
        elif not visited:
            stack.append((node, True))
            stack.extend((child, False) for child in reversed(node[1]))
        else:
            n = len(node[1])
            args = values[len(values) - n:]
            del values[len(values) - n:]
            values.append(apply(node[0], args))
    return values[0]
