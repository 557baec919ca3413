"""The moves of every state of an explicit DFA as one shared decision diagram
over the atoms whose leaves are state numbers (MONA's shared multi-terminal
BDDs), held in arrays: what the backward construction walks (backward.py).
A state's moves BDD (moves.py) and the transition bits of the symbolic DFA
(single.py) are both made from it.

Bit j's transition function is the diagram with each leaf replaced by bit j
of its number, merged over the states by `single.by_state`'s tree.  Through
the transition relation R(q, a, z) that is one relational product per bit,
`\\E z: R /\\ z_j`, each a pass over all of R (urright14: 18 passes over 2.0
million nodes, 1.2-1.6 s each, most of it CUDD's computed and unique tables).
Here the reduction is done on the arrays, a bit at a time, level by level
from the bottom (numpy): a node whose children are equal is its
child; one whose high child is complemented is the complement of the node
with both children complemented (CUDD's canonical form: a then-edge is never
complemented); equal (low, high) pairs at one level are one node.  Each node
of the result is then made once, by an `ite` whose children exist (CUDD
makes it with one lookup in its unique table).  The functions are the same
BDDs: a reduced, ordered BDD with complemented edges is canonical.
"""

from __future__ import annotations

from array import array
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function, branches

if TYPE_CHECKING:
    import numpy as np

#: Inner nodes from which single.bit_functions takes the arrays, worth numpy's
#: import (0.1-0.2 s) there.  CPU seconds, the moves and the relational
#: products against the arrays (load 4-5): urright12 (63,148 inner nodes)
#: 0.49 against 0.41, urright13 (321,952) 3.78 against 2.61.
ARRAYS_FROM = 200_000


@dataclass(frozen=True)
class Numbered:
    """The moves of `len(roots)` states over `atoms` (top first).  An id
    below `num_states` is a leaf, that state; id `num_states + k` is inner
    node k, which reads `atoms[var[k]]` and goes to `low[k]` / `high[k]`
    (ids of nodes listed before it, or leaves).  `roots[s]`: the id of
    state s's moves."""

    atoms: Sequence[str]
    var: Sequence[int]
    low: Sequence[int]
    high: Sequence[int]
    roots: Sequence[int]

    @property
    def num_states(self) -> int:
        return len(self.roots)

    def moves(self, bdd: BDD) -> list[Function]:
        """Each state's moves BDD (moves.py): the diagram with each leaf
        replaced by the cube of its number, one `ite` per inner node."""
        n = self.num_states
        written = moves_.cubes(bdd, moves_.bits(bdd, "z", moves_.width(n)), n)
        ite, x = bdd.ite, [bdd.var(a) for a in self.atoms]
        for v, low, high in zip(self.var, self.low, self.high):
            written.append(ite(x[v], written[high], written[low]))
        return [written[r] for r in self.roots]

    def bit_functions(self, bdd: BDD, names: Sequence[str]) -> dict[str, Function]:
        """The transition function of each state bit `names[j]` (lowest
        first, above the atoms in `bdd`): `by_state(bdd, names, [moves
        with leaves := bit j of their number], unreached=True)`, made
        by the reduction of the module docstring, one bit after the other
        (the Python objects of one bit's nodes at a time: all bits' at once
        took urright14 2.1 GB where the relational products took 1.3 GB)."""
        import numpy as np

        n, var = self.num_states, np.asarray(self.var, dtype=np.int64)
        children = np.asarray(self.low, dtype=np.int64), np.asarray(self.high, dtype=np.int64)
        by_level = np.argsort(var, kind="stable")
        ends = np.cumsum(np.bincount(var, minlength=len(self.atoms))).tolist()
        starts = [0] + ends[:-1]
        levels = [(self.atoms[a], by_level[starts[a]:ends[a]])
                  for a in reversed(range(len(self.atoms))) if ends[a] > starts[a]]
        numbers, roots = np.arange(n, dtype=np.int64), np.asarray(self.roots, dtype=np.int64)
        functions = {}
        for j, name in enumerate(names):
            edges = np.empty(n + len(var), dtype=np.int64)  # edges[id]: node id with leaves := bit j
            edges[:n] = 1 - (numbers >> j & 1)  # true (edge 0) where bit j is set, else false (1)
            functions[name] = _made(bdd, *_reduced(names, edges, levels, children, roots))
        return functions


class Listing:
    """The diagram of `Numbered` as a walk meets it: the states (the nodes
    where paths leave the atom levels, levels below `top`) numbered in the
    order a depth-first walk (high branch first) of each state's successor
    BDD T meets them, T's nodes at atom levels listed children first, each
    node walked once over all the walks.

    Nodes are held by their integer ids (`int(u)`: CUDD's pointer and
    complement bit), each mapped to its code: a state's number, or `-1 - k`
    for listed node k; the listed nodes in machine integer arrays.  The
    latest codes are in a dict (about 100 bytes an entry); past `recent`
    of them, after a walk, they move to sorted arrays (12 bytes an entry;
    a lookup there is a binary search, slower).  An id stands for its node
    only while the node lives: the caller keeps every T given to `walk`
    (its nodes) and the states (`order`) until the diagram is made."""

    def __init__(self, bdd: BDD, top: int, start: Function, recent: int = 1 << 23) -> None:
        self.bdd, self.top, self.recent = bdd, top, recent
        self.order = [start]  # the states, by number
        self.codes = {int(start): 0}
        self.old: tuple[np.ndarray, np.ndarray] | None = None  # (sorted ids, their codes)
        self.var, self.low, self.high = array("i"), array("q"), array("q")
        self.roots = array("q")  # each walked T's code

    def walk(self, t: Function) -> Iterator[Function]:
        """T's states not met before, numbered (appended to `order`) and
        given as they are met; T's nodes at atom levels not met before
        listed, each once its children have codes.  (Walk to the end.)"""
        bdd, codes, top, order = self.bdd, self.codes, self.top, self.order
        var, low, high = self.var, self.low, self.high
        true, false = bdd.true, bdd.false
        code = self._code
        stack: list[Any] = [t]
        while stack:
            node = stack.pop()
            if type(node) is tuple:  # (its subtree is done)
                key, level, lo, hi = node
                codes[key] = -1 - len(var)
                var.append(level)
                low.append(cast(int, code(lo)))  # (children have codes by now)
                high.append(cast(int, code(hi)))
                continue
            key = int(node)
            if code(key) is not None:
                continue
            if node == true or node == false or node.level >= top:
                codes[key] = len(order)
                order.append(node)
                yield node
            else:
                lo, hi = branches(bdd, node)
                stack.append((key, node.level, int(lo), int(hi)))
                stack += (lo, hi)  # (high popped first)
        self.roots.append(cast(int, code(int(t))))
        if len(codes) >= self.recent:
            self._age()

    def _code(self, key: int) -> int | None:
        """The code of id `key`, None for an id not met."""
        found = self.codes.get(key)
        if found is not None or self.old is None:
            return found
        keys, values = self.old
        i = int(keys.searchsorted(key))  # (the array's method: no import on this path, run per node)
        return int(values[i]) if i < len(keys) and keys[i] == key else None

    def _age(self) -> None:
        """The dict's codes moved into the sorted arrays."""
        import numpy as np

        codes = self.codes
        keys = np.fromiter(codes.keys(), np.int64, len(codes))
        values = np.fromiter(codes.values(), np.int32, len(codes))
        codes.clear()
        by_key = np.argsort(keys)
        keys, values = keys[by_key], values[by_key]
        if self.old is not None:
            where = np.searchsorted(self.old[0], keys)
            keys, values = np.insert(self.old[0], where, keys), np.insert(self.old[1], where, values)
        self.old = keys, values

    def numbered(self, atoms: Sequence[str]) -> Numbered:
        """The diagram (atoms top first: a listed node's level is its
        atom's position), each walked T a root: listed node k gets id
        `num_states + k`.  The listing ends here (its ids are dropped)."""
        n = len(self.order)
        self.codes.clear()
        self.old = None
        for codes in (self.low, self.high, self.roots):
            if len(codes) >= ARRAYS_FROM:
                import numpy as np

                ids = np.frombuffer(codes, dtype=np.int64)  # (a view: changed in place)
                inner = ids < 0
                ids[inner] = n - 1 - ids[inner]
            else:
                codes[:] = array("q", [c if c >= 0 else n - 1 - c for c in codes])
        return Numbered(atoms, self.var, self.low, self.high, self.roots)


def _reduced(names: Sequence[str], edges: np.ndarray, levels: list[tuple[str, np.ndarray]],
             children: tuple[np.ndarray, np.ndarray], roots: np.ndarray) -> tuple[list, int]:
    """One bit: the nodes to make, bottom-up, as (variable, low edges, high
    edges), and the edge of the function.  `edges` holds the leaves' edges
    and gets the inner nodes' (`levels`: each atom's inner nodes, the
    deepest atom first)."""
    import numpy as np

    n, (low, high) = len(roots), children
    made: list[tuple[str, np.ndarray, np.ndarray]] = []
    reduce = _Reduction()
    for atom, inner in levels:  # children before parents
        edges[n + inner] = reduce(atom, edges[low[inner]], edges[high[inner]], made)
    level = edges[roots]  # each state's function
    for j in reversed(range(len(names))):  # by_state: the last bit is the deepest split
        half = 1 << j
        pairs = min(half, len(level) - half)  # (past them: no state on the high side, no node)
        if pairs > 0:
            level = np.concatenate([reduce(names[j], level[:pairs], level[half:half + pairs], made),
                                    level[pairs:half]])
    return made, int(level[0])


def _made(bdd: BDD, made: list[tuple[str, np.ndarray, np.ndarray]], edge: int) -> Function:
    """The nodes of `made` in `bdd` (children first), and the function at
    `edge` (2 * node + complemented; node 0 the constant true)."""
    nodes = [bdd.true]
    ite = bdd.ite
    for name, low, high in made:
        x = bdd.var(name)
        nodes += [ite(x, nodes[h >> 1], ~nodes[l >> 1] if l & 1 else nodes[l >> 1])
                  for l, h in zip(low.tolist(), high.tolist())]  # (h is never complemented)
    return ~nodes[edge >> 1] if edge & 1 else nodes[edge >> 1]


class _Reduction:
    """One level of the reduction: numbers the new nodes from 1 on."""

    def __init__(self) -> None:
        self.made = 1  # (node 0: the constant)

    def __call__(self, name: str, low: np.ndarray, high: np.ndarray, made: list) -> np.ndarray:
        """The edges of the nodes (name, low, high), elementwise; the
        distinct new nodes appended to `made` as (name, low edges, high
        edges), the high ones never complemented."""
        import numpy as np

        result = low.copy()
        split = low != high
        flip = high[split] & 1
        key = ((low[split] ^ flip) << 32) | (high[split] ^ flip)
        distinct, which = np.unique(key, return_inverse=True)
        result[split] = (self.made + which) << 1 | flip
        made.append((name, distinct >> 32, distinct & 0xFFFFFFFF))
        self.made += len(distinct)
        return result
