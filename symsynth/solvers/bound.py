"""An admissible lower bound on the value of a position, which guides the
forward solver (`solvers.forward`): never above semantics §6's value, and cheap to
evaluate at every position the search generates.

The bound is 0 for any task, except F(p) with p a
conjunction of propositional parts (no temporal operator: the DFA has not
accepted iff no state so far satisfied p, so some future state must).  For
each location l of interest with conjuncts `at(X, l)`, let C(l) be the
objects carrying all of l's tags.

- L0(v): against a human who always passes (the human may, so val is at
  least this), every location l whose atoms do not all hold needs its own
  final object c in C(l), hence a drop at l, the chain of transfers that
  carries c from where it stands to l (`carry`: a shortest path over places
  whose hops cost the cheapest rule of the motion, max over its start
  anchors; a change of grasp on the way, or a drop and a grab, counted 0),
  a grab (unless c is held) and a first transit to c (unless held or
  aimed at), from the cheapest start set.  Different locations need
  different drops, chains, objects, grabs and first transits, so the sum
  over l of the cheapest c is a lower bound.
- When p is only `at(X, l)` atoms (l in L), each human move adds `strike`:
  the robot wins with a drop, so the state before its last action is a
  *brink*: holding some o in C(l) over l, every other location's atoms
  holding.  The human who passes until its turn comes at a brink and then
  takes one placed object to Else (it does not accept: that location's
  atoms stop holding) leaves the robot L0 >= drop + strike to pay to the
  next brink.  Summing the segments between brinks, val >= L0(v) + h *
  strike at the human's turn, and at the robot's unless v is itself a
  brink (then the robot wins before the human can strike: L0(v)).

In scenes with contacts (semantics §4b) a slide puts an object on its
location with no grab, drop or transfer, so L0 counts less there:
for every location l whose atoms do not all hold, the cheapest c in C(l)
of

- `mixed(at[c] -> l)`: a shortest path over places whose hops are
  transfers (the cheapest rule, as `carry`) and slides (the cheapest slide
  rule over the contacts), in whichever order the robot uses them;
- plus the first transit to c (to any grasp or contact of it, from any
  start set, contacts' anchors included) unless the hand is aimed at c;
- for a held c instead: a drop, then the carry from where it is held to
  some place y, then `mixed(y -> l)`.

Each term counts only actions that move or reach its own object, so the
sum over locations stays a lower bound.  `strike` is 0 with contacts (the
brink argument needs the robot to win with a drop; a slide can win too).
"""

from __future__ import annotations

import functools
import heapq
import math

from symsynth.automata.normal import split_conjuncts
from symsynth.game.abstraction import State, anchors, costmap_of, motion_cost, quantize
from symsynth.game.graph import GameGraph
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND

INF = math.inf


def _propositional(f: ast.Formula) -> bool:
    """No temporal operator (nor `last`) in `f`."""
    if isinstance(f, (ast.Atom, ast.Const)):
        return True
    if isinstance(f, ast.Not):
        return _propositional(f.arg)
    if isinstance(f, (ast.And, ast.Or, ast.Implies, ast.Equiv)):
        return _propositional(f.left) and _propositional(f.right)
    return False


class LowerBound:
    """An admissible lower bound on the value of a position (module doc)."""

    def __init__(self, game: GameGraph, formula: ast.Formula):
        """The bound's tables for `formula` on `game` (module doc): off
        (`enabled` False, the bound 0) unless the task is F(conjunction of
        propositional parts) with some `at(X, l)`; then the first transits,
        the carries and, with slides, the mixed paths; with only `at` atoms
        and no slides, the strike per human move."""
        self.scene = scene = game.scene
        self.enabled = False
        self.strike: float = 0
        self._cache: dict[State, tuple[float, bool]] = {}  # (L0(v), brink)
        # costs in units, INF where there is no way
        self.transit: dict[str, float] = {}  # place -> first transit
        self.from_anywhere: dict[str, float] = {}
        self.carry: dict[tuple[int, str | tuple[str, str], str], float] = {}  # (i, x or (x, g), l)
        self.to_else: dict[tuple[str, str], float] = {}  # (y, g)
        self.mixed: dict[tuple[int, str, str], float] = {}  # (i, x, l)
        found = _groups(game, formula)
        if found is None:
            return
        groups, pattern = found
        self.enabled = True
        self.names = scene.object_names
        self.groups = sorted(groups.items())
        # objects that may end up at l: they carry every tag asked at l
        self.candidates = {l: tuple(i for i, o in enumerate(scene.objects) if tags <= o.tags)
                           for l, tags in self.groups}
        costmap = costmap_of(scene)
        r = game.resolution
        self.grab = quantize(scene.grab_cost, r)
        self.drop = quantize(scene.drop_cost, r)
        motion = self._motion_costs(costmap, r)
        self._transits(motion)
        self._carries(motion)
        self.slides = bool(scene.contacts)
        if self.slides:
            self._mixed(costmap, r)
            return
        if pattern:
            self._to_else(motion)
        self.strike = self._strike() if pattern else 0

    def _motion_costs(self, costmap, r: float):
        """motion(mode, S, T): the motion's cost in units with every place
        free, the least it has in any state (quantizing is monotone, so it
        commutes with the min and max of `motion_cost`)."""
        scene = self.scene
        # every place free: no rule's condition fails (they name places of L ∪ E)
        everywhere = frozenset((*scene.locations, *scene.else_samples))

        def motion(mode, S, T):
            cost = motion_cost(costmap, mode, S, T, everywhere)
            return INF if cost == INF else quantize(cost, r)

        return motion

    def _transits(self, motion) -> None:
        """The first transit to an object standing at x (any grasp, or any
        contact when the scene has them), from any start set the robot can
        have with an empty hand; and from anywhere (hand empty, ee = Else)."""
        scene = self.scene
        anchors_at = functools.partial(anchors, scene)
        places = tuple(scene.locations) + (ELSE,)
        aims = scene.preimages if scene.contacts else scene.grasps
        for x in places:
            best = INF
            for g in aims:
                T = anchors_at(x, g)
                starts = [scene.present_anchors] + [anchors_at(y, h) for y in places for h in scene.preimages
                                                    if not (y == x and y != ELSE and h == g)]
                best = min(best, min(motion(EMPTY, S, T) for S in starts))
            self.transit[x] = best
        self.from_anywhere = {x: min(motion(EMPTY, scene.present_anchors, anchors_at(x, g)) for g in scene.grasps)
                              for x in places}

    def _carries(self, motion) -> None:
        """Carrying o from place x to location l: the cheapest chain of
        transfers, with free changes of grasp at locations (a drop and a
        grab, not counted) and at x (the first grab picks the grasp)."""
        scene, grasps = self.scene, self.scene.grasps
        anchors_at = functools.partial(anchors, scene)
        places = tuple(scene.locations) + (ELSE,)
        regrasp: dict[tuple[str, str], list[tuple[tuple[str, str], float]]] = {
            (l, g): [((l, h), 0) for h in grasps if h != g] for l in scene.locations for g in grasps}
        for i, o in enumerate(self.names):
            edges = {node: list(out) for node, out in regrasp.items()}
            for g in grasps:
                for y in places:
                    for l in scene.locations:
                        c = motion(f"{o}/{g}", anchors_at(y, g), (f"{l}/{g}",)) if l != y else INF
                        if c < INF:
                            edges.setdefault((y, g), []).append(((l, g), c))
            for x in places:
                dist = _distances([(x, g) for g in grasps], edges)
                for g in grasps:
                    for l in scene.locations:
                        self.carry[i, (x, g), l] = dist.get((l, g), INF) if l != x else 0
                for l in scene.locations:
                    self.carry[i, x, l] = min(self.carry[i, (x, g), l] for g in grasps)

    def _to_else(self, motion) -> None:
        """From an empty hand aimed at (y, g), y a location: the least cost of
        reaching an object at Else, over transits and detours that carry the
        aimed object elsewhere (grab, transfers, drop) first: Dijkstra over
        (place, grasp), backwards from every (Else, grasp)."""
        scene, grasps = self.scene, self.scene.grasps
        anchors_at = functools.partial(anchors, scene)
        places = tuple(scene.locations) + (ELSE,)
        hop: dict[tuple[tuple[str, str], tuple[str, str]], float] = {}
        for y in places:
            for g in grasps:
                S = anchors_at(y, g)
                for x in places:
                    for h in grasps:
                        if (x, h) != (y, g) or x == ELSE:
                            hop[(y, g), (x, h)] = motion(EMPTY, S, anchors_at(x, h))
                if y != ELSE:
                    for w in scene.locations:
                        if w != y:
                            c = self.grab + self.drop + min(self.carry[i, (y, g), w] for i in range(len(self.names)))
                            hop[(y, g), (w, g)] = min(hop.get(((y, g), (w, g)), INF), c)
        into: dict = {}  # the hops backwards
        for (a, b), c in hop.items():
            if c < INF:
                into.setdefault(b, []).append((a, c))
        to_else = _distances([node for node in into if node[0] == ELSE], into)
        self.to_else = {(y, g): to_else.get((y, g), INF) for y in scene.locations for g in grasps}

    def _mixed(self, costmap, r: float) -> None:
        """`mixed[i, x, l]` (module doc): Dijkstra from every place over
        transfer hops (`carry`'s single motions) and slide hops."""
        scene, names = self.scene, self.names
        places = tuple(scene.locations) + (ELSE,)
        slide: dict[tuple[str, str], float] = {}
        for (contact, start, goal), rules in costmap.slides.items():
            if rules:
                cheapest = quantize(min(rule.cost for rule in rules), r)
                slide[start, goal] = min(slide.get((start, goal), INF), cheapest)
        for i in range(len(names)):
            edges: dict[str, list[tuple[str, float]]] = {}
            for y in places:
                for l in scene.locations:
                    c = min(self.carry[i, y, l], slide.get((y, l), INF)) if l != y else INF
                    if c < INF:
                        edges.setdefault(y, []).append((l, c))
            for x in places:
                dist = _distances([x], edges)
                for l in scene.locations:
                    self.mixed[i, x, l] = dist.get(l, INF)

    def _strike(self) -> float:
        """What each human move can add at least (module doc): the least, over
        the states one drop from the win (holding o over l, every other
        location's atoms holding), of the most a move of one placed object
        to Else makes the bound grow by."""
        grasps = self.scene.grasps
        locations = self.scene.locations
        any_place = min(self.transit.values())
        best = INF
        for l, _ in self.groups:
            for o in self.candidates[l]:
                # holding o over l, the robot must put o down somewhere (y)
                # before any transit: then go to Else at once, or via
                # another transit first
                to_else = min(self.carry[o, (l, g), y] + self.to_else[y, g]
                              for g in grasps for y in locations)
                worst: float = 0
                for other, _ in self.groups:
                    if other == l:
                        continue
                    standing = [c for c in self.candidates[other] if c != o]
                    if not standing:
                        worst = INF  # no such state
                        break
                    damage = INF
                    for c1 in standing:  # the object the human takes to Else
                        d = self.carry[c1, ELSE, other] + self.grab + to_else
                        for c in self.candidates[other]:
                            if c == o:  # held over l
                                d = min(d, min(self.carry[c, (l, g), other] for g in grasps))
                            elif c != c1:
                                d = min(d, min(self.carry[c, x, other] for x in self.transit)
                                        + self.grab + any_place)
                        damage = min(damage, self.drop + d)
                    worst = max(worst, damage)
                best = min(best, worst)
        return 0 if best == INF else best

    def __call__(self, v: State, h: int, robot: bool) -> float:
        """The bound at (v, h) when it is the robot's turn (`robot`) or the human's."""
        if not self.enabled:
            return 0
        entry = self._cache.get(v)
        if entry is None:
            entry = self._cache[v] = self._compute(v)
        value, brink = entry
        if robot and brink:  # the robot wins with its next drop, before any strike
            return value
        return value + h * self.strike

    def _compute(self, v: State) -> tuple[float, bool]:
        """(L0(v), whether v is a brink: one drop from the win)."""
        at, ee = v.at, v.ee
        total: float = 0
        missing = []
        for l, _ in self.groups:
            here = [i for i, a in enumerate(at) if a == l]
            cands = self.candidates[l]
            if here and here[0] in cands:
                continue  # every atom at l holds
            missing.append(l)
            best = INF
            for i in cands:
                if self.slides:
                    cost = self._with_slides(v, i, l)
                elif at[i] == HAND:
                    cost = self.drop + self.carry[i, _held_over(v), l]
                else:
                    aimed = isinstance(ee, tuple) and ee[0] == self.names[i]
                    cost = (self.drop + self.carry[i, at[i], l] + self.grab
                            + (0 if aimed else self.transit[at[i]]))
                best = min(best, cost)
            total += best
            if total == INF:
                return INF, False
        if self.slides:
            return total, False
        held = v.held()
        brink = (isinstance(ee, str) and missing == [ee] and held is not None and held in self.candidates[ee])
        if missing and held is None and ee == ELSE:
            # the first action is a transit from anywhere: either the first
            # transit to some final object (counted above from the cheapest
            # start) or one more
            total += min((self.from_anywhere[a] - self.transit[a] for a in at
                          if self.transit[a] < INF), default=0)
        return total, brink


    def _with_slides(self, v: State, i: int, l: str) -> float:
        """The least cost of bringing object i to l when slides may do part
        of it (module doc)."""
        at, ee = v.at, v.ee
        if at[i] == HAND:  # put down somewhere first (y = l included: carry 0 from there)
            return self.drop + min(self.carry[i, _held_over(v), y] + (0 if y == l else self.mixed[i, y, l])
                                   for y in self.scene.locations)
        aimed = isinstance(ee, tuple) and ee[0] == self.names[i]
        return self.mixed[i, at[i], l] + (0 if aimed else self.transit[at[i]])


def _groups(game: GameGraph, formula: ast.Formula) -> tuple[dict[str, set[str]], bool] | None:
    """For F(p) with p a conjunction of propositional parts: the tags each
    location's `at` atoms ask for, and whether p is only such atoms (the
    pattern case); None for any other task or with no such atom."""
    if not isinstance(formula, ast.Eventually):
        return None
    parts = split_conjuncts(formula.arg)
    if not all(_propositional(part) for part in parts):
        return None  # e.g. F(a & F b): after a, a need not hold again
    groups: dict[str, set[str]] = {}
    pattern = True  # every conjunct is at(X, l) with l a location of interest
    for part in parts:
        p = game.props.get(part.key) if isinstance(part, ast.Atom) else None
        if p is not None and p.kind == "at" and p.tag is not None and p.location in game.scene.locations:
            groups.setdefault(p.location, set()).add(p.tag)
        else:
            pattern = False
    return (groups, pattern) if groups else None


def _held_over(v: State) -> tuple[str, str]:
    """(location, grasp) of a state whose hand holds an object: the hand is
    then over a location (`ee`) with a grasp (`grip`), semantics §2."""
    if isinstance(v.ee, tuple) or v.grip is None:
        raise ValueError(f"the hand holds nothing in {v}")
    return v.ee, v.grip


def _distances(sources, edges) -> dict:
    """Least cost from any of `sources` (cost 0) to every node, over
    `edges`: node -> [(next node, cost)]."""
    dist: dict = {}
    heap = [(0, node) for node in sources]
    heapq.heapify(heap)
    while heap:
        d, node = heapq.heappop(heap)
        if node in dist:
            continue
        dist[node] = d
        for after, c in edges.get(node, ()):
            if after not in dist:
                heapq.heappush(heap, (d + c, after))
    return dist
