"""Which places rest on which: the support relation of a scene's places.

An object standing at place `p` may rest on one standing at place `x`
when two of the scene's objects, one at `x` and another at `p`, would sit
that way: the bottom of the one at `p` within `TOUCH` metres of the top of
the one at `x`, and their footprints overlapping by more than `OVERLAP`
metres along both horizontal axes (axis-aligned boxes of the shapes at the
places' poses, in the world frame: a box's or cylinder's from its size, a
mesh's from its vertices).  On the arch, `top` rests on `support1` and
`support2`: a white block put on `top` while the lintel lies on a support
stands on the lintel's end.

The costmap reads it (`build.py`): lifting an object from `x`, or sliding
it away from `x`, pulls it out from under whatever rests on it, so every
rule of a transfer that starts at `x/g` and of a slide from `x` requires
the places resting on `x` to be free (semantics §5 conditions: "if every
place of F is free").  The spec lets a grab happen wherever the hand is
at the object; the condition on what follows it is where the strategy
learns that an object with another on it must first be cleared.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping

import numpy as np

from symsynth.planning.anchors import place_of
from symsynth.scene.costmap import Rule
from symsynth.scene.geometry import Pose, Shape
from symsynth.scene.mesh import load_mesh
from symsynth.scene.model import Scene, geometry_of

TOUCH = 5e-3  # metres between one object's bottom and another's top
OVERLAP = 1e-3  # metres: footprints overlapping less than this only touch side by side


def resting(scene: Scene) -> dict[str, frozenset[str]]:
    """For every place `x` with something that may rest on it, the places
    `p` that may (module doc)."""
    geometry = geometry_of(scene)
    outlines = {name: corners(geometry.shapes[name]) for name in scene.object_names}
    boxes = {(name, place): placed(outlines[name], pose)
             for name in scene.object_names for place, pose in geometry.places.items()}
    found: dict[str, set[str]] = {}
    for (below, x), (above, p) in itertools.permutations(boxes, 2):
        if below == above or x == p or p in found.get(x, ()):
            continue
        (low, high), (top_low, top_high) = boxes[(below, x)], boxes[(above, p)]
        overlap = np.minimum(high[:2], top_high[:2]) - np.maximum(low[:2], top_low[:2])
        if abs(top_low[2] - high[2]) <= TOUCH and bool(np.all(overlap > OVERLAP)):
            found.setdefault(x, set()).add(p)
    return {x: frozenset(ps) for x, ps in sorted(found.items())}


def bounds(shape: Shape, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """The world-frame axis-aligned box of `shape` standing at `pose`."""
    return placed(corners(shape), pose)


def corners(shape: Shape) -> np.ndarray:
    """Points in the shape's own frame whose hull is the shape's: a box's or
    cylinder's bounding corners, a mesh's vertices (its file read once a shape,
    not once a place)."""
    if shape.kind == "box":
        sx, sy, sz = shape.size
        return np.array(list(itertools.product((-sx / 2, sx / 2), (-sy / 2, sy / 2), (0.0, sz))))
    if shape.kind == "cylinder":
        r = shape.radius
        return np.array(list(itertools.product((-r, r), (-r, r), (0.0, shape.height))))
    assert shape.mesh is not None  # a mesh shape names its file
    return np.asarray(load_mesh(shape.mesh, shape.scale).vertices, float)


def placed(points: np.ndarray, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
    """The world-frame axis-aligned box of `points` moved to `pose`."""
    matrix = pose.matrix()
    world = points @ matrix[:3, :3].T + matrix[:3, 3]
    return world.min(axis=0), world.max(axis=0)


def lifted(rules: Mapping[tuple[str, str, str], tuple[Rule, ...]], support: Mapping[str, frozenset[str]]
           ) -> dict[tuple[str, str, str], tuple[Rule, ...]]:
    """A holding mode's rules, `{(mode, start, goal): rules}`, each of a
    transfer starting at `x/g` also requiring the places resting on `x` free."""
    return {key: tuple(dataclasses.replace(rule, free=rule.free | support.get(place_of(key[1]) or "", frozenset()))
                       for rule in found)
            for key, found in rules.items()}
