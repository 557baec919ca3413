"""`solvers.bound`'s admissible lower bound as integer tables, for the
compiled AND-OR search (`search._lower` reads them).

The bound (its proof is in `solvers.bound`) is, at a position v with h
human moves left, L0(v) + h * strike, or L0(v) at a robot turn one drop
from the win: L0 sums over the pattern's locations whose atoms do not hold
the cheapest candidate's fetch, carry and drop.  Everything it reads of v
is an object's place, the end-effector and the grip, so it becomes arrays
indexed by object, place and group; scenes with contacts (slides) get no
bound here (`enabled` False, the bound 0).
"""

from __future__ import annotations

import math

import numpy as np

from symsynth.game.graph import GameGraph
from symsynth.logic import ast
from symsynth.scene.model import ELSE
from symsynth.solvers.bound import LowerBound
from symsynth.solvers.packed.kernels import INF
from symsynth.solvers.packed.tables import Tables


def _units(x: float) -> int:
    return int(INF) if x == math.inf else int(x)


class BoundTables:
    """The arrays `search._lower` takes (`args`), built from `LowerBound`."""

    def __init__(self, tables: Tables, formula: ast.Formula):
        scene = tables.scene
        bound = LowerBound(GameGraph(scene, formula, tables.resolution), formula)
        self.enabled = bound.enabled and not bound.slides
        n, m, frames = tables.n, tables.m, scene.preimages
        groups = bound.groups if self.enabled else []
        places = list(scene.locations) + [ELSE]
        G = max(1, len(groups))
        self.place = np.zeros(G, np.int64)  # each group's location
        self.cand = np.zeros(G, np.int64)  # the objects that may end up there, as a mask
        self.carry = np.full((n, m + 1, G), INF, np.int64)  # carry[i, x, g]: from place x to group g's location
        self.held = np.full((n, m + 1, max(1, len(frames)), G), INF, np.int64)  # held over x with frame f
        self.transit = np.full(m + 1, INF, np.int64)
        self.anywhere = np.full(m + 1, INF, np.int64)
        self.grab = self.drop = self.strike = 0
        if not self.enabled:
            return
        for g, (l, _) in enumerate(groups):
            self.place[g] = tables.place_of[l]
            self.cand[g] = sum(1 << i for i in bound.candidates[l])
            for i in range(n):
                for x, name in enumerate(places):
                    self.carry[i, x, g] = _units(bound.carry[i, name, l])
                    for f, frame in enumerate(frames):
                        if frame in scene.grasps:
                            self.held[i, x, f, g] = _units(bound.carry[i, (name, frame), l])
        for x, name in enumerate(places):
            self.transit[x] = _units(bound.transit[name])
            self.anywhere[x] = _units(bound.from_anywhere[name])
        self.grab, self.drop, self.strike = _units(bound.grab), _units(bound.drop), _units(bound.strike)

    def args(self) -> tuple:
        return (self.enabled, self.place, self.cand, self.carry, self.held, self.transit, self.anywhere,
                np.int64(self.grab), np.int64(self.drop), np.int64(self.strike))
