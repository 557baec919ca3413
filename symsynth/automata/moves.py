"""A state's moves as one BDD: the letters over the atoms, then the successor.

An explicit DFA's state `s` with edges `{t: guard_t}` has the *moves* BDD

    T_s(atoms, z) = OR_t guard_t(atoms) & (z = t)

over the atoms and a binary successor number `z` in bits declared below
every atom (MONA's shared multi-terminal BDDs, with the terminal written in
bits).  The product of two states is then one conjunction, whatever their
numbers of successors (`T_s(atoms, x) & T_t(atoms, y)`, its successor pairs
the cubes below the atom levels), and a state's signature for minimization
is one relational product with the map from states to classes.  The cost of
a product or a minimization is a few BDD operations per state, where the
guards cost one per pair of edges (Nim: 250 x 100 successors per state).

Families of bits, `WIDTH` each, declared together the first time a manager
needs them (below its atoms: every atom must be declared before), in this
order:

    z   a successor's number, in the moves of every DFA (a product's pairs:
        the larger operand's state in the low bits, the other's above)
    c   a class of states (the minimization's partition)

(and rows.py's row bits above the atoms, for stacks of many states).

The order matters: a partition B(z, c) reads the state first.

Bit 0 is the least significant.  These functions work on lists of moves;
`GuardedDFA` (progression.py) keeps either form and converts on demand.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from symsynth.automata.bdd import BDD, Function, and_exists, branches, disjoin, exists, split_letters, swap
from symsynth.automata.refine import refine
from symsynth.automata.rows import each, is_row, row_bits, stack

#: Successors per state on average up to which a DFA's edges (guards) are
#: the better form for products: past it a product works on the moves.
SPARSE_DEGREE = 32
#: Pairs of states a product makes in one step (rows.py), at most.
CHUNK = 1024
#: Bits per family: DFAs of up to 2^WIDTH states.
WIDTH = 24
FAMILIES = ("z", "c")  # in level order
_PREFIX = "#m"  # `#` keeps the bits apart from atom names (not in the grammar)


class TooManyStates(Exception):
    """A DFA past 2^WIDTH states (the successor bits' reach)."""


def width(states: int) -> int:
    """Bits numbering `states` states (at least one)."""
    return max(1, (states - 1).bit_length())


def bits(bdd: BDD, family: str, count: int | None = None) -> list[str]:
    """The names of `family`'s first `count` bits (all WIDTH when omitted),
    declaring every family in `bdd` the first time."""
    first = f"{_PREFIX}z0"
    if first not in bdd.vars:
        bdd.declare(*[f"{_PREFIX}{f}{i}" for f in FAMILIES for i in range(WIDTH)])
    if count is not None and count > WIDTH:
        raise TooManyStates(f"more than 2^{WIDTH} states")
    return [f"{_PREFIX}{family}{i}" for i in range(WIDTH if count is None else count)]


def is_bit(name: str) -> bool:
    return name.startswith(_PREFIX)


def cube(bdd: BDD, names: Sequence[str], value: int) -> Function:
    """The assignment of `value` to the bits `names` (least significant first)."""
    return bdd.cube({name: bool(value >> i & 1) for i, name in enumerate(names)})


def cubes(bdd: BDD, names: Sequence[str], count: int) -> list[Function]:
    """`[cube(bdd, names, value) for value in range(count)]`, each cube
    made from the one of `value >> 1` over the bits below its first (the
    top node of its cube over bits i, i+1, ... is remembered by
    `(i, value >> i)`): an `ite` or two a value, where `cube` asks CUDD
    for one conjunction a bit (1.2 s for urright14's 169,542 states,
    0.48 s this way; load 3.5)."""
    if count > 1 << len(names):
        raise ValueError(f"{count} values do not fit {len(names)} bits")
    below: dict[tuple[int, int], Function] = {(len(names), 0): bdd.true}
    bit = [bdd.var(name) for name in names]
    false = bdd.false
    result = []
    for value in range(count):
        i = 0
        while (i, value >> i) not in below:  # (ends: value >> len(names) is 0)
            i += 1
        node = below[i, value >> i]
        for k in reversed(range(i)):
            node = below[k, value >> k] = bdd.ite(bit[k], node, false) if value >> k & 1 else \
                bdd.ite(bit[k], false, node)  # z_k /\ rest, or !z_k /\ rest
        result.append(node)
    return result


def atom_vars(bdd: BDD) -> list[str]:
    """The variables above the bits (the atoms, and any others declared
    before), but for the row bits (rows.py)."""
    top = bdd.level_of_var(f"{_PREFIX}{FAMILIES[0]}0")
    return [v for v in bdd.vars if bdd.level_of_var(v) < top and not is_row(v)]


# ----------------------------------------------------------------- conversion


def encode_all(bdd: BDD, edges: Sequence[dict[int, Function]]) -> list[Function]:
    """The moves of every state of a DFA with `edges`, over the `z` bits:
    `OR_t guard_t & (z = t)`.  (A plain disjunction, each successor's cube
    made once: faster here than a decision tree on the bits joined by
    `ite` or a balanced disjunction, 0.05 s against 0.22 s and 0.19 s for
    Nim nim_04_01's 8,005 edges.)"""
    names = bits(bdd, "z", width(len(edges)))
    cubes = [cube(bdd, names, t) for t in range(len(edges))]
    result = []
    for out in edges:
        moves = bdd.false
        for t, guard in out.items():
            moves |= guard & cubes[t]
        result.append(moves)
    return result


def decode_all(bdd: BDD, moves: Sequence[Function]) -> list[dict[int, Function]]:
    """The edges (successor -> guard over the atoms) of every state: the
    nodes where a state's moves leave the atom levels are cubes over the
    `z` bits, one per successor (`split_letters`, with one memo for all
    states: they share nodes)."""
    zbits = bits(bdd, "z")
    weight = {name: 1 << i for i, name in enumerate(zbits)}
    top = bdd.level_of_var(zbits[0])  # (the atoms above; no other variable is in the moves)
    number: dict[Function, int] = {}
    below: dict[Function, dict[Function, Function]] = {}
    return [{_number(bdd, leaf, weight, number): guard
             for leaf, guard in split_letters(bdd, root, top, below).items() if leaf != bdd.false}
            for root in moves]


def _number(bdd: BDD, leaf: Function, weight: dict[str, int], memo: dict[Function, int]) -> int:
    """The successor a cube over the `z` bits names (absent bits are 0:
    encode writes every bit of the DFA's width)."""
    found = memo.get(leaf)
    if found is None:
        found, node = 0, leaf
        while node != bdd.true:
            if node == bdd.false or node.var not in weight:
                raise ValueError("a state's moves read an atom below the successor bits")
            low, high = branches(bdd, node)
            if high != bdd.false:
                found |= weight[node.var]
                node = high
            else:
                node = low
        memo[leaf] = found
    return found


def numbers(bdd: BDD, u: Function, names: Sequence[str]) -> list[int]:
    """The numbers (bits `names`, least significant first) whose cubes make
    up `u`, a function of those bits only; in increasing level order of
    the walk, not sorted."""
    level = {name: bdd.level_of_var(name) for name in names}
    order = sorted(range(len(names)), key=lambda i: level[names[i]])
    true, false = bdd.true, bdd.false
    found = []
    stack = [(u, 0, 0)]  # (node, position in `order`, value so far)
    while stack:
        node, i, value = stack.pop()
        if node == false:
            continue
        if i == len(order):
            if node != true:
                raise ValueError("a set of numbers reads other variables")
            found.append(value)
            continue
        j = order[i]
        if node != true and node.var == names[j]:
            low, high = branches(bdd, node)
        else:
            low = high = node
        stack.append((low, i + 1, value))
        stack.append((high, i + 1, value | 1 << j))
    return found


def successors(bdd: BDD, moves: Sequence[Function]) -> list[Function]:
    """Each state's successors, as a set of `z` numbers."""
    atoms = atom_vars(bdd)
    return each(bdd, lambda t: exists(bdd, t, atoms), moves)


def count_edges(bdd: BDD, moves: Sequence[Function]) -> list[int]:
    """Each state's number of successors."""
    w = width(len(moves))
    return [int(bdd.count(s, nvars=w)) for s in successors(bdd, moves)]


def rename(bdd: BDD, moves: Sequence[Function], family: str, count: int) -> list[Function]:
    """`moves` with the successor in the bits of `family` instead of `z`."""
    mapping = dict(zip(bits(bdd, "z", count), bits(bdd, family, count)))
    return [swap(bdd, t, mapping) for t in moves]


# ------------------------------------------------------------------- product


@dataclass
class Machine:
    """A DFA given by its moves, with what its construction learnt on the
    way: each state's successors as a set of numbers (over the `z` bits),
    and their count.  `width` is the number of `z` bits the moves are
    written in.  State `i` is written as the number `codes[i]` in the
    moves (a product's pair codes, `product`), or as `i` itself when
    `codes` is None (then the bits above the DFA's own width are 0)."""

    initial: int
    accepting: list[bool]
    moves: list[Function]
    after: list[Function]
    width: int
    degrees: list[int] | None = None
    codes: list[int] | None = None


def product(bdd: BDD, a_moves: Sequence[Function], a_initial: int, a_accepting: Sequence[bool],
            b_moves: Sequence[Function], b_initial: int, b_accepting: Sequence[bool],
            accept: Callable[[list[bool]], bool],
            grown: Callable[[int, int], None] | None = None) -> Machine:
    """The reachable product of two DFAs given by their moves: its states
    numbered from the initial pair (0) in breadth-first order, their
    acceptance (`accept` of the pair's) and moves.  `grown(states, edges)`
    is called after each state (it may raise to stop).

    A pair is written in the moves as its *code*, the larger operand's
    state in the low `z` bits and the smaller one's above them (`codes`):
    the larger operand's moves are used as they are and the smaller's are
    moved up once, so a pair's moves are one conjunction, and its
    successors one quantification over the atoms, with nothing renamed per
    state.  (Numbering the pairs densely instead took a map from pairs to
    numbers and a relational product through it per state, and renaming
    every state of both operands first: on Nim nim_06_01's 1,460 x 4
    product, 12.7 s, of which 3.9 s renaming; `minimize` makes the numbers
    dense.)"""
    if len(a_moves) < len(b_moves):  # the larger operand in the low bits
        return product(bdd, b_moves, b_initial, b_accepting, a_moves, a_initial, a_accepting,
                       lambda xs: accept([xs[1], xs[0]]), grown)
    wa, wb = width(len(a_moves)), width(len(b_moves))
    if wa + wb > WIDTH:
        raise TooManyStates(f"more than 2^{WIDTH} pairs of states")
    pair_bits = bits(bdd, "z", wa + wb)
    up = dict(zip(pair_bits[:wb], pair_bits[wa:]))  # (wa >= wb: a renaming)
    tb = each(bdd, lambda t: swap(bdd, t, up), b_moves)
    atoms = atom_vars(bdd)
    low = (1 << wa) - 1
    codes = [a_initial | b_initial << wa]
    seen = cube(bdd, pair_bits, codes[0])
    accepting: list[bool] = []
    moves: list[Function] = []
    after: list[Function] = []
    degrees: list[int] = []
    edges = 0
    while len(moves) < len(codes):  # the pairs found and not yet made, all at once (rows.py)
        chunk = codes[len(moves):len(moves) + CHUNK]
        made = each(bdd, lambda u, v: u & v,  # T_s(atoms, z_low) & T_t(atoms, z_high)
                    [a_moves[code & low] for code in chunk], [tb[code >> wa] for code in chunk])
        for code, both, pairs in zip(chunk, made, each(bdd, lambda u: exists(bdd, u, atoms), made)):
            accepting.append(accept([a_accepting[code & low], b_accepting[code >> wa]]))
            new = pairs & ~seen
            if new != bdd.false:
                seen |= new
                codes += sorted(numbers(bdd, new, pair_bits))
            moves.append(both)
            after.append(pairs)
            degrees.append(int(bdd.count(pairs, nvars=wa + wb)))
            if grown is not None:
                edges += degrees[-1]
                grown(len(moves), edges)
    return Machine(0, accepting, moves, after, wa + wb, degrees, codes)


# -------------------------------------------------------------- minimization


def minimize(bdd: BDD, dfa: Machine) -> Machine | None:
    """The minimal DFA of a DFA whose states are all reachable from its
    initial state, numbered densely in its own width, or None when the DFA
    is minimal and numbered so already (never when it has `codes`).

    Partition refinement (`refine.refine`, as progression.minimize), a
    state's signature being its moves with the successor replaced by its
    class: one relational product
    `exists z. T_s(atoms, z) & B(z, c)` with the map B from states to
    classes, updated as classes split, made for all states of a class at
    once on their stack (rows.py).  The states to recompute after a split,
    those with a successor that moved, are one relational product with the
    predecessor relation E(r, z), the stack of every state's successors."""
    moves, accepting = dfa.moves, dfa.accepting
    n = len(moves)
    w = dfa.width
    zs, cs = bits(bdd, "z", w), bits(bdd, "c", width(n))
    zcube = [cube(bdd, zs, k) for k in (range(n) if dfa.codes is None else dfa.codes)]
    relation = stack(bdd, dfa.after)  # E(r, z)
    rows = row_bits(bdd, n)[::-1]  # (least significant first)
    states_z = disjoin(bdd, zcube)
    accepting_z = disjoin(bdd, (zcube[k] for k in range(n) if accepting[k]))
    # B(z, c): the class of each state
    classes = (accepting_z & cube(bdd, cs, 1)) | (states_z & ~accepting_z & cube(bdd, cs, 0))

    def signatures(states: list[int], block: list[int]) -> list[Function]:
        return each(bdd, lambda t: and_exists(bdd, t, classes, zs), [moves[s] for s in states])  # \E z: T_s & B(z, c)

    def renumbered(part: list[int], new: int) -> None:
        nonlocal classes
        here = disjoin(bdd, (zcube[state] for state in part))
        classes = (classes & ~here) | (here & cube(bdd, cs, new))

    def predecessors(states: list[int]) -> list[int]:
        moved = disjoin(bdd, (zcube[state] for state in states))
        return numbers(bdd, and_exists(bdd, relation, moved, zs), rows)  # \E z: E(r, z) & Moved(z)

    block = refine(accepting, signatures, predecessors, renumbered)
    if len(set(block)) == n and dfa.codes is None:
        return None
    # classes numbered by their first state (the initial one's first): the
    # input's breadth-first order carries over
    final: dict[int, int] = {block[dfa.initial]: 0}
    for state in range(n):
        final.setdefault(block[state], len(final))
    fw = width(len(final))
    fs = bits(bdd, "c", fw)
    renumber = disjoin(bdd, (zcube[state] & cube(bdd, fs, final[block[state]]) for state in range(n)))
    back = dict(zip(fs, bits(bdd, "z", fw)))
    first: dict[int, int] = {}
    for state in range(n):
        first.setdefault(final[block[state]], state)
    reps = [first[c] for c in range(len(final))]

    def quotient(t: Function) -> Function:
        return swap(bdd, and_exists(bdd, t, renumber, zs), back)  # (\E z: T(atoms, z) & R(z, c))[c := z]

    after = each(bdd, quotient, [dfa.after[r] for r in reps])
    return Machine(0, [accepting[r] for r in reps], each(bdd, quotient, [moves[r] for r in reps]),
                   after, fw, [int(bdd.count(a, nvars=fw)) for a in after])
