"""Partition refinement, the loop shared by both minimizations (of a DFA
given by its guards, `progression.minimize`, and by its moves,
`moves.minimize`): only what a state's signature is differs.

Two states stay together while they agree on acceptance and on their
*signature* (a hashable value computed from the classes of their
successors).  A worklist version of Moore's rounds, with Hopcroft's "all
but the largest" rule: when a class splits, the largest part keeps its
number and the states of the other parts are renumbered; only the states
with a successor renumbered can change signature, so only they are
recomputed, and only the classes holding them are split again.  (Moore's
rounds recompute every state once per round, and a counter's DFA needs as
many rounds as it counts: 2^k rounds for k bits.)
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable, Sequence


def refine(accepting: Sequence[bool], signatures: Callable[[list[int], list[int]], Sequence[Hashable]],
           predecessors: Callable[[list[int]], Iterable[int]],
           renumbered: Callable[[list[int], int], None] | None = None) -> list[int]:
    """The class of each state in the coarsest partition that splits
    accepting from rejecting states and is stable under the signature of a
    state, `signatures(states, block)` giving those of `states` (`block`
    the current class of every state; all of a class's states that need
    one are asked for at once).  After a split,
    `renumbered(states, new)` hears of each part moved to a new class
    number, and `predecessors(states)` names the states with a successor
    among all those moved."""
    block = [int(acc) for acc in accepting]
    members: list[set[int]] = [set(), set()]
    for state, b in enumerate(block):
        members[b].add(state)
    known: list[Hashable] = [None] * len(block)  # valid unless the state is dirty
    dirty: dict[int, set[int]] = {b: set(ms) for b, ms in enumerate(members) if ms}
    while dirty:
        b, changed = dirty.popitem()
        everyone = members[b]
        if len(everyone) == 1:
            known[next(iter(everyone))] = None
            continue
        groups: dict[Hashable, set[int]] = {}
        asked = list(changed)
        for state, sig in zip(asked, signatures(asked, block)):
            known[state] = sig
            groups.setdefault(sig, set()).add(state)
        if len(changed) < len(everyone):  # the others kept one common signature
            clean = everyone - changed
            groups.setdefault(known[next(iter(clean))], set()).update(clean)
        if len(groups) == 1:
            continue
        parts = sorted(groups.values(), key=len, reverse=True)
        members[b] = parts[0]
        moved: list[int] = []
        for part in parts[1:]:
            new = len(members)
            members.append(part)
            for state in part:
                block[state] = new
            if renumbered is not None:
                renumbered(list(part), new)
            moved += part
        for pred in predecessors(moved):  # (after renumbering: `dirty` is keyed by the current class)
            dirty.setdefault(block[pred], set()).add(pred)
    return block
