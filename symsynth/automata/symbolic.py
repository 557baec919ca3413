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

from collections.abc import Callable, Collection, Iterable, Mapping, Sequence

from symsynth.automata.bdd import BDD, Function, and_exists, format_cubes, isop, lexmin
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.progression import GuardedDFA

State = tuple[bool, ...]
Letter = Collection[str]


def prime(bit: str) -> str:
    return bit + "'"


class SymbolicDFA:
    """A complete DFA whose transitions and acceptance are BDDs.

    Use `step`/`accepts` to run it, `to_explicit()` to enumerate it, and
    `relation()`/`delta` to compose it with a game.  `num_states` counts
    the reachable states, the sink included.
    """

    def __init__(self, bdd: BDD, atoms: Sequence[str], bits: Sequence[str],
                 delta: Mapping[str, Function], initial: Mapping[str, bool],
                 accepting: Function, reachable: Function | None = None):
        self.bdd = bdd
        self.atoms = tuple(atoms)
        self.bits = tuple(bits)
        self.delta = dict(delta)
        self.initial_assignment = dict(initial)
        self.accepting = accepting
        self.reachable = self._reach() if reachable is None else reachable  # given: the caller knows

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
        return _dag_size(self.bdd, roots)

    # -- symbolic operations ---------------------------------------------------
    def state_cube(self, state: State | Mapping[str, bool]) -> Function:
        values = state if isinstance(state, Mapping) else dict(zip(self.bits, state))
        return self.bdd.cube(values) if values else self.bdd.true

    def relation(self) -> Function:
        """T(q, x, q') = /\\_b (q'_b <-> delta_b(q, x))."""
        rel = self.bdd.true
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

    def minimize(self) -> SymbolicDFA:
        """The minimal DFA of the same language (self when already minimal).

        The coarsest bisimulation E(q, q') on reachable states is the
        greatest fixpoint of  E = Acc-agreement /\\ \\A x: E(delta(q,x), delta(q',x)).
        Each class is replaced by its least member (in bit order).
        """
        bdd = self.bdd
        if not self.bits:
            return self
        primed = {b: prime(b) for b in self.bits}
        reach2 = self.reachable & bdd.let(primed, self.reachable)
        # E0(q, q') = R(q) /\ R(q') /\ (Acc(q) <-> Acc(q'))
        equiv = reach2 & bdd.apply("<=>", self.accepting, bdd.let(primed, self.accepting))
        step_both = {b: self.delta[b] for b in self.bits}
        step_both.update({primed[b]: bdd.let(primed, self.delta[b]) for b in self.bits})
        old = None
        while equiv != old:
            old = equiv
            # E(q, q') /\ \A x: E(delta(q, x), delta(q', x))
            equiv = equiv & bdd.forall(set(self.atoms), bdd.let(step_both, equiv))
        identity = self.reachable & _equal(bdd, self.bits, [primed[b] for b in self.bits])
        if equiv == identity:
            return self
        representative = _least_member(bdd, equiv, [primed[b] for b in self.bits])
        # rep_b(q) = \E q': Rep(q, q') /\ q'_b
        rep = {b: bdd.exist(set(primed.values()), representative & bdd.var(primed[b]))
               for b in self.bits}
        delta = {b: bdd.let(self.delta, rep[b]) for b in self.bits}
        initial = {b: bdd.let(self.initial_assignment, rep[b]) == bdd.true for b in self.bits}
        return SymbolicDFA(bdd, self.atoms, self.bits, delta, initial, self.accepting)

    # -- explicit form -------------------------------------------------------------
    def to_explicit(self) -> ExplicitDFA:
        """Enumerate the reachable states in BFS order from the initial one.

        Successors of a state are ordered by the least letter leading to
        them (atoms in `self.atoms` order), so the numbering depends on the
        language only, not on the BDD variable order.
        """
        bdd = self.bdd
        start = self.initial
        index = {start: 0}
        order = [start]
        accepting = []
        transitions = []
        for state in order:
            accepting.append(self.is_accepting(state))
            values = dict(zip(self.bits, state))
            functions = [bdd.let(values, self.delta[b]) if values else self.delta[b]
                         for b in self.bits]
            successors = sorted(_split(bdd, functions),
                                key=lambda sg: lexmin(bdd, sg[1], self.atoms))
            for succ, guard in successors:
                if succ not in index:
                    index[succ] = len(order)
                    order.append(succ)
                transitions.append((index[state], format_cubes(isop(bdd, guard)), index[succ]))
        return ExplicitDFA(
            atoms=self.atoms, initial=0,
            accepting=frozenset(i for i, acc in enumerate(accepting) if acc),
            transitions=tuple(transitions), num_states=len(order))


def _evaluate(bdd: BDD, values: Mapping[str, bool], u: Function) -> bool:
    return (bdd.let(values, u) if values else u) == bdd.true


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
    result = bdd.true
    for x, y in zip(xs, ys):
        result &= bdd.apply("<=>", bdd.var(x), bdd.var(y))
    return result


def _least_member(bdd: BDD, relation: Function, targets: Sequence[str]) -> Function:
    """Restrict R(q, t) so that each q keeps only its least t (first bit most
    significant): for each bit in turn, keep t_i = 0 wherever some member
    with the prefix chosen so far has t_i = 0."""
    for i, bit in enumerate(targets):
        rest = set(targets[i:])
        # Z = \E t_i..t_m: R /\ !t_i
        zero_exists = bdd.exist(rest, relation & ~bdd.var(bit))
        relation = relation & (~zero_exists | ~bdd.var(bit))
    return relation


def _dag_size(bdd: BDD, roots: Sequence[Function]) -> int:
    seen = set()
    stack = [r for r in roots]
    while stack:
        u = stack.pop()
        key = int(u) if not getattr(u, "negated", False) else int(~u)
        if key in seen:
            continue
        seen.add(key)
        if u == bdd.true or u == bdd.false:
            continue
        stack.extend((u.low, u.high))
    return len(seen)


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
    BDDs stay small.
    """
    delta: dict[str, Function] = {}
    initial: dict[str, bool] = {}
    bits: list[str] = []
    accepts: list[Function] = []
    reachable = None
    for c, comp in enumerate(components):
        width = (comp.num_states - 1).bit_length()
        names = [f"{prefix}{c}_{j}" for j in range(width)]
        for name in names:
            bdd.declare(name, prime(name))
        for atom in _atoms_read(comp, atoms):
            if atom not in bdd.vars:
                bdd.declare(atom)
        bits.extend(names)
        initial.update({n: bool(comp.initial >> j & 1) for j, n in enumerate(names)})
        if len(components) == 1:
            # next value of bit j in state s: the letters into successors with
            # bit j set, merged over the states by a decision tree on the bits
            ones: list[list[Function]] = [[bdd.false] * comp.num_states for _ in names]
            copied: dict[Function, Function] = {}
            for s, out in enumerate(comp.edges):
                for succ, guard in out.items():
                    here = copied.get(guard)
                    if here is None:
                        here = copied[guard] = comp.bdd.copy(guard, bdd)
                    for j in range(width):
                        if succ >> j & 1:
                            ones[j][s] = ones[j][s] | here
            delta.update({n: _by_state(bdd, names, ones[j]) for j, n in enumerate(names)})
            accepts.append(_by_state(bdd, names, [bdd.true if acc else bdd.false for acc in comp.accepting]))
            reachable = _by_state(bdd, names, [bdd.true] * comp.num_states)  # every state of an explicit DFA
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
    return SymbolicDFA(bdd, atoms, bits, delta, initial, accepting, reachable=reachable)


def _by_state(bdd: BDD, names: Sequence[str], values: Sequence[Function]) -> Function:
    """The function that is `values[s]` where the bits `names` (lowest
    first) encode `s`, and false on the codes past the last state: a
    decision tree on the bits, merged bottom-up by `ite` (one node per
    pair when the values lie below the bits; no disjunction grows)."""
    width = len(names)
    level = list(values) + [bdd.false] * ((1 << width) - len(values))
    for j in reversed(range(width)):  # the last bit is the deepest split
        bit, half = bdd.var(names[j]), 1 << j
        level = [bdd.ite(bit, level[m + half], level[m]) for m in range(half)]
    return level[0]


def _atoms_read(comp: GuardedDFA, atoms: Sequence[str]) -> list[str]:
    support = set()
    for out in comp.edges:
        for guard in out.values():
            support |= comp.bdd.support(guard)
    return [a for a in atoms if a in support]
