"""The minimal DFA of an LTLf formula with no minimization step: evaluate
the formula backwards, then determinize the reverse (Brzozowski).

**Backwards evaluation is deterministic.**  Take the obligations of
progression.py, `X f` (a next position exists and satisfies `f`) and
`WX f` (none does, or it satisfies `f`), closed under unfolding from
`X phi`: the obligations named by `unfold(f)` for every obligation on
`f`.  On a trace w_0 ... w_{n-1} let `u_i` be the vector of their values
at position i.  At the last position every `X f` is false and every `WX f`
true: `u_{n-1} = END`.  For i >= 1, `X f` and `WX f` at i-1 both say `f`
at i, and the expansion laws of LTLf (`f U g = g | f & X(f U g)`, ...)
give `f` at i as `unfold(f)` of the letter w_i and of the obligations
at i.  So `u_{i-1} = H(w_i, u_i)` with `H_o = unfold(f_o)`, a BDD over the
atoms and the obligation variables.  Reading the trace from its end,

    A:  states: vectors u;  start END;  u --a--> H(a, u);  accepting: u[X phi]

is a complete deterministic automaton of the reversed language (after
w_{n-1} ... w_0 it is in `u_{-1}`, whose bit `X phi` is phi at position 0;
the empty trace leaves it in END, where `X phi` is false: traces are
non-empty, as everywhere here).  Restrict A to `Reach`, the vectors it
reaches from END (a symbolic fixpoint below); every state is then reachable.

**The subset construction of A's reverse is the minimal DFA** (Brzozowski,
1962).  Forward, after reading x = x_0 ... x_{k-1}, the set is

    S_x = {u in Reach : A goes from u to an accepting state on x_{k-1} ... x_0},

so `S_eps = Reach & X phi` and `S_xa(u) = Reach(u) & S_x(H(a, u))`: a
simultaneous substitution of the vector H into S_x (dd's `let`).  It
accepts iff END is in S_x.  Correct: END in S_xy iff A goes from END to an
accepting state on (xy) reversed iff xy satisfies phi.  Minimal: if u is
in S_x and not in S_x', take z leading A from END to u (u is in Reach)
and y = z reversed: xy is in the language and x'y is not, so different
sets are different residuals; and every state made is reachable.  The
empty set (a rejecting sink) and Reach itself (an accepting one: H maps
Reach into Reach) are states like the others.

**Explicit states, symbolic guards.**  The atoms sit above the obligation
variables in the order, so `T(a, u) = Reach(u) & S(H(a, u))`, one BDD for
all letters at once, leaves the atom levels at one node per successor set,
reached on exactly that successor's letters (`split_letters`, as in
progression).  Sets are BDDs, so equal sets are one node: every node found
is a new state of the minimal DFA or one already numbered, with no
canonical form to compute and no minimization after.

Cost: one substitution per state, over as many bits as obligations, where
progression makes states that are Boolean combinations of obligations
(more of them than the minimal DFA's states on alternating chains
p1 U (p2 R (p3 U ...)), whose minimization then costs the most), and the
image of `Reach` under H (a relation over two copies of the obligations).
Below the atom levels the substitution makes one set per state and
distinct successor (an edge): 1.45 million on urright12, 10.9 million on
urright13.  The obligations' order sets the cost of each: with the inner
obligations highest (`_order_obligations`) urright13's construction takes
3.3-3.6 s where it took 13.5 s in the order of discovery (load 4-5).
Letter classes would not help: on URright (n = 8, 10, 12) the 2^n letters
act on Reach in 2^(n-1) + 1 different ways, so a subset construction over
explicit bit sets of Reach would gather 2^(n-1) x |Reach| entries a state
(5 million on urright14: 8,193 x 611), where the BDD shares that work
between letters and states.
"""

from __future__ import annotations

from symsynth.automata.bdd import Function, and_exists, branches, children_first, swap
from symsynth.automata.growth import grew
from symsynth.automata.numbered import Listing
from symsynth.automata.progression import GuardedDFA, Progression, TooLarge
from symsynth.logic import ast


class Backward:
    """The backward automaton A of one NNF formula in `progression`'s
    manager: its obligations, their one-step functions H and the vectors
    reachable from END."""

    def __init__(self, progression: Progression, formula: ast.Formula, max_obligations: int | None = None):
        self.progression = progression
        self.bdd = bdd = progression.bdd
        self.start = progression.obligation(True, formula)  # X phi (false when phi is false)
        self.step, self.end = self._closure()  # (END: X f false, WX f true)
        if max_obligations is not None and len(self.step) > max_obligations:
            raise TooLarge(f"more than {max_obligations} obligations")
        self._order_obligations()
        self.reach = self._reachable()
        self._composed: dict[Function, Function] = {bdd.true: self.reach, bdd.false: bdd.false}  # S -> Reach & S(H)
        self._at_end: dict[Function, bool] = {bdd.true: True, bdd.false: False}  # S -> END in S

    def _closure(self) -> tuple[dict[str, Function], dict[str, bool]]:
        """obligation variable -> its H (unfold of its operand), for every
        obligation reached from `X phi`; and its value at END."""
        step: dict[str, Function] = {}
        end: dict[str, bool] = {}
        todo = [name for name in self.bdd.support(self.start)]
        while todo:
            name = todo.pop()
            if name in step:
                continue
            meaning = self.progression.meaning(name)
            if meaning is None:  # (an atom: not an obligation)
                continue
            strong, operand = meaning
            step[name] = self.progression.unfold(operand)
            end[name] = not strong
            todo.extend(v for v in self.bdd.support(step[name]) if v not in step)
        return step, end

    def _order_obligations(self) -> None:
        """The obligations on the least nested operands highest, `X phi`'s
        (phi nests the most) lowest, on the levels they occupied (every
        other variable stays where it was).  A set is then decided by the
        inner obligations first: urright14's successors take 5.4 s of CPU
        where they took 80.6 s in the order of discovery (the root first;
        `backward_dfa` 19 s against 92 s); the inner ones in the reverse
        order are 1.5x slower than discovery on urright12.  The states are
        the same sets, numbered alike (by the letters, above them)."""

        def nesting(name: str) -> int:
            meaning = self.progression.meaning(name)  # (every name of `step` has one)
            return 0 if meaning is None else ast.depth(meaning[1])

        bdd = self.bdd
        names = sorted(self.step, key=bdd.level_of_var)
        wanted = sorted(names, key=nesting)  # (stable: ties keep their order)
        if wanted == names:
            return
        order = {var: bdd.level_of_var(var) for var in bdd.vars}
        order.update(zip(wanted, [order[name] for name in names]))
        bdd.reorder(order)

    def _reachable(self) -> Function:
        """Reach = mu R. END | image(R), image(R)(u') = \\E a, u: R(u) & /\\_o u'_o <-> H_o(a, u)."""
        bdd = self.bdd
        names = sorted(self.step, key=lambda name: bdd.level_of_var(name))
        primed = {name: f"{name}'" for name in names}
        for name in names:  # below every obligation: H reads none of them
            if primed[name] not in bdd.vars:
                bdd.declare(primed[name])
        relation = bdd.true
        for name in reversed(names):
            relation &= bdd.var(primed[name]).equiv(self.step[name])  # u'_o <-> H_o(a, u)
        qvars = list(self.progression.atom_keys) + names
        reach = bdd.cube(self.end)
        old = None
        while reach != old:
            old = reach
            image = and_exists(bdd, reach, relation, qvars)  # \E a, u: R(u) & u' = H(a, u)
            reach = reach | swap(bdd, image, primed)  # R | image(R)[u' := u]
        return reach

    def initial(self) -> Function:
        """S_eps = Reach & X phi."""
        return self.reach & self.start

    def successors(self, state: Function) -> Function:
        """T(a, u) = Reach(u) & S(H(a, u)): a BDD over the letter and the
        obligations whose nodes below the atom levels are the successors.

        By Shannon expansion on S's top variable v, Reach & S(H) is
        ite(H_v, Reach & S_high(H), Reach & S_low(H)), with Reach for S =
        true: one `ite` per node of S, remembered across states (successive
        sets share most nodes), where dd's `let` (CUDD's vector compose)
        starts afresh at every call (3x the time on urright12).  (S and H
        restricted to Reach, CUDD's `restrict`, had 15 % fewer `ite`s and
        saved a quarter of the time in the order of discovery; in the order
        of `_order_obligations` it costs 5-10 %.)"""
        bdd, done, step = self.bdd, self._composed, self.step
        for node, low, high in children_first(bdd, state, done):
            done[node] = bdd.ite(step[node.var], done[high], done[low])
        return done[state]

    def accepts(self, state: Function) -> bool:
        """END in S: S's path under END's values, the answer remembered for
        every node on it (sets share nodes: urright14's 169,542 states take
        0.3 s this way, 1.3-1.7 s as one cofactor each; load 3)."""
        bdd, known, end = self.bdd, self._at_end, self.end
        path = []
        node = state
        while node not in known:
            path.append(node)
            low, high = branches(bdd, node)
            node = high if end[node.var] else low
        for passed in path:
            known[passed] = known[node]
        return known[node]


def backward_dfa(progression: Progression, formula: ast.Formula, max_states: int | None = None,
                 max_obligations: int | None = None) -> GuardedDFA:
    """The minimal complete DFA of the NNF `formula` (module docstring),
    states numbered in BFS order from the initial one, given by its moves
    (moves.py); `TooLarge` past `max_states` states or, before any state is
    made, past `max_obligations` obligations.

    The successors of a state are numbered as a depth-first walk (high
    branch first) of T meets them; nodes at atom levels met for an earlier
    state are not walked again (every successor below them has its number).
    The walk lists those nodes children first (numbered.py's `Listing`), and
    the DFA is given by them as one diagram whose leaves are the successors'
    numbers (numbered.py), from which the moves (T with each successor's
    node replaced by the cube of its number, one `ite` per node at atom
    levels) or the transition bits are made when asked for.  No guard is
    made: urright12 has 1.45 million edges, 8,898 states and 63,148 such
    nodes.  (Walking T's nodes a second time for the moves, children first,
    took urright14's construction 5.7 s where the list takes 2.5 s, and the
    walk 0.9 s more; load 3.5.)"""
    automaton = Backward(progression, formula, max_obligations)
    bdd = progression.bdd
    num_atoms = len(progression.atom_keys)
    if any(bdd.level_of_var(key) != i for i, key in enumerate(progression.atom_keys)):  # (the diagram reads atoms by level)
        raise AssertionError("internal error: the atoms are not the top levels of the manager, in their order")
    listing = Listing(bdd, num_atoms, automaton.initial())
    order = listing.order
    tops: list[Function] = []  # T of each state (alive while the listing holds their nodes' ids)
    for state in order:  # `order` grows while we walk it: BFS
        grew(len(order))
        top = automaton.successors(state)
        tops.append(top)
        for _ in listing.walk(top):  # the successors, numbered, each node walked once in all
            if max_states is not None and len(order) > max_states:
                raise TooLarge(f"more than {max_states} states")
    numbered = listing.numbered(progression.atom_keys)
    del tops, listing
    return GuardedDFA(bdd, 0, [automaton.accepts(s) for s in order], numbered=numbered)

