"""`solvers.bound`'s admissible lower bound as integer tables, for the
compiled AND-OR search (`search._lower` reads them), and a tighter one
for distinct objects: the assignment bound.

The first bound (its proof is in `solvers.bound`) is, at a position v with
h human moves left, L0(v) + h * strike, or L0(v) at a robot turn one drop
from the win: L0 sums over the pattern's locations whose atoms do not hold
the cheapest candidate's fetch, carry and drop.  Everything it reads of v
is an object's place, the end-effector and the grip, so it becomes arrays
indexed by object, place and group; scenes with contacts (slides) get no
bound here (`enabled` False, the bound 0).

**The assignment bound A(v)** (`assign._assignment`), on when every group
(a location l with atoms `at(X, l)`) has one candidate and no object is the
candidate of two: then each object c has at most one goal l(c), and M is
the set of objects not at their goal.  Against the human who passes, take
any plan from v to the win (robot actions only; at h = 0 only the robot
moves objects, and there are no slides).  Every motion goes from an anchor
at some place to an anchor at another (places: the locations and Else, all
Else samples one place), so its cost is at least `edge(x, y)`: the
cheapest rule, every place free (a rule's cost never falls when fewer
places are free), least over the modes and the grasps and contacts at x
and y, and the max over the Else samples (a motion from or to an object
at Else has all of them in its start or target set, semantics §5); `D` is
the closure of `edge` (Floyd-Warshall), so D(x, z) <= D(x, y) + D(y, z).

- Jobs.  For c in M the plan holds c on a chain of transfers from where it
  stands, p(c), to l(c) (drops and grabs on the way join the chain at the
  place they happen), so those transfers cost at least carry(c, p(c), l(c));
  it grabs c at least once (unless held) and drops it at l(c) last.  These
  are `solvers.bound`'s terms without the first transit.
- Extra grabs and drops.  If c in M is held and l(c) is taken by another
  object, that object must leave l(c) before c's last drop, so the hand
  drops c somewhere else first and grabs it again: one drop and one grab
  more.  If the objects standing on locations form a cycle c1 -> c2 -> ...
  -> c1 (c(i+1) stands at l(ci)), take the first moment some l(ci) receives
  ci for good: c(i+1) has left l(ci), is not in the hand (ci is), and is not
  for good at l(c(i+1)) yet, so it was dropped elsewhere and must be
  grabbed again: one drop and one grab more, on objects of this cycle only.
- The rest R: every motion that is not a transfer of an object of M, over
  the places.  Removing each job's chain (a path from p(c), or from the
  start when c is held, to l(c)) from the plan's walk leaves R with one
  unit of supply at the start s0 (unless the hand holds an object of M at
  v) and at each l(c), and one unit of demand at each p(c) of an object not
  held and at the walk's end.  So R splits into paths from supplies to
  demands, and costs at least the cheapest way to give each p(c) its own
  supply: a minimum-cost assignment with costs D, the end taking the
  supply left over at no cost.  When the hand is empty with ee = Else the
  first motion starts from every anchor at once (semantics §5: the max over
  its start set), so s0's cost to p is the max over those anchors s of the
  least path cost from s to p.
- Pairs that run backwards in time.  Build the split explicitly: cut the
  walk at the jobs' pieces; each stretch of R between two pieces leads from
  the end of one (the start s0, a last drop at l(c), or a drop of c
  elsewhere: a pause) to the start of the next (a first grab at p(c), a
  grab again after a pause, or the walk's end).  Follow a supply's stretch;
  where it ends at a grab after a pause of c at y, go on with the stretch
  that leaves that pause (also at y).  Each stretch is used once, so these
  chains are disjoint, end at distinct demands, and each costs at least D
  between its ends; its last stretch reaches p(c) from another place unless
  it is s0's own stretch (s0 aimed at c, or both at Else), so a chain to
  p(c) also costs at least near(p(c)), the least D into p(c) from another
  place: the assignment's cost is max(D(x, p), near(p)), and 0 from s0 at
  its own place.  A chain without a pause is one stretch, forwards in
  time; a supply l(c) whose demand's first grab must come before c's last
  drop (c's own p(c), or p(d) of the object d standing on l(c)) needs a
  pause on its chain, a different one for each chain, and every pause is a
  drop that is not last and is followed by a grab that is not first.

These count different actions (transfers of M's objects; first grabs and
last drops; pauses' drops and grabs; the other motions).  With E the
pauses counted by the extras and P(π) the backwards pairs of an
assignment π, the plan pays at least jobs + min over π of [cost(π) +
(drop + grab) max(E, P(π))], which is at least jobs + the larger of
min cost(π) + E (drop + grab) and min [cost(π) + P(π) (drop + grab)]: that
is A(v), at most V_0(v); the search uses max(L0(v), A(v)).  The strike
argument of `solvers.bound` needs only that the bound at h = 0 is
admissible and at least L0 after a strike, so the h > 0 form carries over
unchanged: max(L0, A) + h * strike.

A(v) costs two Hungarian assignments (under a microsecond at 8 objects),
so a node gets L0 when made and A when first expanded (`search._tighten`),
and only in memos that asked for it (`andor.Memo.tighten`: the no-human
searches of `solvers.replan`; the rounds from below lost more time to it
than it saved them; bench/results/h0-assignment-bound.md).
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
        self.goal = np.full(n, -1, np.int64)  # the assignment bound: object i's group (-1: none)
        self.dist = np.zeros((m + 2, m + 1), np.int64)  # D between places; row m + 1: from anywhere
        self.work = np.zeros(10 * (n + 2), np.int64)  # the assignment's scratch
        self.assign = False
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
        chosen = [bound.candidates[l] for l, _ in groups]
        if all(len(c) == 1 for c in chosen) and len({c[0] for c in chosen}) == len(chosen):
            self.assign = True
            for g, c in enumerate(chosen):
                self.goal[c[0]] = g
            self.dist = place_distances(tables)

    def args(self, tight: bool = False) -> tuple:
        """The kernels' tuple; `tight`: with the assignment bound on where the tables have it."""
        return (self.enabled, self.place, self.cand, self.carry, self.held, self.transit, self.anywhere,
                np.int64(self.grab), np.int64(self.drop), np.int64(self.strike),
                self.assign and tight, self.goal, self.dist, self.work)


def place_distances(tables: Tables) -> np.ndarray:
    """The assignment's costs (module doc), in units (INF: no way): rows
    0..m a supply at a place (m: Else), max(D(x, p), near(p)); row m + 1
    the start set of an empty hand at Else (every present anchor: the max
    over them of the least path cost); columns the demand's place p."""
    m, F = tables.m, tables.F
    A = len(tables.anchors)
    # each anchor's group (place, frame): home -1, x/f at x * F + f (Else samples all at m)
    group = np.array([-1] + [min(x, m) * F + f for x in range(m + len(tables.scene.else_samples)) for f in range(F)],
                     np.int64)
    K = (m + 1) * F
    # the cheapest rule of every (mode, s, t) cell (the cell's rules are sorted by cost), least over modes
    cheap = np.where(tables.rule_count > 0, tables.rule_units[tables.rule_start], INF).min(axis=0)
    np.fill_diagonal(cheap, 0)
    into = np.full((A, K), INF, np.int64)  # anchor -> group: a motion's cost is the max over its targets
    for y in range(K):  # (no anchor in the group, as Else without samples: no motion, INF)
        if (group == y).any():
            into[:, y] = cheap[:, group == y].max(axis=1)
    edge = np.full((m + 1, m + 1), INF, np.int64)  # place -> place: the least over groups, max over sources
    for y in range(K):
        for x in range(K):
            if (group == x).any():
                edge[x // F, y // F] = min(edge[x // F, y // F], into[group == x, y].max())
    dist = edge.copy()
    np.fill_diagonal(dist, 0)
    for y in range(m + 1):  # Floyd-Warshall
        dist = np.minimum(dist, np.minimum(dist[:, [y]] + dist[[y], :], INF))
    out = np.zeros((m + 2, m + 1), np.int64)
    off = dist + np.where(np.eye(m + 1, dtype=bool), INF, 0)
    near = np.minimum(off, INF).min(axis=0)  # the least D into p from another place
    out[:m + 1] = np.maximum(dist, near[None, :])
    for s in tables.home_starts:  # from anchor s: its first motion to a group, then D; the max over s
        via = np.full(m + 1, INF, np.int64)
        for y in range(K):
            via = np.minimum(via, np.minimum(into[s, y] + dist[y // F], INF))
        out[m + 1] = np.maximum(out[m + 1], via)
    return out
