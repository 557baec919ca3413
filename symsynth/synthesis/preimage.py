"""The game's one-step predecessor as a relational product.

    G(delta(q, x, y)) = \\E q': T(q, x, y, q') /\\ G(q'),   T = /\\_b (q'_b <-> delta_b(q, x, y))

`bdd.let(delta, G)` (CUDD's vector compose) computes the left side with an
if-then-else of a whole `delta_b` at every node of G, so each round of the
fixpoint pays for every transition function again (Double-Counter 05: 17 of
its 18 s after the DFA).  Here T is built once, as *clusters*: neighbouring
conjuncts (in bit order) are conjoined pairwise, level by level (a balanced
tree: 1.9 s for Double-Counter 06's T, against 3.7 s one conjunct after the
other), where the conjunction has at most `limit` nodes; each primed bit is
quantified in the one cluster that reads it (no other does):

    \\E q': G(q') /\\ C_1 /\\ ... /\\ C_k
        = \\E q'(C_k): (... \\E q'(C_1): (G(q') /\\ C_1) ...) /\\ C_k

With `limit` 0 every conjunct is its own cluster (the partitioned relation);
when every conjunct fits in one, T is monolithic.  The product is
distributive over `|` in G, which the fixpoint uses: it takes the preimage of
the states new in each round only.
"""

from __future__ import annotations

from symsynth.automata.bdd import Function, and_exists
from symsynth.automata.symbolic import SymbolicDFA, prime

#: A cluster grows while it has at most this many BDD nodes (Double-Counter
#: 06, 16,389 states: its monolithic T has 708,000).
CLUSTER_NODES = 1 << 20


class Preimage:
    """`preimage(G)` = G(delta(q, x, y)) for a BDD G over the DFA's state bits."""

    def __init__(self, dfa: SymbolicDFA, limit: int = CLUSTER_NODES):
        bdd = self.bdd = dfa.bdd
        self.primed = {b: prime(b) for b in dfa.bits}
        # (C_j, the primed bits only C_j reads); first one conjunct per bit
        level = [(bdd.apply("<=>", bdd.var(prime(b)), dfa.delta[b]), {prime(b)})  # q'_b <-> delta_b(q, x, y)
                 for b in dfa.bits]
        joined = True
        while joined and len(level) > 1:  # neighbours conjoined pairwise, a balanced tree
            joined, merged, i = False, [], 0
            while i < len(level):
                if i + 1 < len(level):
                    both = level[i][0] & level[i + 1][0]
                    if len(both) <= limit:
                        merged.append((both, level[i][1] | level[i + 1][1]))
                        joined, i = True, i + 2
                        continue
                merged.append(level[i])
                i += 1
            level = merged
        self.clusters = level

    def __call__(self, target: Function) -> Function:
        if not self.clusters:  # no state bits: one state
            return target
        image = self.bdd.let(self.primed, target)  # G(q')
        for cluster, qvars in self.clusters:
            image = and_exists(self.bdd, image, cluster, qvars)  # \E q'(C): image /\ C
        return image

    @property
    def nodes(self) -> int:
        """The clusters' nodes, counted one cluster at a time."""
        return sum(len(c) for c, _ in self.clusters)
