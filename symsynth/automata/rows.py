"""Many BDDs as one: the *stack* of functions `u_0, ..., u_{n-1}` is the
BDD that is `u_i` where the row bits read `i`, a decision tree on row bits
declared above every other variable, with the functions below it.

An operation that treats every row alike (a conjunction with, or a
quantification or renaming of, variables other than the rows) applied to
the stack is the stack of its results, so `each` does in one BDD call the
work of one call per function, and every node the functions share is
visited once.  That is what makes renaming cheap: CUDD's variable swap
keeps no cache from one call to the next, so renaming the 2,909 states'
moves of Nim nim_06_01's largest product one at a time visited 9.1 million
nodes, where the stack of them has 0.43 million.

The row bits are inserted at the top of the manager's order the first time
it needs them: the atoms are then no longer at the first levels, and code
that bounds the atom levels asks `below_atoms`.  Without CUDD (no variable
can be inserted above others) they are declared below the others, and
`each` applies the operation row by row."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from symsynth.automata.bdd import BACKEND, BDD, Function, branches, cofactor

#: Row bits: stacks of up to 2^WIDTH functions.
WIDTH = 24
_PREFIX = "#r"  # `#` keeps the bits apart from atom names (not in the grammar)


def is_row(name: str) -> bool:
    return name.startswith(_PREFIX)


def row_bits(bdd: BDD, count: int) -> list[str]:
    """The row bits numbering `count` rows, most significant (and highest)
    first, all WIDTH of them inserted at the top of `bdd`'s order the first
    time."""
    names = [f"{_PREFIX}{i}" for i in range(WIDTH)]
    if names[0] not in bdd.vars:
        if BACKEND == "cudd":
            for level, name in enumerate(names):
                bdd.insert_var(name, level)
        else:  # pragma: no cover - only without CUDD: below the others (`each` makes no stack there)
            bdd.declare(*names)
    size = max(1, (count - 1).bit_length())
    if size > WIDTH:
        raise ValueError(f"more than 2^{WIDTH} rows")
    return names[:size]


def below_atoms(bdd: BDD, atoms: Sequence[str]) -> int:
    """The first level below the atoms `atoms` (declared together, before any
    other variable but the row bits)."""
    return bdd.level_of_var(atoms[-1]) + 1 if atoms else 0


def stack(bdd: BDD, items: Sequence[Function]) -> Function:
    """The stack of `items` (none reads a row bit): `items[i]` under the
    row code `i`, false under the codes past the last."""
    names = row_bits(bdd, len(items))
    layer = list(items)
    for name in reversed(names):  # the least significant bit is the deepest split
        bit = bdd.var(name)
        if len(layer) % 2:
            layer.append(bdd.false)
        layer = [bdd.ite(bit, layer[m + 1], layer[m]) for m in range(0, len(layer), 2)]
    return layer[0]


def unstack(bdd: BDD, u: Function, count: int) -> list[Function]:
    """The first `count` rows of the stack `u`."""
    if BACKEND != "cudd":  # pragma: no cover - only without CUDD (the row bits below the others)
        names = row_bits(bdd, count)
        return [cofactor(bdd, {name: bool(i >> (len(names) - 1 - k) & 1) for k, name in enumerate(names)}, u)
                for i in range(count)]
    layer = [u]
    for name in row_bits(bdd, count):
        split: list[Function] = []
        for node in layer:
            if node.var == name:
                split.extend(branches(bdd, node))
            else:  # (a constant, or a node below: the same on both values)
                split += (node, node)
        layer = split[:count]
    return layer[:count]


def each(bdd: BDD, op: Callable[..., Function], *columns: Sequence[Function]) -> list[Function]:
    """`[op(*row) for row in zip(*columns)]`, as one `op` on the columns'
    stacks: `op` must treat every row alike (read no row bit)."""
    count = len(columns[0])
    if BACKEND != "cudd" or count < 2:  # (the row bits need CUDD's insertion above the atoms)
        return [op(*row) for row in zip(*columns)]
    return unstack(bdd, op(*(stack(bdd, column) for column in columns)), count)
