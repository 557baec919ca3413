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
Here the reduction is done on the arrays for all bits at once, level by
level from the bottom (numpy): a node whose children are equal is its
child; one whose high child is complemented is the complement of the node
with both children complemented (CUDD's canonical form: a then-edge is never
complemented); equal (low, high) pairs at one level are one node.  Each node
of the result is then made once, by an `ite` whose children exist (CUDD
makes it with one lookup in its unique table).  The functions are the same
BDDs: a reduced, ordered BDD with complemented edges is canonical.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import BDD, Function

if TYPE_CHECKING:
    import numpy as np

#: Inner nodes from which `bit_functions` is worth numpy's import (0.1-0.2 s):
#: urright12 (63,000 inner nodes) takes as long either way, urright14
#: (1.51 million) 19 s where the relational products took 27 s.
ARRAYS_FROM = 200_000


@dataclass(frozen=True)
class Numbered:
    """The moves of `len(roots)` states over `atoms` (top first).  An id
    below `num_states` is a leaf, that state; id `num_states + k` is inner
    node k, which reads `atoms[var[k]]` and goes to `low[k]` / `high[k]`
    (ids of nodes listed before it, or leaves).  `roots[s]`: the id of
    state s's moves."""

    atoms: Sequence[str]
    var: list[int]
    low: list[int]
    high: list[int]
    roots: list[int]

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
        by the reduction of the module docstring."""
        import numpy as np

        width = len(names)
        made: list[tuple[str, Any, Any]] = []  # (variable, low edges, high edges): the nodes to make, bottom-up
        reduce = _Reduction()
        edges = self._atom_levels(width, made, reduce)
        level = edges[:, np.asarray(self.roots, dtype=np.int64)]  # (bit, state): each state's function
        for j in reversed(range(width)):  # by_state: the last bit is the deepest split
            half = 1 << j
            pairs = min(half, level.shape[1] - half)  # (past them: no state on the high side, no node)
            if pairs <= 0:
                continue
            merged = reduce(names[j], level[:, :pairs], level[:, half:half + pairs], made)
            level = np.concatenate([merged, level[:, pairs:half]], axis=1)
        nodes = [bdd.true]  # node 0 is the constant true; an edge is 2 * node + complemented
        for name, low, high in made:  # children first
            x, ite = bdd.var(name), bdd.ite
            nodes += [ite(x, nodes[h >> 1], ~nodes[l >> 1] if l & 1 else nodes[l >> 1])
                      for l, h in zip(low.tolist(), high.tolist())]  # (h is never complemented)
        roots = level[:, 0].tolist()
        return {name: ~nodes[e >> 1] if e & 1 else nodes[e >> 1] for name, e in zip(names, roots)}

    def _atom_levels(self, width: int, made: list, reduce: _Reduction) -> np.ndarray:
        """edges[j, id]: the edge of node `id` with leaves := bit j of their
        number, the nodes at atom levels reduced (and listed in `made`)."""
        import numpy as np

        n, var = self.num_states, np.asarray(self.var, dtype=np.int64)
        low, high = np.asarray(self.low, dtype=np.int64), np.asarray(self.high, dtype=np.int64)
        edges = np.empty((width, n + len(var)), dtype=np.int64)
        numbers = np.arange(n, dtype=np.int64)
        for j in range(width):
            edges[j, :n] = 1 - (numbers >> j & 1)  # true (edge 0) where bit j is set, else false (1)
        by_level = np.argsort(var, kind="stable")
        ends = np.cumsum(np.bincount(var, minlength=len(self.atoms)))
        for a in reversed(range(len(self.atoms))):  # deepest first: children before parents
            inner = by_level[(ends[a - 1] if a else 0):ends[a]]
            if len(inner):
                edges[:, n + inner] = reduce(self.atoms[a], edges[:, low[inner]], edges[:, high[inner]], made)
        return edges


class _Reduction:
    """One level of the reduction: numbers the new nodes from 1 on."""

    def __init__(self) -> None:
        self.made = 1  # (node 0: the constant)

    def __call__(self, name: str, low: np.ndarray, high: np.ndarray, made: list) -> np.ndarray:
        """The edges of the nodes (name, low, high), elementwise (any shape);
        the distinct new nodes appended to `made` as (name, low edges, high
        edges), the high ones never complemented."""
        import numpy as np

        result = low.copy()
        split = low != high
        flip = high[split] & 1
        key = ((low[split] ^ flip) << 32) | (high[split] ^ flip)
        distinct, which = np.unique(key, return_inverse=True)
        result[split] = (self.made + which.reshape(-1)) << 1 | flip
        made.append((name, distinct >> 32, distinct & 0xFFFFFFFF))
        self.made += len(distinct)
        return result
