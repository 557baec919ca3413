"""Explicit products of minimal DFAs (`GuardedDFA`) and what keeps them
minimal: the product of two DFAs under a Boolean operator, from their guards
or their moves, of many components at once, the complement, and the
non-empty-trace rule (a DFA never accepts at its start).  Each result is
minimized (`progression.minimize`).  Limits: `tuning.py`."""

from __future__ import annotations

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function
from symsynth.automata.growth import grew
from symsynth.automata.prefix import prefix_product, prefix_product_moves
from symsynth.automata.progression import GuardedDFA, TooDense, TooLarge, minimize
from symsynth.automata.tuning import DENSE_AFTER, MOVES_DEGREE, MOVES_PAIRS, PREFIX_STATES

#: Boolean operators of the skeleton, as functions of the operands' acceptance.
OPS = {
    "and": lambda xs: all(xs),
    "or": lambda xs: any(xs),
    "implies": lambda xs: (not xs[0]) or xs[1],
    "equiv": lambda xs: xs[0] == xs[1],
    "not": lambda xs: not xs[0],
}




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
        return moves_product(a, b, op, max_edges)
    for big, small in ((a, b), (b, a)):  # (`&` and `|` are symmetric)
        if op in ("and", "or") and small.num_states <= PREFIX_STATES < big.num_states:
            done = prefix_product(big, small, op, max_edges)
            if done is not None:
                return done
    bdd, accept = a.bdd, OPS[op]
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
            early = check_growth(len(edges), count, early, max_edges, max_degree)
        except TooDense:  # each edge costs a guard: the moves cost per state
            return moves_product(a, b, op, max_edges)
    return minimize(reject_at_start(GuardedDFA(bdd, 0, accepting, edges)))


def moves_product(a: GuardedDFA, b: GuardedDFA, op: str, max_edges: int | None) -> GuardedDFA:
    """`explicit_product` on the operands' moves (moves.product); no limit
    on successors per state (a state's moves are one BDD however many)."""

    def grown(states: int, edges: int) -> None:
        check_growth(states, edges, 0, max_edges, None)

    bdd = a.bdd
    try:
        made = moves_.product(bdd, a.moves, a.initial, a.accepting, b.moves, b.initial, b.accepting,
                              OPS[op], grown)
    except moves_.TooManyStates as error:
        raise TooLarge(str(error)) from None
    if made.accepting[0]:  # (an implication, a disjunction with a negation)
        start = moves_.cube(bdd, moves_.bits(bdd, "z", made.width), made.codes[0] if made.codes else 0)
        if any(succ & start != bdd.false for succ in made.after):  # entered again: a fresh start
            dense = moves_.minimize(bdd, made) or made  # (numbered densely: `made` has no codes)
            return minimize(reject_at_start(GuardedDFA(bdd, 0, dense.accepting, moves=dense.moves,
                                                        degrees=dense.degrees)))
        made.accepting[0] = False
    found = moves_.minimize(bdd, made) or made  # (None: minimal, and dense)
    return GuardedDFA(bdd, 0, found.accepting, moves=found.moves, degrees=found.degrees)


def check_growth(states: int, count: int, early: int, max_edges: int | None,
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
        accepting.append(fold(acceptance, lambda d: d.accepting[states[position[id(d)]]],
                               lambda op, xs: OPS[op](xs)))
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
        early = check_growth(len(edges), count, early, max_edges, max_degree)
    return minimize(reject_at_start(GuardedDFA(bdd, 0, accepting, edges)))


def complement(a: GuardedDFA) -> GuardedDFA:
    """The minimal DFA of the non-empty traces `a` rejects."""
    flipped = GuardedDFA(a.bdd, a.initial, [not x for x in a.accepting],
                         a.edges if a.has_edges() else None, moves=None if a.has_edges() else a.moves)
    return minimize(reject_at_start(flipped))


def reject_at_start(dfa: GuardedDFA) -> GuardedDFA:
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
    """`reject_at_start` of a DFA given by its moves (no edges made)."""
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


def is_empty(dfa: GuardedDFA) -> bool:
    """Whether the minimal `dfa` accepts no trace (one rejecting state)."""
    return dfa.num_states == 1 and not dfa.accepting[0]


def is_universal(dfa: GuardedDFA) -> bool:
    """Whether the minimal `dfa` accepts every non-empty trace (`started`)."""
    if dfa.num_states != 2:
        return False
    start, other = dfa.initial, 1 - dfa.initial
    true = dfa.bdd.true
    return (not dfa.accepting[start] and dfa.accepting[other]
            and dfa.edges[start] == {other: true} and dfa.edges[other] == {other: true})


def started(bdd: BDD) -> GuardedDFA:
    """Two states: the start, and 'at least one letter read' (accepting)."""
    return GuardedDFA(bdd, 0, [False, True], [{1: bdd.true}, {1: bdd.true}])


def fold(expr: tuple, leaf, apply):
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
