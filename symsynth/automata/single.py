"""One explicit DFA as the state bits of a symbolic one (symbolic.py's
`product` of a single component): a function of the state given state by
state is a decision tree on the bits, and each bit's transition function
is the letters into successors with that bit set, merged over the states
by such a tree.

The bits (lowest first) write a state's number; the codes past the last
state are no state's.  The transition functions may take any value there
(`by_state(..., unreached=True)`): no reachable state leads to them, and
the tree has a node less for each code without a state under its split
(urright14, 169,542 states in 18 bits, has 92,602 such splits on its
deepest bit: its DFA has 11.97 million nodes where it had 13.15 million
with false there).  The acceptance and the reachable set are exact: false
there.
"""

from __future__ import annotations

from collections.abc import Sequence

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function, and_exists
from symsynth.automata.numbered import ARRAYS_FROM
from symsynth.automata.progression import GuardedDFA
from symsynth.automata.rows import each


def bit_functions(bdd: BDD, comp: GuardedDFA, names: Sequence[str]) -> dict[str, Function]:
    """The transition function of each bit `names[j]` of the explicit
    `comp` alone: the letters into successors with bit j set, merged over
    the states by a decision tree on the bits (`by_state`), any value on
    the codes past the last state.

    A DFA given by its moves in `bdd` itself, its bits above the atoms:
    the moves merged over the states the same way are the transition
    relation R(q, a, z), and bit j's function is \\E z: R /\\ z_j, one
    relational product per bit.  (One `and_exists` per state and bit cost
    urright12 1.3 to 2.1 s, 124,584 calls; per bit, 0.2 to 0.55 s.)  A
    large DFA given as one numbered diagram (the backward construction's)
    gets the same functions from it (numbered.py), without R."""
    numbered = comp.numbered
    if comp.bdd is bdd and numbered is not None and len(numbered.var) >= ARRAYS_FROM:
        return numbered.bit_functions(bdd, names)
    if comp.bdd is bdd and not comp.has_edges():
        zs = moves_.bits(bdd, "z", len(names))
        relation = by_state(bdd, names, comp.moves, unreached=True)  # R(q, a, z): T_q(a, z)
        return {n: and_exists(bdd, relation, bdd.var(z), zs) for n, z in zip(names, zs)}  # \E z: R /\ z_j
    ones = _next_bits(bdd, comp, len(names))
    return {n: by_state(bdd, names, ones[j], unreached=True) for j, n in enumerate(names)}


def _next_bits(bdd: BDD, comp: GuardedDFA, width: int) -> list[list[Function]]:
    """`ones[j][s]`: the letters (in `bdd`) after which state `s` of the
    explicit `comp` goes to a successor with bit `j` set."""
    ones: list[list[Function]] = [[bdd.false] * comp.num_states for _ in range(width)]
    if not comp.has_edges():  # given by its moves: bit j's letters in one step for all states
        # (on the moves' stack, rows.py: one step per state was 3 s of Nim nim_06_01's 819 states)
        zs = moves_.bits(comp.bdd, "z", width)
        for j in range(width):
            bit = comp.bdd.var(zs[j])
            found = each(comp.bdd, lambda t: and_exists(comp.bdd, t, bit, zs), comp.moves)  # \E z: T_s & z_j
            ones[j] = [_copied(u, bdd) for u in found]
        return ones
    copied: dict[Function, Function] = {}
    for s, out in enumerate(comp.edges):
        every, some = -1, 0
        for succ in out:
            every &= succ
            some |= succ
        for j in range(width):
            if every >> j & 1:
                ones[j][s] = bdd.true
            elif some >> j & 1:  # the guards are disjoint and cover every letter:
                # the fewer of those into a 1 and into a 0 suffice
                set_ = [guard for succ, guard in out.items() if succ >> j & 1]
                clear = len(set_) * 2 > len(out)
                if clear:
                    set_ = [guard for succ, guard in out.items() if not succ >> j & 1]
                value = bdd.false
                for guard in set_:
                    here = copied.get(guard)
                    if here is None:
                        here = copied[guard] = _copied(guard, bdd)
                    value = value | here
                ones[j][s] = ~value if clear else value
    return ones


def _copied(u: Function, bdd: BDD) -> Function:
    """`u` in `bdd` (itself when it is there already)."""
    return u if u.bdd is bdd else u.bdd.copy(u, bdd)


def by_state(bdd: BDD, names: Sequence[str], values: Sequence[Function], unreached: bool = False) -> Function:
    """The function that is `values[s]` where the bits `names` (lowest
    first) encode `s`: a decision tree on the bits, merged bottom-up by
    `ite` (one node per pair when the values lie below the bits; no
    disjunction grows).  On the codes past the last state it is false, or
    with `unreached` the value of a state below them: the split on a bit
    whose high side has no state is no node."""
    level = list(values)
    for j in reversed(range(len(names))):  # the last bit is the deepest split
        bit, half = bdd.var(names[j]), 1 << j
        merged = [bdd.ite(bit, level[m + half], level[m]) for m in range(min(half, len(level) - half))]
        rest = level[len(merged):min(half, len(level))]  # no state on their high side
        level = merged + (rest if unreached else [bdd.ite(bit, bdd.false, low) for low in rest])
    return level[0]
