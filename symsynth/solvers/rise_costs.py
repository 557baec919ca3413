"""What the rise bounds of `solvers.rise` read from a costmap, in the packed search's integer
units (every cost rounded up to whole units of the resolution, as `packed.tables` does, so the
bounds hold for the game the solvers search): per motion pair (mode, s, t)

- U, the least cost of a rule with no condition (it holds in every state; inf when none);
- Lo, the least cost of any rule (no state pays less);

both 0 when s = t; the least sums of Lo over chains of transfers (`path`); and the objects
that stand for all others with the same carrying rules (`kinds`)."""

from __future__ import annotations

import itertools
import math

from symsynth.game.abstraction import anchors, costmap_of, quantize
from symsynth.scene.model import ELSE, Scene

INF = math.inf


def less(upper: float, lower: float) -> float:
    """upper - lower, -inf when `lower` is inf (what it bounds below cannot happen)."""
    return -INF if lower == INF else upper - lower


class Costs:
    """U, Lo and Lo-paths of one scene's costmap in units of `resolution`, with its places."""

    def __init__(self, scene: Scene, resolution: float = 1.0):
        self.scene, self.cm, self.resolution = scene, costmap_of(scene), resolution
        self.L = list(scene.locations)
        self.A = tuple(scene.present_anchors)
        self.grab, self.drop = self.units(scene.grab_cost), self.units(scene.drop_cost)
        self._pairs: dict = {}
        self._paths: dict[str, dict] = {}

    def units(self, cost: float) -> float:
        return quantize(cost, self.resolution) if math.isfinite(cost) else INF

    def U(self, mode: str, S, T) -> float:
        """The most a motion from S to T can cost, in any state."""
        return max(self._pair(mode, s, t)[0] for s in S for t in T)

    def Lo(self, mode: str, S, T) -> float:
        """The least a motion from S to T can cost: max over s, t of the least rule."""
        return max(self._pair(mode, s, t)[1] for s in S for t in T)

    def _pair(self, mode: str, s: str, t: str) -> tuple[float, float]:
        key = (mode, s, t)
        if key not in self._pairs:
            if s == t:
                self._pairs[key] = (0, 0)
            else:
                rules = self.cm.rules(mode, s, t)
                self._pairs[key] = (min((self.units(r.cost) for r in rules if not r.free), default=INF),
                                    min((self.units(r.cost) for r in rules), default=INF))
        return self._pairs[key]

    def path(self, mode: str, s: str, t: str) -> float:
        """The least sum of least rules over transfers from anchor s to anchor t."""
        if mode not in self._paths:
            nodes = sorted({a for a in self.A if a != "home"})
            d = {(a, b): self._pair(mode, a, b)[1] for a in nodes for b in nodes}
            for k, i, j in itertools.product(nodes, nodes, nodes):
                if d[i, k] + d[k, j] < d[i, j]:
                    d[i, j] = d[i, k] + d[k, j]
            self._paths[mode] = d
        return self._paths[mode].get((s, t), INF)

    def at(self, place: str, g: str) -> tuple[str, ...]:
        return anchors(self.scene, place, g)

    def Else(self, g: str) -> tuple[str, ...]:
        return anchors(self.scene, ELSE, g)

    def kinds(self) -> list[str]:
        """One object per set of objects whose carrying modes have the same rules, two of a set
        with more than one (the cases pair the moved object with another, which may be of the
        same set), so that the cases need not repeat the same numbers for every object."""
        seen: dict = {}
        for o in self.scene.object_names:
            sig = tuple((s, t, tuple(sorted((tuple(sorted(x.free)), x.cost) for x in r)), mode.split("/")[1])
                        for (mode, s, t), r in sorted(self.cm.motions.items()) if mode.split("/")[0] == o)
            seen.setdefault(sig, []).append(o)
        return [o for members in seen.values() for o in members[:2]]
