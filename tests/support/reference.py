"""Independent oracles for the LTLf -> DFA tests: explicit letters, no BDDs.

Nothing here imports `symsynth.automata`; it is a second, deliberately
naive implementation that the symbolic one is compared with.

The method
----------
1.  The formula is put in negation normal form (`nnf`), so negation only
    sits on atoms.  `!last` becomes `X[!] true`, `!X f` becomes `WX !f`,
    `!(f U g)` becomes `!f R !g`, and `!(f W g)` becomes `!g U (!f & !g)`.

2.  A DFA state after reading a non-empty prefix `w` is a pair
    `(obligation, accepted)`:

    - `accepted` says whether `w |= phi`;
    - `obligation` is a positive Boolean combination, kept in DNF as a set of
      clauses (sets of NNF formulas), such that for every non-empty `v`:
      `w v |= phi  iff  v |= obligation`.

    The initial state is `(dnf(nnf(phi)), False)`: the empty trace is never
    accepted, and `v |= phi` iff `v |= phi`.

3.  Reading a letter `s` from `(obl, _)` gives `(progress(obl, s), at_last(obl, s))`:

    - `at_last(f, s)`: whether `f` holds at a position that carries `s` and is
      the last one.  Then `X f` is false, `WX f` true, `last` true, and every
      temporal operator is decided by its arguments at this position.
    - `progress(f, s)`: a formula that holds at position i+1 iff `f` holds at
      position i, given that i carries `s` and is *not* the last position
      (the classic expansion laws, e.g. `f U g = g | (f & X(f U g))`).

    Both follow directly from the semantics in `symsynth.logic.semantics`.
    The state space is finite: every formula that ever appears in a clause is
    a subformula of `nnf(phi)`, and a DNF over a finite set of elements with
    subsumed clauses removed can take only finitely many values.

4.  `minimize` is Moore's partition refinement over the explicit letters; on
    the reachable, complete DFA it yields the Myhill-Nerode index of
    L(phi) subset of Sigma+ (the class of the empty word counts, non-accepting).

5.  `distinguishing_trace` explores the product of two DFAs breadth first and
    returns a shortest non-empty trace on which they differ, or None.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Collection, Iterable, Iterator, Sequence
from dataclasses import dataclass

from symsynth.logic import ast, holds, parse_ltlf

Letter = frozenset[str]
Clause = frozenset[ast.Formula]
Dnf = frozenset[Clause]

TRUE_DNF: Dnf = frozenset({frozenset()})
FALSE_DNF: Dnf = frozenset()


def letters(atom_keys: Iterable[str]) -> list[Letter]:
    """All 2^n letters over `atom_keys`, each a frozenset of the true atoms."""
    keys = sorted(set(atom_keys))
    return [frozenset(k for k, bit in zip(keys, bits) if bit)
            for bits in itertools.product((False, True), repeat=len(keys))]


def all_traces(atom_keys: Iterable[str], max_length: int) -> Iterator[list[Letter]]:
    """Every trace of length 1..max_length over the letters of `atom_keys`."""
    alphabet = letters(atom_keys)
    for n in range(1, max_length + 1):
        yield from (list(t) for t in itertools.product(alphabet, repeat=n))


def atom_keys(formula: ast.Formula) -> tuple[str, ...]:
    return tuple(a.key for a in ast.atoms(formula))


# --------------------------------------------------------------------- NNF


def nnf(f: ast.Formula, negate: bool = False) -> ast.Formula:
    """Negation normal form of `f` (of `!f` when `negate`)."""
    n = negate
    match f:
        case ast.Const(value):
            return ast.Const(value != n)
        case ast.Last():
            # !last at i  <=>  position i+1 exists  <=>  X[!] true at i
            return ast.Next(ast.TRUE) if n else f
        case ast.Atom():
            return ast.Not(f) if n else f
        case ast.Not(g):
            return nnf(g, not n)
        case ast.Next(g):
            return ast.WeakNext(nnf(g, True)) if n else ast.Next(nnf(g))
        case ast.WeakNext(g):
            return ast.Next(nnf(g, True)) if n else ast.WeakNext(nnf(g))
        case ast.Eventually(g):
            return ast.Always(nnf(g, True)) if n else ast.Eventually(nnf(g))
        case ast.Always(g):
            return ast.Eventually(nnf(g, True)) if n else ast.Always(nnf(g))
        case ast.Until(g, h):
            return ast.Release(nnf(g, True), nnf(h, True)) if n else ast.Until(nnf(g), nnf(h))
        case ast.Release(g, h):
            return ast.Until(nnf(g, True), nnf(h, True)) if n else ast.Release(nnf(g), nnf(h))
        case ast.WeakUntil(g, h):
            if n:  # !(g W h)  ==  !h U (!g & !h)
                return ast.Until(nnf(h, True), ast.And(nnf(g, True), nnf(h, True)))
            return ast.WeakUntil(nnf(g), nnf(h))
        case ast.And(g, h):
            return ast.Or(nnf(g, True), nnf(h, True)) if n else ast.And(nnf(g), nnf(h))
        case ast.Or(g, h):
            return ast.And(nnf(g, True), nnf(h, True)) if n else ast.Or(nnf(g), nnf(h))
        case ast.Implies(g, h):
            return ast.And(nnf(g), nnf(h, True)) if n else ast.Or(nnf(g, True), nnf(h))
        case ast.Equiv(g, h):
            same = ast.And(nnf(g), nnf(h))
            differ_left, differ_right = ast.And(nnf(g), nnf(h, True)), ast.And(nnf(g, True), nnf(h))
            both_false = ast.And(nnf(g, True), nnf(h, True))
            return ast.Or(differ_left, differ_right) if n else ast.Or(same, both_false)
    raise TypeError(f"not an LTLf node: {f!r}")


# --------------------------------------------------------------------- DNF


def _absorb(clauses: Iterable[Clause]) -> Dnf:
    """Drop every clause that contains another one (it adds nothing to the disjunction)."""
    unique = sorted(set(clauses), key=len)
    kept: list[Clause] = []
    for clause in unique:
        if not any(other <= clause for other in kept):
            kept.append(clause)
    return frozenset(kept)


def dnf_or(x: Dnf, y: Dnf) -> Dnf:
    return _absorb(x | y)


def dnf_and(x: Dnf, y: Dnf) -> Dnf:
    return _absorb(cx | cy for cx in x for cy in y)


def dnf(f: ast.Formula) -> Dnf:
    """`f` (in NNF) as a DNF whose elements are the non-Boolean subformulas."""
    match f:
        case ast.Const(value):
            return TRUE_DNF if value else FALSE_DNF
        case ast.And(g, h):
            return dnf_and(dnf(g), dnf(h))
        case ast.Or(g, h):
            return dnf_or(dnf(g), dnf(h))
    return frozenset({frozenset({f})})


# --------------------------------------------------------- progression


def at_last(f: ast.Formula, letter: Letter) -> bool:
    """Whether NNF formula `f` holds at the last position, which carries `letter`."""
    match f:
        case ast.Const(value):
            return value
        case ast.Last():
            return True
        case ast.Atom():
            return f.key in letter
        case ast.Not(ast.Atom() as a):
            return a.key not in letter
        case ast.Next():
            return False
        case ast.WeakNext():
            return True
        case ast.Eventually(g) | ast.Always(g):
            return at_last(g, letter)
        case ast.Until(_, h) | ast.Release(_, h):
            return at_last(h, letter)
        case ast.WeakUntil(g, h):
            return at_last(h, letter) or at_last(g, letter)
        case ast.And(g, h):
            return at_last(g, letter) and at_last(h, letter)
        case ast.Or(g, h):
            return at_last(g, letter) or at_last(h, letter)
    raise TypeError(f"not an NNF node: {f!r}")


def progress(f: ast.Formula, letter: Letter) -> Dnf:
    """What must hold at i+1 for NNF `f` to hold at i (i carries `letter`, i is not last)."""
    single = frozenset({frozenset({f})})  # "f again, one position later"
    match f:
        case ast.Const(value):
            return TRUE_DNF if value else FALSE_DNF
        case ast.Last():
            return FALSE_DNF
        case ast.Atom():
            return TRUE_DNF if f.key in letter else FALSE_DNF
        case ast.Not(ast.Atom() as a):
            return FALSE_DNF if a.key in letter else TRUE_DNF
        case ast.Next(g) | ast.WeakNext(g):
            return dnf(g)  # a next position exists, so both kinds of next agree
        case ast.Eventually(g):  # F g = g | X F g
            return dnf_or(progress(g, letter), single)
        case ast.Always(g):  # G g = g & X G g
            return dnf_and(progress(g, letter), single)
        case ast.Until(g, h) | ast.WeakUntil(g, h):  # g U h = h | (g & X(g U h))
            return dnf_or(progress(h, letter), dnf_and(progress(g, letter), single))
        case ast.Release(g, h):  # g R h = h & (g | X(g R h))
            return dnf_and(progress(h, letter), dnf_or(progress(g, letter), single))
        case ast.And(g, h):
            return dnf_and(progress(g, letter), progress(h, letter))
        case ast.Or(g, h):
            return dnf_or(progress(g, letter), progress(h, letter))
    raise TypeError(f"not an NNF node: {f!r}")


def progress_dnf(obligation: Dnf, letter: Letter) -> Dnf:
    result = FALSE_DNF
    for clause in obligation:
        part = TRUE_DNF
        for element in clause:
            part = dnf_and(part, progress(element, letter))
        result = dnf_or(result, part)
    return result


def at_last_dnf(obligation: Dnf, letter: Letter) -> bool:
    return any(all(at_last(e, letter) for e in clause) for clause in obligation)


# ----------------------------------------------------------------- DFAs


class _Runs:
    """Running a DFA on a trace, given `step`, `initial` and `accepting`."""

    def is_accepting(self, state: int) -> bool:
        return state in self.accepting

    def accepts(self, trace: Sequence[Collection[str]]) -> bool:
        state = self.initial
        for letter in trace:
            state = self.step(state, letter)
        return bool(trace) and self.is_accepting(state)


@dataclass(frozen=True)
class ReferenceDFA(_Runs):
    """An explicit, complete DFA: `delta[state][i]` is the successor on `alphabet[i]`."""

    atoms: tuple[str, ...]
    alphabet: tuple[Letter, ...]
    initial: int
    accepting: frozenset[int]
    delta: tuple[tuple[int, ...], ...]

    @property
    def num_states(self) -> int:
        return len(self.delta)

    def step(self, state: int, letter: Collection[str]) -> int:
        return self.delta[state][self.alphabet.index(frozenset(letter) & frozenset(self.atoms))]


def reference_dfa(formula: ast.Formula) -> ReferenceDFA:
    """The (unminimized, reachable, complete) progression DFA of `formula`."""
    keys = atom_keys(formula)
    alphabet = tuple(letters(keys))
    start = (dnf(nnf(formula)), False)
    index = {start: 0}
    rows: list[tuple[int, ...]] = []
    queue = deque([start])
    while queue:
        obligation, _ = queue.popleft()
        row = []
        for letter in alphabet:
            succ = (progress_dnf(obligation, letter), at_last_dnf(obligation, letter))
            if succ not in index:
                index[succ] = len(index)
                queue.append(succ)
            row.append(index[succ])
        rows.append(tuple(row))
    accepting = frozenset(i for (_, accepted), i in index.items() if accepted)
    return ReferenceDFA(keys, alphabet, 0, accepting, tuple(rows))


def minimize(dfa: ReferenceDFA) -> ReferenceDFA:
    """Moore's algorithm: split blocks by acceptance, then by successor blocks, until stable.

    `dfa` must be complete and every state reachable (true of `reference_dfa`).
    """
    block = [int(s in dfa.accepting) for s in range(dfa.num_states)]
    count = len(set(block))
    while True:
        signature = [(block[s], tuple(block[t] for t in dfa.delta[s]))
                     for s in range(dfa.num_states)]
        ids: dict[tuple, int] = {}
        block = [ids.setdefault(sig, len(ids)) for sig in signature]
        if len(ids) == count:
            break
        count = len(ids)
    rows: dict[int, tuple[int, ...]] = {}
    for s in range(dfa.num_states):
        rows.setdefault(block[s], tuple(block[t] for t in dfa.delta[s]))
    return ReferenceDFA(dfa.atoms, dfa.alphabet, block[dfa.initial],
                        frozenset(block[s] for s in dfa.accepting),
                        tuple(rows[b] for b in range(count)))


def minimal_num_states(formula: ast.Formula) -> int:
    """States of the minimal complete DFA of L(formula) (the Myhill-Nerode index)."""
    return minimize(reference_dfa(formula)).num_states


def _accepting(dfa, state) -> bool:
    is_accepting = getattr(dfa, "is_accepting", None)
    return is_accepting(state) if is_accepting is not None else state in dfa.accepting


def distinguishing_trace(first, second, atom_keys_: Iterable[str]) -> list[Letter] | None:
    """A shortest non-empty trace accepted by exactly one of two DFAs, or None.

    Each DFA needs `.initial`, `.step(state, letter)` and either
    `.is_accepting(state)` or `.accepting`.  Letters range over `atom_keys_`.
    """
    alphabet = letters(atom_keys_)
    start = (first.initial, second.initial)
    parent: dict[tuple, tuple | None] = {start: None}
    queue = deque([start])
    while queue:
        pair = queue.popleft()
        for letter in alphabet:
            succ = (first.step(pair[0], letter), second.step(pair[1], letter))
            if _accepting(first, succ[0]) != _accepting(second, succ[1]):
                trace = [letter]
                node = pair
                while parent[node] is not None:
                    node, previous_letter = parent[node]
                    trace.append(previous_letter)
                return trace[::-1]
            if succ not in parent:
                parent[succ] = (pair, letter)
                queue.append(succ)
    return None


# ------------------------------------------------------ the JSON format


class JsonDFA(_Runs):
    """A DFA read from the documented JSON form, simulated through its guard texts.

    Guards are parsed with `parse_ltlf` and evaluated with `holds` on a
    one-letter trace, so this checks the JSON independently of the BDDs.
    `step` fails unless exactly one guard of the state holds.
    """

    def __init__(self, data: dict):
        self.atoms = tuple(data["atoms"])
        self.initial = data["initial"]
        self.accepting = frozenset(data["accepting"])
        self.edges: dict[int, list[tuple[ast.Formula, int, str]]] = {}
        for t in data["transitions"]:
            guard = parse_ltlf(t["guard"])
            self.edges.setdefault(t["from"], []).append((guard, t["to"], t["guard"]))

    @property
    def states(self) -> set[int]:
        found = {self.initial, *self.accepting, *self.edges}
        found.update(dst for out in self.edges.values() for _, dst, _ in out)
        return found

    def step(self, state: int, letter: Collection[str]) -> int:
        letter = frozenset(letter) & frozenset(self.atoms)
        targets = [dst for guard, dst, _ in self.edges.get(state, []) if holds(guard, [letter])]
        if len(targets) != 1:
            raise AssertionError(f"state {state} on letter {sorted(letter)}: "
                                 f"{len(targets)} enabled transitions, expected exactly 1")
        return targets[0]
