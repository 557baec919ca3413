"""Explicit DFA of a (small) LTLf formula by formula progression over BDDs.

A state is a positive Boolean combination of *obligations* on the rest of
the trace, `X f` (strong: a next position exists and satisfies `f`) and
`WX f` (weak), kept as a BDD over one variable per obligation — so equal
combinations are the same state.  Reading a letter replaces every
obligation `X f` / `WX f` by `unfold(f)`, a BDD over the atoms (this letter)
and new obligations (the next one):

    unfold(F f)   = unfold(f) | X F f          unfold(f U g) = unfold(g) | unfold(f) & X(f U g)
    unfold(G f)   = unfold(f) & WX G f         unfold(f R g) = unfold(g) & (unfold(f) | WX(f R g))
    unfold(last)  = WX false                   unfold(f W g) = unfold(g) | unfold(f) & WX(f W g)

The atom variables come first in the order (but for the row bits of
rows.py), so below the atom levels of the successor BDD sit the successor
states themselves (the multi-terminal trick of Spot's MTDFA).  A state
accepts (the trace may end here) iff it is true with every `X` obligation
false and every `WX` obligation true.  The start state is `X phi`, which is
never accepting: traces are non-empty.

Every obligation is `X`/`WX` of a subformula, so the construction ends.
"""

from __future__ import annotations

from collections.abc import Iterator
from functools import singledispatchmethod
from itertools import islice

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function, cofactor, exits, new_manager, split_letters
from symsynth.automata.growth import grew
from symsynth.automata.numbered import Numbered
from symsynth.automata.refine import refine
from symsynth.automata.rows import below_atoms
from symsynth.logic import ast


class GuardedDFA:
    """A complete explicit DFA whose edges carry BDD guards over the atoms.

    `edges[s]` maps each successor of `s` to the guard (letters) leading there;
    the guards of one state are disjoint and cover every letter.  The same
    transitions may be given instead as `moves[s]`, one BDD over the atoms
    and the successor's bits (moves.py: products and minimization of dense
    DFAs cost a few BDD operations per state that way, where guards cost
    one per pair of edges); each form is made from the other when first
    asked for, and kept.  The backward construction gives `numbered`
    instead (numbered.py: all states' moves as one diagram in arrays), from
    which the moves are made when asked for.
    """

    __slots__ = ("bdd", "initial", "accepting", "numbered", "_edges", "_moves", "_degrees")

    def __init__(self, bdd: BDD, initial: int, accepting: list[bool],
                 edges: list[dict[int, Function]] | None = None, *,
                 moves: list[Function] | None = None, degrees: list[int] | None = None,
                 numbered: Numbered | None = None):
        if edges is None and moves is None and numbered is None:
            raise ValueError("a GuardedDFA needs its edges, its moves or its numbered diagram")
        self.bdd = bdd
        self.initial = initial
        self.accepting = accepting
        self.numbered = numbered
        self._edges = edges
        self._moves = moves
        self._degrees = degrees  # (when known: each state's number of successors)

    @property
    def num_states(self) -> int:
        return len(self.accepting)

    @property
    def edges(self) -> list[dict[int, Function]]:
        if self._edges is None:
            self._edges = moves_.decode_all(self.bdd, self.moves)
        return self._edges

    @property
    def moves(self) -> list[Function]:
        if self._moves is None:
            self._moves = self.numbered.moves(self.bdd) if self.numbered is not None \
                else moves_.encode_all(self.bdd, self.edges)
        return self._moves

    def has_edges(self) -> bool:
        """Whether the edges are at hand (not to be made from the moves)."""
        return self._edges is not None

    def successor_lists(self) -> list[list[int]]:
        """Each state's successors."""
        if self._edges is not None:
            return [list(out) for out in self._edges]
        names = moves_.bits(self.bdd, "z", moves_.width(self.num_states))
        return [moves_.numbers(self.bdd, succ, names) for succ in moves_.successors(self.bdd, self.moves)]

    def degrees(self) -> list[int]:
        """Each state's number of successors."""
        if self._degrees is None:
            if self._edges is not None:
                self._degrees = [len(out) for out in self._edges]
            else:
                self._degrees = moves_.count_edges(self.bdd, self.moves)
        return self._degrees

    @property
    def num_edges(self) -> int:
        """Pairs of a state and a successor."""
        return sum(self.degrees())

    def __repr__(self) -> str:
        return f"GuardedDFA({self.num_states} states, initial {self.initial})"


class TooLarge(Exception):
    """A construction went past the size it was given."""


class TooDense(TooLarge):
    """A construction went past the successors per state it was given
    (found early, after a few states: cheap to try)."""


class Progression:
    """Builds `GuardedDFA`s for formulas over a fixed list of atoms."""

    def __init__(self, atom_keys: list[str]):
        self.bdd = new_manager(reordering=False)
        self.atom_keys = list(atom_keys)
        for key in self.atom_keys:  # atoms above every obligation
            self.bdd.declare(key)
        self._obligation_var: dict[tuple[bool, ast.Formula], str] = {}
        self._obligation: dict[str, tuple[bool, ast.Formula]] = {}
        self._unfolded: dict[ast.Formula, Function] = {}
        self._implied: dict[ast.Formula, set[ast.Formula]] = {}  # f -> what f implies (_learn_implications)
        self._constraints: dict[frozenset[str], Function] = {}  # obligations named -> their implications

    # -- obligations -------------------------------------------------------
    def obligation(self, strong: bool, formula: ast.Formula) -> Function:
        """The BDD of `X formula` (strong) or `WX formula` (weak)."""
        if formula == ast.TRUE and not strong:
            return self.bdd.true  # WX true
        if formula == ast.FALSE and strong:
            return self.bdd.false  # X false
        key = (strong, formula)
        name = self._obligation_var.get(key)
        if name is None:
            name = f"#o{len(self._obligation)}"  # "#" keeps it apart from atom names
            self.bdd.declare(name)
            self._obligation_var[key] = name
            self._obligation[name] = key
        return self.bdd.var(name)

    def meaning(self, name: str) -> tuple[bool, ast.Formula] | None:
        """`(strong, f)` when the variable `name` is the obligation `X f`
        (strong) or `WX f`; None for an atom or another variable."""
        return self._obligation.get(name)

    def unfold(self, formula: ast.Formula) -> Function:
        """What `formula` demands of the current letter and the next position."""
        result = self._unfolded.get(formula)
        if result is None:
            result = self._unfold(formula)
            self._unfolded[formula] = result
        return result

    @singledispatchmethod
    def _unfold(self, node: ast.Formula) -> Function:
        raise TypeError(f"not an NNF node: {node!r}")

    @_unfold.register
    def _(self, node: ast.Const):
        return self.bdd.true if node.value else self.bdd.false

    @_unfold.register
    def _(self, node: ast.Atom):
        return self.bdd.var(node.key)

    @_unfold.register
    def _(self, node: ast.Not):
        if not isinstance(node.arg, ast.Atom):  # NNF: only atoms are negated
            raise ValueError(f"not in negation normal form: {node!r}")
        return ~self.bdd.var(node.arg.key)

    @_unfold.register
    def _(self, node: ast.Last):
        return self.obligation(False, ast.FALSE)

    @_unfold.register
    def _(self, node: ast.Next):
        return self.obligation(True, node.arg)

    @_unfold.register
    def _(self, node: ast.WeakNext):
        return self.obligation(False, node.arg)

    @_unfold.register
    def _(self, node: ast.Eventually):
        return self.unfold(node.arg) | self.obligation(True, node)

    @_unfold.register
    def _(self, node: ast.Always):
        return self.unfold(node.arg) & self.obligation(False, node)

    @_unfold.register
    def _(self, node: ast.Until):
        return self.unfold(node.right) | (self.unfold(node.left) & self.obligation(True, node))

    @_unfold.register
    def _(self, node: ast.Release):
        return self.unfold(node.right) & (self.unfold(node.left) | self.obligation(False, node))

    @_unfold.register
    def _(self, node: ast.WeakUntil):
        return self.unfold(node.right) | (self.unfold(node.left) & self.obligation(False, node))

    @_unfold.register
    def _(self, node: ast.And):
        return self.unfold(node.left) & self.unfold(node.right)

    @_unfold.register
    def _(self, node: ast.Or):
        return self.unfold(node.left) | self.unfold(node.right)

    # -- states ------------------------------------------------------------
    def _accepts(self, state: Function) -> bool:
        # the trace ends here: X f is false, WX f is true
        ending = {name: not self._obligation[name][0] for name in self.bdd.support(state)}
        return cofactor(self.bdd, ending, state) == self.bdd.true

    def _successors(self, state: Function, below: dict | None = None,
                    most: int | None = None) -> dict[Function, Function]:
        """successor state -> guard, by splitting on the atom levels; with
        `most`, `TooDense` when there are more successors than that (counted
        before their guards are made)."""
        step = {name: self.unfold(self._obligation[name][1]) for name in self.bdd.support(state)}
        after = self.bdd.let(step, state) if step else state
        after = self._canonical(after)  # so that successors that say the same are one BDD
        if most is not None and next(islice(exits(self.bdd, after, below_atoms(self.bdd, self.atom_keys)), most, None), None) is not None:
            # (a successor past the first `most`)
            raise TooDense(f"a state with more than {most} successors")
        return split_letters(self.bdd, after, below_atoms(self.bdd, self.atom_keys), below)

    # -- states that say the same -------------------------------------------
    def _learn_implications(self, formula: ast.Formula) -> None:
        """Which subformulas of `formula` imply which others at every position,
        by rules whose unfoldings imply each other as BDDs: psi implies
        phi U psi, phi W psi and F psi; G psi and phi R psi imply psi; and
        the transitive closure.  (An until chain p1 U (p2 U (... U pn))
        makes states that are disjunctions of its links' obligations: without
        these, 2^n states before minimization; with them, n + 1.)"""
        direct: dict[ast.Formula, set[ast.Formula]] = {}
        stack, seen = [formula], set()
        while stack:
            f = stack.pop()
            if f in seen:
                continue
            seen.add(f)
            if isinstance(f, (ast.Until, ast.WeakUntil)):
                direct.setdefault(f.right, set()).add(f)
            elif isinstance(f, ast.Eventually):
                direct.setdefault(f.arg, set()).add(f)
            elif isinstance(f, ast.Release):
                direct.setdefault(f, set()).add(f.right)
            elif isinstance(f, ast.Always):
                direct.setdefault(f, set()).add(f.arg)
            stack += ast.children(f)
        for f in direct:
            if f in self._implied:
                continue
            closure, todo = set(), list(direct[f])
            while todo:
                g = todo.pop()
                if g not in closure and g != f:
                    closure.add(g)
                    todo += direct.get(g, ())
            self._implied[f] = closure

    def _canonical(self, state: Function) -> Function:
        """`state` with the implications among the obligations it names
        (X f -> X g and WX f -> WX g for f implying g) applied: equal to
        `state` on every trace, and one BDD for states that differ only by
        them.  First each implied obligation `g` is replaced by `g | f` for
        the obligations `f` that imply it (`WX R1 & WX R3` is `WX R1` for
        R1 = p1 R (p2 R R3): a release chain's states, 2^n without this),
        then the state is conjoined with the implications among what is
        left (`X psi | X(phi U psi)` is `X(phi U psi)`: an until chain's).
        Only obligations already in `state` take part, so the support never
        grows and unfolding it costs no more."""
        names = frozenset(name for name in self.bdd.support(state) if name in self._obligation)
        implied = self._implications(names)
        if not implied:
            return state
        lifted = {b: self.bdd.var(b) | _any(self.bdd, above) for b, above in implied.items()}
        state = self.bdd.let(lifted, state)  # b := b | (the a -> b)
        names = frozenset(name for name in self.bdd.support(state) if name in self._obligation)
        constraint = self._constraints.get(names)
        if constraint is None:
            constraint = self.bdd.true
            for b, above in self._implications(names).items():
                for a in above:
                    constraint &= ~self.bdd.var(a) | self.bdd.var(b)  # X f -> X g
            self._constraints[names] = constraint
        return state & constraint if constraint != self.bdd.true else state

    def _implications(self, names: frozenset[str]) -> dict[str, list[str]]:
        """obligation b -> the obligations a of `names` that imply it, for the
        b of `names` that some a implies."""
        found: dict[str, list[str]] = {}
        for name in names:
            strong, f = self._obligation[name]
            for g in self._implied.get(f, ()):
                other = self._obligation_var.get((strong, g))
                if other in names:
                    found.setdefault(other, []).append(name)
        return found

    def dfa(self, formula: ast.Formula, max_edges: int | None = None,
            max_degree: tuple[int, int] | None = None) -> GuardedDFA:
        """The complete DFA of an NNF formula; states are numbered in BFS order.

        With `max_edges`, `TooLarge` is raised once the DFA has more edges
        (pairs of a state and a successor) than that; with `max_degree`
        `(states, degree)`, `TooDense` when the first `states` states have
        more than `degree` successors each on average: as soon as fewer
        states have more than `states * degree` (the count only grows, so
        the verdict is the same, found sooner: Syft syft_1/001's first
        states have 512 successors each, and its first two already decide,
        where 16 took 0.14 s), and before the guards of one state's
        successors are made when that state alone has more than the rest
        of the budget and more than `states` (then there are more than
        `states` states, and the check at the last one would fail: the AG
        family's first state at n = 8 has 1,536 successors, whose guards
        cost 0.25 s at load 6)."""
        self._learn_implications(formula)
        start = self._canonical(self.obligation(True, formula))
        index = {start: 0}
        order = [start]
        accepting: list[bool] = []
        edges: list[dict[int, Function]] = []
        count = 0
        below: dict = {}  # split_letters' memo: successive states share BDD nodes
        for state in order:  # `order` grows while we walk it: BFS
            grew(len(order))
            accepting.append(self._accepts(state))
            out: dict[int, Function] = {}
            count += len(edges[-1]) if edges else 0
            if max_edges is not None and count > max_edges:
                raise TooLarge(f"more than {max_edges} edges")
            if max_degree is not None and len(edges) <= max_degree[0] and count > max_degree[0] * max_degree[1]:
                raise TooDense(f"more than {max_degree[1]} successors per state")
            most = None if max_degree is None or len(edges) >= max_degree[0] else \
                max(max_degree[0] * max_degree[1] - count, max_degree[0])
            for succ, guard in self._successors(state, below, most).items():
                if succ not in index:
                    index[succ] = len(order)
                    order.append(succ)
                out[index[succ]] = guard
            edges.append(out)
        return GuardedDFA(self.bdd, 0, accepting, edges)


def _any(bdd: BDD, names: list[str]) -> Function:
    """The disjunction of the variables `names`."""
    result = bdd.false
    for name in names:
        result |= bdd.var(name)
    return result


def minimize(dfa: GuardedDFA) -> GuardedDFA:
    """Partition refinement; the result is the minimal complete DFA.

    Two states stay together while they agree on acceptance and, for every
    class, on the set of letters leading into it (their *signature*; guards
    are canonical BDDs, so it is a hashable value), by `refine.refine`'s
    worklist.  Only reachable states are given (the construction yields no
    others).

    A signature ORs a state's guards class by class, except into the class
    entered on the most of them when they outnumber the classes: its letters
    are all the others' complement (the guards of a state are disjoint and
    cover every letter).  In the first round, two classes, that is most of
    the work saved: nim_03_01 45 -> 33 ms.  (With many classes of one guard
    each, the complement would cost an OR per class instead of none.)

    A DFA given by its moves only (a dense product's) is minimized on them
    (moves.minimize: a BDD operation per signature, not one per edge).
    """
    bdd = dfa.bdd
    false = bdd.false
    if not dfa.has_edges():
        given = moves_.Machine(dfa.initial, dfa.accepting, dfa.moves, moves_.successors(bdd, dfa.moves),
                               moves_.width(dfa.num_states))
        found = moves_.minimize(bdd, given)
        return dfa if found is None else GuardedDFA(bdd, 0, found.accepting, moves=found.moves,
                                                    degrees=found.degrees)
    old_edges = dfa.edges
    n = len(old_edges)
    before: list[list[int]] = [[] for _ in range(n)]
    for state, out in enumerate(old_edges):
        for succ in out:
            before[succ].append(state)

    def predecessors(states: list[int]) -> Iterator[int]:
        for state in states:
            yield from before[state]

    block = refine(dfa.accepting, lambda states, block: [_signature(old_edges[state], block, false)
                                                         for state in states], predecessors)
    if dfa.initial == 0 and len(set(block)) == n:
        return dfa  # already minimal (and numbered from its initial state)
    return _quotient(dfa, block)


def _quotient(dfa: GuardedDFA, block: list[int]) -> GuardedDFA:
    """`dfa`'s states merged by `block`, numbered in BFS order from the
    initial state."""
    rename: dict[int, int] = {block[dfa.initial]: 0}
    order = [dfa.initial]
    representative: dict[int, int] = {}  # block -> its first state in BFS order
    for state in order:
        representative.setdefault(block[state], state)
        for succ in dfa.edges[state]:
            if block[succ] not in rename:
                rename[block[succ]] = len(rename)
                order.append(succ)
    accepting = [False] * len(rename)
    edges: list[dict[int, Function]] = [{} for _ in rename]
    for old_block, new in rename.items():
        state = representative[old_block]
        accepting[new] = dfa.accepting[state]
        out = edges[new]
        for succ, guard in dfa.edges[state].items():
            target = rename[block[succ]]
            out[target] = out[target] | guard if target in out else guard
    return GuardedDFA(dfa.bdd, 0, accepting, edges)


def _signature(out_edges: dict[int, Function], block: list[int], false: Function) -> frozenset:
    """A state's letters into each class (its edges `out_edges`, classes
    `block`), as `minimize` compares them."""
    into: dict[int, list[Function]] = {}
    for succ, guard in out_edges.items():
        b = block[succ]
        if b in into:
            into[b].append(guard)
        else:
            into[b] = [guard]
    # the guards are disjoint and cover every letter: the class with the
    # most of them is entered on the letters the others are not, which
    # saves ORs when it has more guards than there are classes (one
    # class: true, no OR at all)
    most = max(into, key=lambda b: len(into[b]))
    skip = most if len(into[most]) > len(into) else None
    joined: dict[int, Function] = {}
    for b, guards in into.items():
        if b != skip:
            union = guards[0]
            for guard in guards[1:]:
                union |= guard
            joined[b] = union
    if skip is not None:
        rest = false
        for union in joined.values():
            rest |= union
        joined[skip] = ~rest
    return frozenset(joined.items())
