"""The start-goal and recursive costmap algorithms (paper, Alg. 2 and 3), written once over a roadmap.

Once every roadmap edge knows the location obstacles it touches (its
"blocked by" set, `protocol.edge_contacts`), the question "best motion from
`s` to `t` while the places in `O` are occupied" is a shortest-path search on
the roadmap with the edges blocked by `O` removed.  `RoadmapSearch` answers
it; each (source, set of removed edges) costs one Dijkstra, which serves
every target.

Conventions:
- A *place* is the name of a location obstacle (`x ∈ L ∪ E`).  A `Query`
  names two sets of places: `always` are occupied during the whole motion
  (the target of a transit, where the object to grab stands): the edges they
  block are never used and they never appear in a rule; `never` are never
  occupied during it (the target of a transfer): what they block is ignored
  and they never appear in a rule.  The other places are the *candidates*;
  a rule's `free` is a set of candidates.
- A path's *length* is the sum of its edge lengths (radians), added in path
  order from the start; a rule costs `per_radian * length`; its evidence
  `path` is the configurations of the roadmap vertices along it, start first.
  A motion from an anchor to itself is the rule `(∅, 0, (config,))`.
- Rules are undominated (no rule has a `free` containing another's at a cost
  at least as high) and sorted by cost, then by sorted `free`.
- Same input, same output: the roadmap's arcs are searched in a fixed order
  and every set is iterated sorted.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

import numpy as np

from symsynth.planning.protocol import Mode, PlannerError, Roadmap
from symsynth.scene.costmap import Key, Rule


@dataclass(frozen=True)
class Query:
    """One motion to cost: from anchor `start` to anchor `goal`, with the
    places `always` occupied and the places `never` occupied (module doc)."""

    start: str
    goal: str
    always: frozenset[str] = frozenset()
    never: frozenset[str] = frozenset()

    def __post_init__(self) -> None:
        object.__setattr__(self, "always", frozenset(self.always))
        object.__setattr__(self, "never", frozenset(self.never))


@dataclass(frozen=True)
class RoadmapPath:
    """A roadmap path: its vertices (start first), length, and the union of
    the blocked-by sets of its edges."""

    vertices: tuple[int, ...]
    length: float
    touched: frozenset[str]


class RoadmapSearch:
    """Shortest roadmap paths that avoid the edges blocked by a set of places.

    Shortest-path trees are cached for the most recent source only, keyed by
    the set of removed edges (two obstacle sets blocking the same edges share
    one search): ask the questions of one source together.
    """

    def __init__(self, roadmap: Roadmap, blocked: list[frozenset[str]], places: Iterable[str]):
        self.roadmap = roadmap
        self.places = frozenset(places)
        self._configs = np.asarray(roadmap.configs, dtype=float)
        edges, self._lengths = _checked(roadmap, blocked, self.places, len(self._configs))
        self._blocked = [frozenset(b) for b in blocked]
        self._edge = {(min(i, j), max(i, j)): e for e, (i, j) in enumerate(edges.tolist())}
        # Both directions of every edge, as arcs sorted by (tail, head).
        tails = np.concatenate([edges[:, 0], edges[:, 1]])
        heads = np.concatenate([edges[:, 1], edges[:, 0]])
        order = np.lexsort((heads, tails))
        self._tails, self._heads = tails[order], heads[order]
        self._arc_edge = np.concatenate([np.arange(len(edges))] * 2)[order]
        self._blocks = {x: np.array([x in b for b in self._blocked], dtype=bool) for x in sorted(self.places)}
        self._removed: dict[frozenset[str], tuple[np.ndarray, bytes]] = {}  # edges each obstacle set blocks
        self._source: int | None = None
        self._trees: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}

    def vertex(self, anchor: str) -> int:
        """The roadmap vertex of an anchor."""
        if anchor not in self.roadmap.anchors:
            raise PlannerError(f"anchor {anchor!r} is not in the roadmap "
                               f"(it has {', '.join(sorted(self.roadmap.anchors)) or 'no anchors'})")
        return int(self.roadmap.anchors[anchor])

    def config(self, vertex: int) -> tuple[float, ...]:
        return tuple(float(x) for x in self._configs[vertex])

    def best_path(self, start: int, goal: int, obstacles: frozenset[str]) -> RoadmapPath | None:
        """A shortest path from `start` to `goal` using no edge blocked by a
        place in `obstacles`; None if there is none."""
        dist, pred = self._tree(start, obstacles)
        if not math.isfinite(dist[goal]):
            return None
        vertices = [goal]
        while vertices[-1] != start:
            vertices.append(int(pred[vertices[-1]]))
        vertices.reverse()
        edges = [self._edge[min(a, b), max(a, b)] for a, b in zip(vertices, vertices[1:])]
        length = sum((float(self._lengths[e]) for e in edges), 0.0)
        touched = frozenset().union(*(self._blocked[e] for e in edges))
        return RoadmapPath(tuple(vertices), length, touched)

    def _tree(self, source: int, obstacles: frozenset[str]) -> tuple[np.ndarray, np.ndarray]:
        if obstacles not in self._removed:
            unknown = obstacles - self.places
            if unknown:
                raise PlannerError(f"obstacles {sorted(unknown)} are not places of this costmap")
            removed = np.zeros(len(self._lengths), dtype=bool)
            for x in sorted(obstacles):
                removed |= self._blocks[x]
            self._removed[obstacles] = removed, np.packbits(removed).tobytes()
        removed, key = self._removed[obstacles]
        if source != self._source:
            self._source, self._trees = source, {}
        if key not in self._trees:
            from scipy.sparse import csr_matrix  # see dijkstra() below

            keep = ~removed[self._arc_edge]
            n = len(self._configs)
            indptr = np.concatenate([[0], np.cumsum(np.bincount(self._tails[keep], minlength=n))])
            graph = csr_matrix((self._lengths[self._arc_edge[keep]], self._heads[keep], indptr), shape=(n, n))
            self._trees[key] = dijkstra(graph, directed=True, indices=source, return_predecessors=True)
        return self._trees[key]

    def rule(self, free: frozenset[str], path: RoadmapPath, per_radian: float) -> Rule:
        return Rule(free, per_radian * path.length, tuple(self.config(v) for v in path.vertices))


def dijkstra(graph, **options):
    """scipy's Dijkstra, imported on first use: every `symsynth` command
    imports this module (for METHODS) and scipy.sparse costs 0.3 s to load."""
    from scipy.sparse.csgraph import dijkstra as scipy_dijkstra

    return scipy_dijkstra(graph, **options)


def _checked(roadmap: Roadmap, blocked: list[frozenset[str]], places: frozenset[str],
             n: int) -> tuple[np.ndarray, np.ndarray]:
    """The roadmap's edges as an (m, 2) int array and lengths as floats,
    after checking that roadmap and blocked-by sets fit together."""
    if np.ndim(roadmap.configs) != 2:
        raise PlannerError("roadmap configs must be an (n, d) array, "
                           f"found shape {np.shape(roadmap.configs)}")
    edges = np.asarray(roadmap.edges)
    if edges.size == 0:
        edges = np.zeros((0, 2), dtype=np.int64)
    if edges.ndim != 2 or edges.shape[1] != 2 or not np.issubdtype(edges.dtype, np.integer):
        raise PlannerError("roadmap edges must be an (m, 2) integer array, "
                           f"found {edges.dtype} {edges.shape}")
    edges = edges.astype(np.int64)
    lengths = np.asarray(roadmap.lengths, dtype=float).reshape(-1)
    if len(lengths) != len(edges) or len(blocked) != len(edges):
        raise PlannerError(f"roadmap has {len(edges)} edges but {len(lengths)} lengths "
                           f"and {len(blocked)} blocked-by sets")
    if len(edges) and (edges.min() < 0 or edges.max() >= n):
        raise PlannerError(f"roadmap edges name vertices outside 0..{n - 1}")
    if not np.all(np.isfinite(lengths)) or np.any(lengths < 0):
        raise PlannerError("roadmap edge lengths must be finite and >= 0")
    if np.any(edges[:, 0] == edges[:, 1]):
        raise PlannerError(f"roadmap edge {int(np.argmax(edges[:, 0] == edges[:, 1]))} is a loop")
    pairs = np.sort(edges, axis=1)
    if len(np.unique(pairs, axis=0)) != len(edges):
        raise PlannerError("roadmap lists an undirected edge twice")
    for e, b in enumerate(blocked):
        if not set(b) <= places:
            raise PlannerError(f"edge {e} is blocked by {sorted(set(b) - places)}, which are not places "
                               f"(places: {sorted(places)})")
    for name, v in roadmap.anchors.items():
        if not 0 <= int(v) < n:
            raise PlannerError(f"anchor {name!r} is vertex {v}, outside 0..{n - 1}")
    return edges, lengths


def candidates(search: RoadmapSearch, query: Query) -> frozenset[str]:
    """The places a rule of `query` may require free: places - always - never."""
    for name, group in (("always", query.always), ("never", query.never)):
        if not group <= search.places:
            raise PlannerError(f"{query.start} -> {query.goal}: {name} names "
                               f"{sorted(group - search.places)}, which are not places")
    if query.always & query.never:
        raise PlannerError(f"{query.start} -> {query.goal}: {sorted(query.always & query.never)} "
                           "cannot be both always and never occupied")
    return search.places - query.always - query.never


def start_goal(search: RoadmapSearch, query: Query, per_radian: float) -> tuple[Rule, ...]:
    """Alg. 2: one rule with `free = ∅`, the best path avoiding every
    candidate and `always`; no rule if there is none."""
    avoid = candidates(search, query) | query.always
    path = search.best_path(search.vertex(query.start), search.vertex(query.goal), avoid)
    return () if path is None else (search.rule(frozenset(), path, per_radian),)


def recursive(search: RoadmapSearch, query: Query, per_radian: float) -> tuple[Rule, ...]:
    """Alg. 3: for each obstacle set `obs` reached (from ∅), the best path
    `P_obs` avoiding `obs ∪ always` gives the rule (candidates it touches,
    its cost), and each of those candidates `l` leads to `obs ∪ {l}`.

    Exactness: for every set `S` of candidates, the least cost over the rules
    with `free ∩ S = ∅` is `per_radian * d(S)`, `d(S)` the shortest path
    avoiding `S ∪ always` (both infinite together).
    (>=) A rule `(F, c)` comes from some `P_obs`, which touches only places
    (candidates, always or never), no place of `always` and no candidate
    outside `F`; if `F ∩ S = ∅` it avoids `S ∪ always`, so
    `c >= per_radian * d(S)`.  Dropping dominated rules keeps
    this least cost: a satisfied dropped rule has a satisfied dominating rule
    no dearer.
    (<=) Let `d(S)` be finite.  Start at `obs = ∅` and keep the invariant
    `obs ⊆ S`, hence `cost(P_obs) <= per_radian * d(S)` (every path avoiding
    `S ∪ always` avoids `obs ∪ always`, so `P_obs` exists and is no longer).
    Its rule has `F = touched(P_obs) ∩ candidates`, disjoint from `obs`.  If
    `F ∩ S = ∅` the rule is satisfied with cost <= `per_radian * d(S)`.
    Otherwise some `l ∈ F ∩ S` makes `obs ∪ {l} ⊆ S` a strictly larger set,
    also reached (memoized or not, its rule is emitted); candidates are
    finite, so the chain ends at a satisfied rule.
    """
    start, goal = search.vertex(query.start), search.vertex(query.goal)
    cands = candidates(search, query)
    rules = []
    seen: set[frozenset[str]] = {frozenset()}
    todo: deque[frozenset[str]] = deque([frozenset()])
    while todo:
        obs = todo.popleft()
        path = search.best_path(start, goal, obs | query.always)
        if path is None:
            continue
        new = path.touched & cands  # disjoint from obs: the path avoids it
        rules.append(search.rule(new, path, per_radian))
        for place in sorted(new):
            if obs | {place} not in seen:
                seen.add(obs | {place})
                todo.append(obs | {place})
    return undominated(rules)


def undominated(rules: Iterable[Rule]) -> tuple[Rule, ...]:
    """The rules no other rule dominates (`free ⊆` and `cost <=`; of equal
    rules the first is kept), sorted by cost, then by sorted `free`."""
    kept: list[Rule] = []
    # Dominators come first in this order, so comparing with kept rules suffices.
    for rule in sorted(rules, key=lambda r: (r.cost, len(r.free), sorted(r.free))):
        if not any(k.free <= rule.free for k in kept):
            kept.append(rule)
    return tuple(sorted(kept, key=lambda r: (r.cost, sorted(r.free))))


Method = Callable[[RoadmapSearch, Query, float], tuple[Rule, ...]]
METHODS: dict[str, Method] = {"sg": start_goal, "recursive": recursive}


def costmap_for_mode(mode: Mode | str, roadmap: Roadmap, blocked: list[frozenset[str]],
                     queries: Iterable[Query], method: Method | str, places: Iterable[str],
                     per_radian: float = 1.0) -> dict[Key, tuple[Rule, ...]]:
    """The rules of every query in one mode: `{(str(mode), start, goal): rules}`
    in query order (a motion without rules maps to `()`).

    `blocked[e]` is the set of places edge `e` touches; every place it names
    must be in `places`.  `method` is a `METHODS` name or function.  Queries
    are answered grouped by start anchor, so that each (start, obstacle set)
    is one Dijkstra for all goals.
    """
    if isinstance(method, str):
        if method not in METHODS:
            raise PlannerError(f"unknown costmap method {method!r} (known: {', '.join(METHODS)})")
        method = METHODS[method]
    if not (isinstance(per_radian, (int, float)) and math.isfinite(per_radian) and per_radian >= 0):
        raise PlannerError(f"per_radian must be a finite number >= 0, found {per_radian!r}")
    search = RoadmapSearch(roadmap, blocked, places)
    label = str(mode)
    asked: dict[Key, Query] = {}
    for query in queries:
        key = (label, query.start, query.goal)
        if asked.setdefault(key, query) != query:
            raise PlannerError(f"{label}: {query.start} -> {query.goal} asked twice with different "
                               f"always/never sets ({asked[key]} and {query})")
    answers = {}
    for key in sorted(asked, key=lambda k: (search.vertex(k[1]), k[1], k[2])):
        answers[key] = method(search, asked[key], float(per_radian))
    return {key: answers[key] for key in asked}
