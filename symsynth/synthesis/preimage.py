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
when every conjunct fits in one, T is monolithic.  T is built only for
games past their first small rounds (`SUBSTITUTED_NODES`); before, the
preimage is the substitution.  Both are distributive over `|` in G, which the fixpoint uses:
it takes the preimage of the states new in each round only.
"""

from __future__ import annotations

from symsynth.automata.bdd import Function, and_exists
from symsynth.automata.symbolic import SymbolicDFA, prime

#: A cluster grows while it has at most this many BDD nodes (Double-Counter
#: 06, 16,389 states: its monolithic T has 708,000).
CLUSTER_NODES = 1 << 20

#: Before T is built the preimage substitutes delta into G (`bdd.let`),
#: about |G| x |delta| steps, where building T costs about |delta| times a
#: constant: as in renting until the rent paid would have bought, the
#: substitutions go on while their targets have at most this many nodes
#: together (measured: 25 ns per |G| x |delta| step, 2-5 us per delta node
#: for T).  Nim and the random families end within it (0 to 3 rounds of
#: small targets: Nim 01_15, 50 nodes in 4 calls, 0.02 s, where T costs 0.05 s);
#: Double-Counter 05 builds T at its second call.
SUBSTITUTED_NODES = 64


class Preimage:
    """`preimage(G)` = G(delta(q, x, y)) for a BDD G over the DFA's state
    bits: by substitution while the targets so far have at most `substituted`
    nodes together, then by the clustered relation (built then)."""

    def __init__(self, dfa: SymbolicDFA, limit: int = CLUSTER_NODES, substituted: int = SUBSTITUTED_NODES):
        self.dfa, self.bdd, self.limit, self.substituted = dfa, dfa.bdd, limit, substituted
        self.primed = {b: prime(b) for b in dfa.bits}
        self._clusters: list[tuple[Function, set[str]]] | None = None

    def __call__(self, target: Function) -> Function:
        if not self.dfa.bits:  # one state
            return target
        if self._clusters is None and len(target) <= self.substituted:
            self.substituted -= len(target)
            return self.bdd.let(self.dfa.delta, target)  # G(delta(q, x, y))
        image = self.bdd.let(self.primed, target)  # G(q')
        for cluster, qvars in self.clusters:
            image = and_exists(self.bdd, image, cluster, qvars)  # \E q'(C): image /\ C
        return image

    @property
    def clusters(self) -> list[tuple[Function, set[str]]]:
        """(C_j, the primed bits only C_j reads), built on first use."""
        if self._clusters is None:
            self._clusters = _clusters(self.dfa, self.limit)
        return self._clusters

    @property
    def built(self) -> bool:
        """Whether the relation has been built (by a call past the substitutions, or `clusters`)."""
        return self._clusters is not None

    @property
    def nodes(self) -> int:
        """The clusters' nodes, counted one cluster at a time."""
        return sum(len(c) for c, _ in self.clusters)


def _clusters(dfa: SymbolicDFA, limit: int) -> list[tuple[Function, set[str]]]:
    """The conjuncts q'_b <-> delta_b, neighbours conjoined pairwise level by
    level (a balanced tree) where the conjunction has at most `limit` nodes."""
    bdd = dfa.bdd
    level = [(bdd.apply("<=>", bdd.var(prime(b)), dfa.delta[b]), {prime(b)}) for b in dfa.bits]
    joined = True
    while joined and len(level) > 1:
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
    return level
