"""Prefix products: the minimal DFA of `big & small` or `big | small` when
`small` looks a bounded number of letters ahead (its states other than its
sinks form no cycle: a condition on the first letters, such as a counter's
initial value), made from the last letters to the first in about one pass
over `big`'s edges, from its guards (`prefix_product`) or its moves
(`prefix_product_moves`)."""

from __future__ import annotations

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function, and_exists, disjoin, exists, swap
from symsynth.automata.progression import GuardedDFA, TooLarge
from symsynth.automata.rows import each

def sink_states(dfa: GuardedDFA) -> tuple[int | None, int | None]:
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
    """The states of `dfa` other than its sinks (`sink_states`), each after its
    successors (a reverse topological order), or None when they form a
    cycle (the DFA does not look a bounded number of letters ahead)."""
    sinks = {s for s in sink_states(dfa) if s is not None}
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
    accept_sink, reject_sink = sink_states(small)
    sinks = {s for s in (accept_sink, reject_sink) if s is not None}
    table = _Table(big)
    # the language of (q, sink): q's own, or a constant
    keeps = accept_sink if op == "and" else reject_sink
    other = reject_sink if op == "and" else accept_sink
    combine = all if op == "and" else any
    start = (big.initial, small.initial)
    if small.initial in sinks:
        initial = big.initial if small.initial == keeps else table.constant(op == "or")
        return _renumbered(big.bdd, initial, table.accepting, table.edges)
    steps = _prefix_pairs(big, small, start, sinks, max_edges)
    rank = {s: i for i, s in enumerate(order)}
    canonical: dict[tuple[int, int], int] = {}
    for q, s in sorted(steps, key=lambda pair: rank[pair[1]]):  # successors first
        out: dict[int, Function] = {}
        for q2, s2, guard in steps[(q, s)]:
            if s2 == keeps:
                target = q2
            elif s2 == other:
                target = table.constant(op == "or")
            else:
                target = canonical[(q2, s2)]
            out[target] = out[target] | guard if target in out else guard
        canonical[(q, s)] = table.state(q, combine((big.accepting[q], small.accepting[s])), out)
    return _renumbered(big.bdd, canonical[start], table.accepting, table.edges)


def _prefix_pairs(big: GuardedDFA, small: GuardedDFA, start: tuple[int, int], sinks: set[int],
                  max_edges: int | None) -> dict[tuple[int, int], list[tuple[int, int, Function]]]:
    """The pairs reachable from `start` before `small` is in a sink, with
    their edges: (successor in `big`, successor in `small`, guard)."""
    false = big.bdd.false
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
    return steps


class _Table:
    """`big`'s states and the states `prefix_product` adds after them, each
    made once: a state with the acceptance and edges of one already there is
    that one (`big` is minimal, so two states with canonical successors are
    equivalent iff those agree)."""

    def __init__(self, big: GuardedDFA):
        self.big, self.n = big, big.num_states
        self.accepting = list(big.accepting)
        self.edges: list[dict[int, Function]] = list(big.edges)
        self.sinks = dict(zip((True, False), sink_states(big)))
        self.made: dict[tuple, int] = {}  # (accepting, edges) of a state added -> the state
        self.preds: list[list[int]] | None = None  # of `big`'s states, made when first needed

    def constant(self, value: bool) -> int:
        """The state of the universal (`value`) or the empty language."""
        found = self.sinks[value]
        if found is None:
            found = self.sinks[value] = self._add(value, {len(self.accepting): self.big.bdd.true})
        return found

    def state(self, q: int, value: bool, out: dict[int, Function]) -> int:
        """The state with acceptance `value` and edges `out`, made when new
        (`q`: `big`'s state of the pair, the likeliest match)."""
        key = (value, frozenset(out.items()))
        found = self.made.get(key)
        if found is None:
            found = self._existing(q, value, out)
        if found is None:
            found = self._add(value, out)
        return found

    def _add(self, value: bool, out: dict[int, Function]) -> int:
        state = len(self.accepting)
        self.accepting.append(value)
        self.edges.append(out)
        self.made[(value, frozenset(out.items()))] = state
        return state

    def _existing(self, q: int, value: bool, out: dict[int, Function]) -> int | None:
        """A state of `big` with acceptance `value` and edges `out`: one of
        the states with an edge into `out`'s first target."""
        accepting, edges = self.accepting, self.edges
        if q < self.n and accepting[q] == value and edges[q] == out:
            return q  # (most often: the condition met, the state goes on as `big`'s)
        first = next(iter(out))
        if first >= self.n:  # a state added: only those are its predecessors
            return None
        if self.preds is None:
            self.preds = [[] for _ in range(self.n)]
            for state in range(self.n):
                for succ in self.big.edges[state]:
                    self.preds[succ].append(state)
        for state in self.preds[first]:
            if accepting[state] == value and edges[state] == out:
                return state
        return None


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
    accept_sink, reject_sink = sink_states(small)
    sinks = {s for s in (accept_sink, reject_sink) if s is not None}
    if small.initial in sinks:
        return None  # (an operand that decides the product: `Composer._settled`'s)
    keeps = accept_sink if op == "and" else reject_sink
    combine = all if op == "and" else any
    bdd = big.bdd
    false = bdd.false
    n, T = big.num_states, big.moves
    w = moves_.width(n)
    narrow = moves_.bits(bdd, "z", w)
    start = (big.initial, small.initial)
    steps = _prefix_pairs_moves(big, small, start, sinks, narrow)
    # numbers: `big`'s states, the constant when `big` has no such sink, the pairs made
    value = op == "or"  # the constant language: universal for `or`, empty for `and`
    constant = sink_states(big)[0 if value else 1]
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


def _prefix_pairs_moves(big: GuardedDFA, small: GuardedDFA, start: tuple[int, int], sinks: set[int],
                        narrow: list[str]) -> dict[tuple[int, int], list[tuple[int, Function, Function, list[int]]]]:
    """`_prefix_pairs` for a `big` given by its moves (successors numbered on
    the bits `narrow`): each pair's parts, (successor in `small`, its guard,
    `big`'s moves under that guard, `big`'s successors there: none into a
    sink of `small`)."""
    bdd = big.bdd
    atoms = moves_.atom_vars(bdd)
    steps: dict[tuple[int, int], list[tuple[int, Function, Function, list[int]]]] = {}
    todo = [start]
    while todo:
        q, s = pair = todo.pop()
        if pair in steps:
            continue
        out = steps[pair] = []
        for s2, g2 in small.edges[s].items():
            part = big.moves[q] & g2
            if part == bdd.false:
                continue
            after = [] if s2 in sinks else moves_.numbers(bdd, exists(bdd, part, atoms), narrow)
            out.append((s2, g2, part, after))
            todo.extend((q2, s2) for q2 in after if (q2, s2) not in steps)
    return steps


def _renumbered_moves(big: GuardedDFA, initial: int, accepting: list[bool], moves: list[Function],
                      wide: dict[int, Function], width: int) -> GuardedDFA:
    """The states reachable from `initial` of `big`'s states and the ones
    made after them (their moves in `width` bits, `wide`), numbered in
    breadth-first order from `initial` and written in their own width.
    Each state's successors are found by one quantification of all the
    moves' stack (rows.py), and only the successors not seen before are
    listed (each state once in all)."""
    bdd = big.bdd
    atoms = moves_.atom_vars(bdd)
    zs = moves_.bits(bdd, "z", width)
    zero = bdd.true  # the bits `big`'s moves do not write
    for name in zs[moves_.width(big.num_states):]:
        zero &= ~bdd.var(name)
    narrow = [state for state in range(len(moves)) if state not in wide]
    zeroed = dict(zip(narrow, each(bdd, lambda t: t & zero, [moves[state] for state in narrow])))
    full = [wide[state] if state in wide else zeroed[state] for state in range(len(moves))]  # in `width` bits
    after = each(bdd, lambda t: exists(bdd, t, atoms), full)
    order, seen = [initial], moves_.cube(bdd, zs, initial)
    for state in order:  # grows while walked
        new = after[state] & ~seen
        if new != bdd.false:
            seen |= new
            order += moves_.numbers(bdd, new, zs)  # (in the walk's order, as listing all of them gives)
    degrees = [int(bdd.count(after[state], nvars=width)) for state in order]
    if len(order) == len(moves):  # all reachable: numbered as they are, the start where it is (no
        # renaming, a swap per state: 5 s of Nim nim_06_01's 819 states), the bits past their width dropped
        high = zs[moves_.width(len(moves)):]
        per_state = dict(zip(order, degrees))
        kept = each(bdd, lambda t: exists(bdd, t, high), full) if high else full
        return GuardedDFA(bdd, initial, accepting, moves=kept, degrees=[per_state[old] for old in range(len(moves))])
    fw = moves_.width(len(order))
    cs = moves_.bits(bdd, "c", fw)
    table = disjoin(bdd, (moves_.cube(bdd, zs, old) & moves_.cube(bdd, cs, new) for new, old in enumerate(order)))
    rename = dict(zip(cs, moves_.bits(bdd, "z", fw)))
    result = each(bdd, lambda t: swap(bdd, and_exists(bdd, t, table, zs), rename),  # (\E z: T & R(z, c))[c := z]
                  [full[old] for old in order])
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
