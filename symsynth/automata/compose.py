"""LTLf -> minimal symbolic DFA, compositionally over the Boolean structure
(the explicit steps are `products.py` and `prefix.py`, their limits `tuning.py`).

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
   need not be minimal (compiler.py, which also chooses this construction
   or another for the whole formula).

Traces are non-empty: every explicit DFA here has a non-accepting initial
state, and a combination that would accept at the start (the complement, an
implication, an equivalence) gets a fresh initial state (explicitly) or a
"started" component (symbolically).  Every pass is iterative or bounded by
the parser's nesting limit.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from symsynth.automata.invariant import Invariants, invariant_shape
from symsynth.automata.normal import expose, nnf
from symsynth.automata.prefix import bounded_order
from symsynth.automata.products import (complement, explicit_product, explicit_product_many, fold, is_empty,
                                        is_universal, started)
from symsynth.automata.progression import GuardedDFA, Progression, TooDense, TooLarge, minimize
from symsynth.automata.tuning import (EXPLICIT_SINGLE, EXPLICIT_PRODUCT, EXPLICIT_EDGES, EXPLICIT_DEGREE,
                                      MOVES_PAIRS, PREFIX_STATES, DISJOINT_PAIRS, DISJOINT_TRIES, GROWTH,
                                      SPARSE_DEGREE, SPARSE_EDGES, FINAL_PRODUCT, FINAL_EDGES, FACTOR_STATES,
                                      FACTOR_DEGREE, MERGED_EDGES, MERGED_INVARIANT_EDGES)
from symsynth.logic import ast



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
        self._parts: dict[int, list[ast.Formula]] = {}  # merged invariant leaf -> its parts' formulas

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
        if is_empty(operand):
            if op == "and":
                return operand
            if op == "implies" and index == 0:
                return self._note(started(operand.bdd), set())
        elif is_universal(operand):
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
                if d.num_states < self.factor_states or d.num_edges < self.factor_degree * d.num_states:
                    return ("c", d)
                factors = self._factors.get(id(d))
                if factors is None and id(d) in self._parts:
                    factors = self._factors[id(d)] = ("and", self.merge([self.leaf(f) for f in self._parts[id(d)]], "and"))
                if factors is None:
                    return ("c", d)
                split = True
                return (factors[0], [("c", f) for f in factors[1]])

            acceptance = fold(acceptance, leaf, lambda op, xs: (op, xs))
            if not split:
                break
        if acceptance is result.acceptance:
            return result
        found: dict[int, GuardedDFA] = {}
        fold(acceptance, lambda d: found.setdefault(id(d), d), lambda op, xs: None)
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
        if len(operands) == 1 and id(operands[0]) in self._merged:
            return op, operands  # (a node of its own: built as a merged invariant, not progressed whole)
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
                edges = min(self.merged_edges * 1000, MERGED_INVARIANT_EDGES) if merged else None
                dfa = minimize(self.invariants.dfa(*shape, edges))
            else:
                dfa = minimize(self.progression.dfa(normal, self.merged_edges if merged else None))
            self._leaves[formula] = dfa
            self._note(dfa, {a.key for a in ast.atoms(formula)})
            if merged:
                self._parts[id(dfa)] = self._merged[id(formula)][1]
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
                    merged.num_states > max(dfas[i].num_states, dfas[j].num_states):
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
        `merge` keeps only when it is no larger than the larger of them:
        `G(r1 -> F !r1) & G(r2 -> F !r2) & ...` says the last letter has no
        r_i, 2 states, where a symbolic product of the parts has 2^n codes
        to minimize (assume-guarantee formulas: 8 pairs, 6.3 s that way)."""
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
        children = ast.children(node)
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
