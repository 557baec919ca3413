"""A manager asked for a large memory estimate keeps CUDD's growth policy for
that estimate (`loose_up_to`, memory / 160, as `Cudd_Init` computes it) but
does not reserve CUDD's out-of-memory stash for it (memory / 128, allocated
at creation: 45 ms for the arena's 4 GiB, paid by every game).

`shared_size` (the node count `symsynth dfa` prints) counts a node shared by
several roots once, and the constant node once."""

from __future__ import annotations

import warnings

from dd import cudd

from symsynth.automata.bdd import new_manager, shared_size


def test_a_large_estimate_keeps_cudds_growth_policy_without_its_stash():
    asked = 2**32
    reference = cudd.BDD(memory_estimate=asked, initial_cache_size=2**14)  # CUDD's own sizing
    made = new_manager(memory=asked)
    assert made.configure()["loose_up_to"] == reference.configure()["loose_up_to"] == asked // 160
    assert allocated(reference) >= asked / 128
    assert allocated(made) < 8 * 2**20


def test_a_small_estimate_is_cudds_own():
    made, reference = new_manager(memory=2**24), cudd.BDD(memory_estimate=2**24, initial_cache_size=2**14)
    assert made.configure()["loose_up_to"] == reference.configure()["loose_up_to"]


def allocated(bdd) -> float:
    """CUDD's memory in use, in bytes (dd warns that the unit changed in 0.5.7)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return bdd.statistics()["mem"]


def test_shared_size_counts_shared_nodes_once():
    bdd = new_manager()
    bdd.declare("a", "b", "c")
    a, b, c = (bdd.var(x) for x in "abc")
    assert shared_size(bdd, [bdd.true, bdd.false]) == 1  # one constant, complemented edges
    assert shared_size(bdd, [b]) == 2
    assert shared_size(bdd, [a & b]) == 3
    assert shared_size(bdd, [a & b, b, ~b]) == 3  # b's node is a & b's
    assert shared_size(bdd, [a & b, c]) == 4
