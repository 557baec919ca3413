"""The symbolic DFA: state bits, atom variables and BDDs in one manager.

A `SymbolicDFA` over state bits `q = (q_0, q_1, ...)` and atoms `x` holds

- `delta[b]`: the next value of bit `b` as a BDD over `q` and `x`
  (the transition *function*, one BDD per bit);
- `accepting`: a BDD over `q`;
- `initial`: the initial state as an assignment to `q`;
- `reachable`: the states reachable from `initial`, a BDD over `q`.

Each bit `b` has a primed copy `b'`, declared next to it, for relational
uses (`relation()`, bisimulation, the game's next-state variables).

Products of components are built here, and `minimize` computes the coarsest
bisimulation on the reachable states symbolically and quotients by it, so
the result is the minimal DFA of the language.
"""

from __future__ import annotations

from bisect import bisect_left
from collections import Counter
from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from contextlib import AbstractContextManager, nullcontext
from functools import partial

from symsynth.automata.bdd import (BDD, Function, and_exists, children_first, cofactor, exists, fixed_order,
                                   format_cubes, is_constant, isop, lexmin, restrict, shared_size,
                                   without_cyclic_gc)
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.numbered import Numbered
from symsynth.automata.progression import GuardedDFA
from symsynth.automata.single import bit_functions, by_state

State = tuple[bool, ...]
Letter = Collection[str]


def prime(bit: str) -> str:
    return bit + "'"


class TooManyTransitions(Exception):
    """An explicit DFA past the transitions asked for (`to_explicit`)."""

    def __init__(self, states: int, transitions: int, limit: int):
        self.states, self.transitions, self.limit = states, transitions, limit
        super().__init__(f"the DFA has {states:,} states and {transitions:,} transitions "
                         f"(more than {limit:,})")


class SymbolicDFA:
    """A complete DFA whose transitions and acceptance are BDDs.

    Use `step`/`accepts` to run it, `to_explicit()` to enumerate it, and
    `relation()`/`delta` to compose it with a game.  `num_states` counts
    the reachable states, the sink included.

    `local`: the declared variable order keeps each part's atoms next to its
    bits and no atom is read by two parts (a `product` of LOCAL_PARTS or
    more components over disjoint atoms); `_reach` and `minimize` then
    suspend dynamic reordering, which costs more than it finds there (see
    `minimize`).

    `delta` may be given as a function that makes the transition functions:
    they are then made when first read (`delta_made` says whether they are).
    `diagram`: the moves of every state as one numbered diagram over the
    atoms (numbered.py), when the construction gave one: the DFA itself, in
    MONA's form, which a summary can describe without the bits' functions
    (urright16: 5 million states, its bits' functions too large to make).
    """

    def __init__(self, bdd: BDD, atoms: Sequence[str], bits: Sequence[str],
                 delta: Mapping[str, Function] | Callable[[], Mapping[str, Function]],
                 initial: Mapping[str, bool], accepting: Function, reachable: Function | None = None, *,
                 local: bool = False, diagram: Numbered | None = None):
        self.bdd = bdd
        self.local = local
        self.atoms = tuple(atoms)
        self.bits = tuple(bits)
        self._delta = delta if callable(delta) else dict(delta)
        self.diagram = diagram
        self.initial_assignment = dict(initial)
        self.accepting = accepting
        self.reachable = self._reach() if reachable is None else reachable  # given: the caller knows

    @property
    def delta(self) -> dict[str, Function]:
        """bit -> its transition function (made on first use when `delta`
        was given as a function)."""
        return self.make_delta()

    def make_delta(self) -> dict[str, Function]:
        """`delta`, made now if it was not yet (a caller that times its
        steps counts them where it wants)."""
        if callable(self._delta):
            with without_cyclic_gc():  # (as the compilation that gave the maker)
                self._delta = dict(self._delta())  # (the maker goes, and what it held)
        return self._delta

    @property
    def delta_made(self) -> bool:
        """Whether the transition functions exist (they always do unless
        given as a function and not read since)."""
        return not callable(self._delta)

    def copy_to(self, bdd: BDD) -> SymbolicDFA:
        """The same DFA in the manager `bdd`: the variables of this one's
        manager that `bdd` lacks declared below its own, in this one's
        order, and its functions copied."""
        for var in sorted(self.bdd.vars, key=self.bdd.level_of_var):
            if var not in bdd.vars:
                bdd.declare(var)

        def copy(u: Function) -> Function:
            return self.bdd.copy(u, bdd)
        return SymbolicDFA(bdd, self.atoms, self.bits, {b: copy(d) for b, d in self.delta.items()},
                           self.initial_assignment, copy(self.accepting), copy(self.reachable),
                           local=self.local, diagram=self.diagram)

    # -- running -------------------------------------------------------------
    @property
    def initial(self) -> State:
        return tuple(self.initial_assignment[b] for b in self.bits)

    def _letter(self, letter: Letter) -> dict[str, bool]:
        return {atom: atom in letter for atom in self.atoms}

    def step(self, state: State, letter: Letter) -> State:
        """The state after reading `letter` (the set of atoms that hold)."""
        values = dict(zip(self.bits, state)) | self._letter(letter)
        return tuple(_evaluate(self.bdd, values, self.delta[b]) for b in self.bits)

    def is_accepting(self, state: State) -> bool:
        return _evaluate(self.bdd, dict(zip(self.bits, state)), self.accepting)

    def accepts(self, trace: Iterable[Letter]) -> bool:
        """Whether the (non-empty) trace satisfies the formula."""
        state, empty = self.initial, True
        for letter in trace:
            state, empty = self.step(state, letter), False
        return not empty and self.is_accepting(state)

    # -- sizes ---------------------------------------------------------------
    @property
    def num_states(self) -> int:
        return int(self.bdd.count(self.reachable, nvars=len(self.bits))) if self.bits else 1

    @property
    def num_nodes(self) -> int:
        """BDD nodes of the transition functions and acceptance, shared."""
        roots = list(self.delta.values()) + [self.accepting, self.reachable]
        return shared_size(self.bdd, roots)

    # -- symbolic operations ---------------------------------------------------
    def state_cube(self, state: State | Mapping[str, bool]) -> Function:
        values = state if isinstance(state, Mapping) else dict(zip(self.bits, state))
        return self.bdd.cube(values) if values else self.bdd.true

    def relation(self, within: Function | None = None) -> Function:
        """T(q, x, q') = /\\_b (q'_b <-> delta_b(q, x)), conjoined from the
        start with `within` when given (a set of states q keeps T small)."""
        rel = self.bdd.true if within is None else within
        for b in self.bits:
            rel &= self.bdd.apply("<=>", self.bdd.var(prime(b)), self.delta[b])
        return rel

    def _reach(self) -> Function:
        """Least fixpoint: states reachable from `initial`.

        The image is taken conjunct by conjunct of T (one per bit, in bit
        order), each variable of q and x quantified as soon as no later
        conjunct reads it: the monolithic T of a product of independent
        components, with every atom above every state bit, is exponential
        in their number (44 one-step invariants: 6.4 s for T alone)."""
        bdd = self.bdd
        if not self.bits:
            return bdd.true
        with self._order():
            conjuncts = [bdd.apply("<=>", bdd.var(prime(b)), self.delta[b]) for b in self.bits]
            quantified = set(self.bits) | set(self.atoms)
            # the q and x variables to quantify after conjunct i: read by none after it
            schedule: list[set[str]] = []
            later: set[str] = set()
            for conjunct in reversed(conjuncts):
                support = bdd.support(conjunct) & quantified
                schedule.append(support - later)
                later |= support
            schedule.reverse()
            first = quantified - later  # read by no conjunct: quantified with the first one
            unprime = {prime(b): b for b in self.bits}
            reached = self.state_cube(self.initial_assignment)
            old = None
            while reached != old:
                old = reached
                # \E q, x: Reached(q) /\ T(q, x, q'), renamed q' -> q
                image = bdd.exist(first, reached) if first else reached
                for conjunct, qvars in zip(conjuncts, schedule):
                    image = and_exists(bdd, image, conjunct, qvars)
                reached = reached | bdd.let(unprime, image)
            return reached

    def _order(self) -> AbstractContextManager[None]:
        """The manager's reordering as it is, or suspended for a local DFA."""
        return fixed_order(self.bdd) if self.local else nullcontext()

    def minimize(self) -> SymbolicDFA:
        """The minimal DFA of the same language (self when already minimal).

        The coarsest bisimulation E(q, q') on reachable states is the
        greatest fixpoint of  E = Acc-agreement /\\ \\A x: E(delta(q,x), delta(q',x)).
        Each class is replaced by its least member (in bit order).

        The variable order decides the cost.  In a local DFA (a product of
        LOCAL_PARTS or more parts over disjoint atoms, each part's bits,
        their primed copies and its atoms declared together) every BDD here
        is a sum of per-part pieces: for n one-step invariants
        `G(a_i -> X b_i)`, E has O(n) nodes.  Dynamic reordering (sifting)
        minimizes the BDDs alive when it runs, not E(delta(q,x), delta(q',x))
        under construction: it lifted the atoms above the bits and parted
        bits from their primed copies, and that BDD became exponential in n
        (44 invariants: 20 s in one step; 100: 146 s in all; with each
        part's variables grouped so that they move together, 16 s at 100,
        in sifting alone).  So a local DFA is minimized in its declared
        order (100: 0.3 s with the rest below).  Where parts share atoms
        (the Syft specifications) no declared order is known to be good and
        sifting pays (syft_2/004: 0.4 s with it, 47 s in the declared
        order), as it does for a few disjoint parts (`LOCAL_PARTS`), so the
        manager's setting is kept there.

        The least members come from one pass over E's nodes
        (`_least_member`), and the quotient's functions differ from the
        product's only where the successor is moved (not its class's least
        member): delta'_b = ite(Moved(delta), rep_b(delta), delta_b), with
        rep_b simplified on Moved, a constant where one class is merged (the
        invariants' sink).  On codes no reachable state leads to, delta'
        may differ from rep(delta): those are no states of the DFA.
        """
        if not self.bits:
            return self
        with self._order():
            return self._quotient(self._bisimulation())

    def _bisimulation(self) -> Function:
        """E(q, q'), the coarsest bisimulation on reachable states: the
        coarsest one on all codes, restricted to reachable pairs at the end.
        The two are equal since the reachable states are closed under
        delta, and the fixpoint without R(q) /\\ R(q') costs less: the
        substitution of delta into E (`let`) built its large intermediates
        on R's conjunction (Random/Lydia case_07_50/01, 26,799,601 states:
        two such steps of 12 s each, 24 s in all; 8 s without R, load 4-6)."""
        bdd = self.bdd
        primed = {b: prime(b) for b in self.bits}
        # E0(q, q') = (Acc(q) <-> Acc(q'))
        equiv = bdd.apply("<=>", self.accepting, bdd.let(primed, self.accepting))
        step_both = {b: self.delta[b] for b in self.bits}
        step_both.update({primed[b]: bdd.let(primed, self.delta[b]) for b in self.bits})
        old = None
        while equiv != old:
            old = equiv
            # E(q, q') /\ \A x: E(delta(q, x), delta(q', x))
            equiv = equiv & bdd.forall(set(self.atoms), bdd.let(step_both, equiv))
        return equiv & self.reachable & bdd.let(primed, self.reachable)

    def _quotient(self, equiv: Function) -> SymbolicDFA:
        """The DFA of the least members of the classes of `equiv`."""
        bdd = self.bdd
        primed = {b: prime(b) for b in self.bits}
        targets = [primed[b] for b in self.bits]
        identity = _equal(bdd, self.bits, targets)
        if equiv == self.reachable & identity:
            return self
        representative = _least_member(bdd, equiv, targets)
        # Moved(q) = R(q) /\ !Rep(q, q): the states that are not their class's least member
        moved = self.reachable & ~and_exists(bdd, representative, identity, set(targets))
        # rep_b(q) = \E q': Rep(q, q') /\ q'_b on Moved (a constant where one class is moved)
        onto = representative & moved
        rep = {b: restrict(bdd, and_exists(bdd, onto, bdd.var(t), set(targets)), moved)
               for b, t in primed.items()}
        # delta'_b(q, x) = rep_b(delta(q, x)) = ite(Moved(delta(q, x)), rep_b(delta(q, x)), delta_b(q, x))
        moved_next = bdd.let(self.delta, moved)
        delta = {b: bdd.ite(moved_next, rep[b] if is_constant(bdd, rep[b]) else bdd.let(self.delta, rep[b]),
                            self.delta[b]) for b in self.bits}
        start = cofactor(bdd, self.initial_assignment, representative)  # Rep(init, q'): one q'
        initial = {b: start & bdd.var(t) != bdd.false for b, t in primed.items()}
        # the quotient's reachable states are the least members of the classes
        # of reachable states: rep(init) is one, and rep(delta(rep(s), x)) =
        # rep(delta(s, x)) since rep(s) ~ s.  R'(q) = (\E q: Rep(q, q'))[q' -> q]
        unprime = {t: b for b, t in primed.items()}
        reachable = bdd.let(unprime, bdd.exist(set(self.bits), representative))
        return SymbolicDFA(bdd, self.atoms, self.bits, delta, initial, self.accepting, reachable,
                           local=self.local)

    # -- explicit form -------------------------------------------------------------
    def to_explicit(self, max_transitions: int | None = None,
                    progress: Callable[[int], None] | None = None) -> ExplicitDFA:
        """Enumerate the reachable states in BFS order from the initial one.

        Successors of a state are ordered by the least letter leading to
        them (atoms in `self.atoms` order), so the numbering depends on the
        language only, not on the BDD variable order.  `TooManyTransitions`
        when there are more than `max_transitions` (counted first, in one
        BDD: Random/Syft's syft_2/001 has 2,066 states of some 2,000
        successors each); `progress(n)` is called after each of the n
        states.
        """
        if max_transitions is not None:
            count = self.num_transitions()
            if count > max_transitions:
                raise TooManyTransitions(self.num_states, count, max_transitions)
        bdd = self.bdd
        start = self.initial
        index = {start: 0}
        order = [start]
        accepting = []
        transitions = []
        for state in order:
            accepting.append(self.is_accepting(state))
            values = dict(zip(self.bits, state))
            functions = [cofactor(bdd, values, self.delta[b]) for b in self.bits]
            successors = sorted(_split(bdd, functions), key=lambda sg: lexmin(bdd, sg[1], self.atoms))
            if progress is not None:
                progress(len(accepting))
            for succ, guard in successors:
                if succ not in index:
                    index[succ] = len(order)
                    order.append(succ)
                transitions.append((index[state], format_cubes(isop(bdd, guard)), index[succ]))
        return ExplicitDFA(
            atoms=self.atoms, initial=0,
            accepting=frozenset(i for i, acc in enumerate(accepting) if acc),
            transitions=tuple(transitions), num_states=len(order))

    def num_transitions(self) -> int:
        """The number of (state, successor) pairs over the reachable states,
        as `to_explicit` lists them: the transition relation
        \\E x: Reach(q) /\\ /\\_b (b' <-> delta_b(q, x)), counted (0.05 s for
        Random/Syft's syft_2/001: 2,066 states, 4.2 million pairs)."""
        pairs = exists(self.bdd, self.relation(within=self.reachable), list(self.atoms))
        return int(self.bdd.count(pairs, nvars=2 * len(self.bits)))


def _evaluate(bdd: BDD, values: Mapping[str, bool], u: Function) -> bool:
    return cofactor(bdd, values, u) == bdd.true


def _split(bdd: BDD, functions: list[Function]) -> list[tuple[State, Function]]:
    """The distinct values of a vector of Boolean functions of the letter,
    each with the set of letters that produce it."""
    found: list[tuple[State, Function]] = [((), bdd.true)]
    for f in functions:
        found = [(value + (bit,), part)
                 for value, guard in found
                 for bit, part in ((False, guard & ~f), (True, guard & f))
                 if part != bdd.false]
    return found


def _equal(bdd: BDD, xs: Sequence[str], ys: Sequence[str]) -> Function:
    """/\\_i (x_i <-> y_i), conjoined from the deepest pair up: each step
    then adds a node or two above the BDD so far (top down, each step
    rebuilds it: quadratic in the number of pairs)."""
    pairs = sorted(zip(xs, ys), key=lambda p: -min(bdd.level_of_var(p[0]), bdd.level_of_var(p[1])))
    result = bdd.true
    for x, y in pairs:
        result &= bdd.apply("<=>", bdd.var(x), bdd.var(y))
    return result


def _least_member(bdd: BDD, relation: Function, targets: Sequence[str]) -> Function:
    """Restrict R(q, t) so that each q keeps only its least t (first target
    most significant), in one pass over R's nodes when the targets lie in
    the variable order in their order of significance and reordering is
    off (else target by target, `_least_member_by_bits`).

    Bottom up, each node u gets least(u) and some(u) = \\E t: u.  At a node
    on target t_i with cofactors L (t_i = 0) and H, a member with t_i = 0
    exists exactly where some(L) holds, so
        least(u) = ite(t_i, least(H) /\\ !some(L), least(L)),
        some(u) = some(L) \\/ some(H);
    at a node on any other variable v, the ite on v of the cofactors'.
    A target that an edge skips is 0 in the least member.  Each node is
    visited once, where target by target rebuilds all of R once per target
    (quadratic in the bits: 200 invariants, 400 bits, took 5.1 s; 300
    invariants, 600 bits, take 0.2 s in one pass)."""
    levels = [bdd.level_of_var(t) for t in targets]
    if levels != sorted(levels) or bdd.configure()["reordering"]:  # levels must hold still
        return _least_member_by_bits(bdd, relation, targets)
    is_target = set(targets)
    least = {bdd.false: bdd.false, bdd.true: bdd.true}
    some = {bdd.false: bdd.false, bdd.true: bdd.true}

    padded: dict[tuple[Function, int], Function] = {}

    def zeros(u: Function, level: int) -> Function:
        """least(u) with the targets from `level` down to u's top set to 0."""
        first, last = bisect_left(levels, level), bisect_left(levels, u.level)
        if first == last or u == bdd.false:
            return least[u]
        missing = first  # padded[u, i] for i from `first` on, the last missing first
        while missing < last and (u, missing) not in padded:
            missing += 1
        result = least[u] if missing == last else padded[u, missing]
        for i in reversed(range(first, missing)):
            result = padded[u, i] = bdd.ite(bdd.var(targets[i]), bdd.false, result)  # !t_i /\ ...
        return result

    for u, low, high in children_first(bdd, relation, least):
        var = bdd.var(u.var)
        least_low, least_high = zeros(low, u.level + 1), zeros(high, u.level + 1)
        if u.var in is_target:
            least[u] = bdd.ite(var, least_high & ~some[low], least_low)
            some[u] = some[low] | some[high]
        else:
            least[u] = bdd.ite(var, least_high, least_low)
            some[u] = bdd.ite(var, some[high], some[low])
    return zeros(relation, 0)


def _least_member_by_bits(bdd: BDD, relation: Function, targets: Sequence[str]) -> Function:
    """`_least_member` in any variable order: for each target in turn, keep
    t_i = 0 wherever some member with the prefix chosen so far has t_i = 0."""
    for i, bit in enumerate(targets):
        rest = set(targets[i:])
        # Z = \E t_i..t_m: R /\ !t_i
        zero_exists = bdd.exist(rest, relation & ~bdd.var(bit))
        relation = relation & (~zero_exists | ~bdd.var(bit))
    return relation


#: A product of at least this many components over pairwise disjoint atoms
#: is built and minimized in its declared order (`SymbolicDFA.minimize`).
#: Fewer, and sifting pays for itself: syft_5/001 (8 such parts, one of 29
#: states over 6 atoms) minimizes in 0.12 s with it, 1.1 s without.  Up to
#: 32 independent one-step invariants the two cost the same (sifting rarely
#: starts); from there sifting costs more than it finds (40: 0.5 s against
#: 0.08 s in the declared order; 60: 34 s against 0.2 s).
LOCAL_PARTS = 16


def is_local(read: Sequence[Sequence[str]]) -> bool:
    """Whether a product of components reading the atoms `read` (one list
    per component) keeps its declared order: LOCAL_PARTS or more parts, no
    atom read by two (see SymbolicDFA.minimize)."""
    readers = Counter(atom for r in read for atom in r)
    return len(read) >= LOCAL_PARTS and all(n == 1 for n in readers.values())


def atoms_read(components: Sequence[GuardedDFA], atoms: Sequence[str]) -> list[list[str]]:
    """The atoms of `atoms` each component's guards read, in that order."""
    return [_atoms_read(comp, atoms) for comp in components]


def product(bdd: BDD, atoms: Sequence[str], components: Sequence[GuardedDFA],
            prefix: str = "#q",
            combine: Callable[[list[Function]], Function] | None = None) -> SymbolicDFA:
    """The synchronous product of complete DFAs, accepting when all accept,
    or as `combine` says: it maps the components' acceptance BDDs (in order)
    to the product's.

    Component `c` gets bits `{prefix}{c}_0, ...` (lowest first), each with its
    primed copy next to it; the atoms a component reads (and no earlier one
    did) are declared just after its bits.  State bits above the atoms keep
    a transition function a small case split on the state, and a
    conjunction of independent parts gets an order in which every part's
    BDDs stay small.  When no atom is read by two of LOCAL_PARTS or more
    components, that order is kept: the product is built with dynamic
    reordering suspended and the DFA is `local` (`SymbolicDFA.minimize`
    says why).

    A single component built in `bdd` itself gets its bits inserted above
    the atoms already there, and its guards are used as they are (copying
    them to another manager cost a compilation of nim_03_01 a sixth of its
    time: 8 us a guard, 731 guards).
    """
    if len(components) == 1 and components[0].bdd is bdd:  # its atoms declared already
        return _product(bdd, atoms, components, [[]], prefix, combine, False)
    read = [_atoms_read(comp, atoms) for comp in components]
    local = is_local(read)
    with fixed_order(bdd) if local else nullcontext():
        return _product(bdd, atoms, components, read, prefix, combine, local)


def _product(bdd: BDD, atoms: Sequence[str], components: Sequence[GuardedDFA], read: list[list[str]],
             prefix: str, combine: Callable[[list[Function]], Function] | None,
             local: bool) -> SymbolicDFA:
    delta: dict[str, Function] = {}
    initial: dict[str, bool] = {}
    bits: list[str] = []
    accepts: list[Function] = []
    reachable = None
    made_later = None  # (a single numbered component's bits: made on first use)
    for c, comp in enumerate(components):
        width = (comp.num_states - 1).bit_length()
        names = [f"{prefix}{c}_{j}" for j in range(width)]
        if comp.bdd is bdd:  # the component's own manager: its bits go above its atoms
            for j, name in enumerate(names):
                bdd.insert_var(name, 2 * j)
                bdd.insert_var(prime(name), 2 * j + 1)
        else:
            for name in names:
                bdd.declare(name, prime(name))
        for atom in read[c]:
            if atom not in bdd.vars:
                bdd.declare(atom)
        bits.extend(names)
        initial.update({n: bool(comp.initial >> j & 1) for j, n in enumerate(names)})
        if len(components) == 1:
            accepts.append(by_state(bdd, names, [bdd.true if acc else bdd.false for acc in comp.accepting]))
            reachable = by_state(bdd, names, [bdd.true] * comp.num_states)  # every state of an explicit DFA
            # next value of bit j in state s: the letters into successors with
            # bit j set, merged over the states by a decision tree on the bits
            # (a bit all successors agree on needs no disjunction: most bits
            # of most states, the successors of a state being few and near);
            # from a numbered diagram, made on first use (the class docstring)
            if comp.numbered is not None and comp.bdd is bdd:
                made_later = partial(bit_functions, bdd, comp, names)
            else:
                delta.update(bit_functions(bdd, comp, names))
            continue
        # several components: the manager reorders while they are built, and
        # disjunctions of state codes fare better there than the tree above
        codes = [bdd.cube({n: bool(s >> j & 1) for j, n in enumerate(names)}) if names else bdd.true
                 for s in range(comp.num_states)]
        comp_delta = {n: bdd.false for n in names}
        for s, out in enumerate(comp.edges):
            for succ, guard in out.items():
                moved = codes[s] & comp.bdd.copy(guard, bdd)
                for j, n in enumerate(names):
                    if succ >> j & 1:
                        comp_delta[n] |= moved
        delta.update(comp_delta)
        comp_acc = bdd.false
        for s, acc in enumerate(comp.accepting):
            if acc:
                comp_acc |= codes[s]
        accepts.append(comp_acc)
    for atom in atoms:  # atoms no component reads still get a variable
        if atom not in bdd.vars:
            bdd.declare(atom)
    if combine is not None:
        accepting = combine(accepts)
    else:
        accepting = bdd.true
        for comp_acc in accepts:
            accepting &= comp_acc
    if made_later is not None:
        return SymbolicDFA(bdd, atoms, bits, made_later, initial, accepting, reachable=reachable,
                           diagram=components[0].numbered)
    return SymbolicDFA(bdd, atoms, bits, delta, initial, accepting, reachable=reachable, local=local)


def _atoms_read(comp: GuardedDFA, atoms: Sequence[str]) -> list[str]:
    if not comp.has_edges():
        guards = set(comp.moves)  # (their successor bits are no atoms)
    else:
        guards = {guard for out in comp.edges for guard in out.values()}  # (each once)
    support: set[str] = set()
    for guard in guards:
        support |= comp.bdd.support(guard)
    return [a for a in atoms if a in support]
