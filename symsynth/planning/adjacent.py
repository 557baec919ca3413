"""The adjacent-link rule: which pairs of robot links are never checked
against each other.

Two links with collision geometry are *adjacent* when the kinematic path
between them runs only through links without collision geometry: a link
and its nearest ancestor that has geometry.  Adjacent links touch by
construction at their joint, so a contact between them says nothing.  For
the Franka Panda these are the parent-child pairs (link0, link1), ...,
(link6, link7), then (link7, hand), joined rigidly through the
geometry-less link8, and (hand, leftfinger), (hand, rightfinger).  The two
fingers are siblings, not adjacent; everything else is checked, e.g. link5
against link7 and the hand, which really meet when joint 6 is near its
lower limit.  Every planner plugin excludes exactly these pairs.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from typing import TypeVar

Link = TypeVar("Link", bound=Hashable)


def adjacent_pairs(links: Sequence[Link], parent: Callable[[Link], Link | None]) -> list[tuple[Link, Link]]:
    """(ancestor, link) for each of `links` (those with collision geometry)
    that has an ancestor among them, the nearest such; `parent` gives the
    link a link hangs from, None at the root."""
    with_geometry = set(links)
    pairs = []
    for link in links:
        up = parent(link)
        while up is not None and up not in with_geometry:
            up = parent(up)
        if up is not None:
            pairs.append((up, link))
    return pairs
