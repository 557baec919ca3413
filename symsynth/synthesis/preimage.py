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
when every conjunct fits in one, T is monolithic.  T is not built until
substituting has cost about what T would (`STEPS_PER_NODE`,
`SUBSTITUTION_STEPS`); until then the preimage is the substitution.  Both
are distributive over `|` in G, which the fixpoint uses: it takes the
preimage of the states new in each round only.
"""

from __future__ import annotations

from symsynth.automata.bdd import Function, and_exists
from symsynth.automata.symbolic import SymbolicDFA, prime

#: A cluster grows while it has at most this many BDD nodes (Double-Counter
#: 06, 16,389 states: its monolithic T has 708,000; 07, 65,541 states: 2.8
#: million, and its 253 rounds take 28.6 s through it; through the three
#: clusters of 0.7-1 million nodes that 2^20 allowed, 1.1-1.6 s each).
CLUSTER_NODES = 1 << 22

#: Before T is built the preimage substitutes delta into G (`bdd.let`),
#: about |G| x |delta| steps (|delta|: the transition functions' nodes),
#: 20-25 ns each here, where building T costs 2-5 us per node of T, and T
#: has at least |delta| nodes, often many more (a random Syft DFA: |delta|
#: 289, T 17,854).  As in renting until the rent paid would have bought,
#: the substitutions go on while they have cost at most STEPS_PER_NODE
#: steps per node of delta (T's least price), and at least
#: SUBSTITUTION_STEPS (about 40 ms: small deltas, whose T may blow up,
#: keep substituting).  Nim and the random families end within a few
#: rounds and never build T (Nim 02_07: |delta| 58,853, 3 targets of 61
#: nodes together; T would cost 0.36 s against 0.06 s); Double-Counter 05
#: (|delta| 99,231, targets of 49 and 159 nodes) builds it at its second call.
STEPS_PER_NODE = 150
SUBSTITUTION_STEPS = 2_000_000


class Preimage:
    """`preimage(G)` = G(delta(q, x, y)) for a BDD G over the DFA's state
    bits: by substitution while the substitutions so far have cost at most
    `steps` (|G| x |delta| each; by default the budget above), then by the
    clustered relation (built then)."""

    def __init__(self, dfa: SymbolicDFA, limit: int = CLUSTER_NODES, steps: int | None = None):
        self.dfa, self.bdd, self.limit = dfa, dfa.bdd, limit
        self.primed = {b: prime(b) for b in dfa.bits}
        self.delta_nodes = sum(len(f) for f in dfa.delta.values())  # shared nodes counted once per function
        self.steps = max(SUBSTITUTION_STEPS, STEPS_PER_NODE * self.delta_nodes) if steps is None else steps
        self._clusters: list[tuple[Function, set[str]]] | None = None

    def __call__(self, target: Function) -> Function:
        if not self.dfa.bits:  # one state
            return target
        cost = len(target) * self.delta_nodes
        if self._clusters is None and cost <= self.steps:
            self.steps -= cost
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
