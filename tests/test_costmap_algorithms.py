"""The start-goal and recursive costmap algorithms against brute force.

Expected values come from a plain Bellman-Ford over the edges left after
removing those blocked by the occupied places (no scipy), from hand-built
roadmaps whose answers are computed by hand, and from re-running the code
on fresh inputs.  Edge lengths are small integers so every sum is exact.
"""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from symsynth.planning import methods
from symsynth.planning.methods import (METHODS, Query, costmap_for_mode, recursive, start_goal,
                                        undominated)
from symsynth.planning.protocol import Mode, PlannerError, Roadmap
from symsynth.scene.costmap import Costmap, Rule

PLACES = ("a", "b", "c", "d")
PER_RADIAN = 2.0
FEW = settings(max_examples=200, deadline=None)


def rule(cost, *free):
    return Rule(frozenset(free), cost)


def config(i):
    return (float(i), 0.5 * i)


def roadmap(n, edges, lengths, anchors):
    return Roadmap(np.array([config(i) for i in range(n)]), np.array(edges, dtype=np.int64).reshape(-1, 2),
                   np.array(lengths, dtype=float), anchors)


@st.composite
def problems(draw):
    """A random graph (<= 12 vertices) with blocked-by sets over <= 4 places,
    an anchor pair and disjoint always/never sets."""
    n = draw(st.integers(1, 12))
    places = PLACES[:draw(st.integers(0, 4))]
    some = (lambda size: st.just(frozenset())) if not places else (
        lambda size: st.frozensets(st.sampled_from(places), max_size=size))
    pairs = list(itertools.combinations(range(n), 2))
    edges = draw(st.lists(st.sampled_from(pairs), unique=True, min_size=min(n, len(pairs)),
                          max_size=30)) if pairs else []
    lengths = [draw(st.integers(0, 9)) for _ in edges]
    blocked = [draw(some(2)) for _ in edges]
    s, t = draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))
    always = draw(some(1))
    never = draw(some(1)) - always
    return roadmap(n, edges, lengths, {"s": s, "t": t}), blocked, places, Query("s", "t", always, never)


def brute_force(rm, blocked, occupied, s, t):
    """Shortest s-t length using no edge blocked by `occupied` (Bellman-Ford)."""
    dist = [math.inf] * len(rm.configs)
    dist[s] = 0.0
    usable = [(int(i), int(j), float(w)) for (i, j), w, b in zip(rm.edges, rm.lengths, blocked)
              if not b & occupied]
    for _ in range(len(dist)):
        for i, j, w in usable:
            dist[j] = min(dist[j], dist[i] + w)
            dist[i] = min(dist[i], dist[j] + w)
    return dist[t]


def bound(rules, occupied):
    """What a costmap says for one motion when `occupied` are occupied."""
    return min((r.cost for r in rules if not r.free & occupied), default=math.inf)


def subsets(places):
    return [frozenset(c) for k in range(len(places) + 1) for c in itertools.combinations(sorted(places), k)]


def check_evidence(rule, rm, blocked, query, places):
    """The evidence path is a real s-t path of the roadmap costing `rule.cost`
    and touching no place outside `free` but `never` places."""
    vertex = {config(i): i for i in range(len(rm.configs))}
    edge = {frozenset((int(i), int(j))): e for e, (i, j) in enumerate(rm.edges)}
    walk = [vertex[q] for q in rule.path]
    assert walk[0] == rm.anchors[query.start] and walk[-1] == rm.anchors[query.goal]
    used = [edge[frozenset(step)] for step in zip(walk, walk[1:])]  # KeyError: not an edge
    assert rule.cost == PER_RADIAN * sum(float(rm.lengths[e]) for e in used)
    touched = frozenset().union(*(blocked[e] for e in used))
    assert touched <= rule.free | query.never
    assert rule.free <= frozenset(places) - query.always - query.never


@FEW
@given(problems())
def test_recursive_bound_is_exact_for_every_occupied_set(problem):
    rm, blocked, places, query = problem
    rules = recursive(methods.RoadmapSearch(rm, blocked, places), query, PER_RADIAN)
    s, t = rm.anchors["s"], rm.anchors["t"]
    for occupied in subsets(frozenset(places) - query.always - query.never):
        expected = brute_force(rm, blocked, occupied | query.always, s, t)
        assert bound(rules, occupied) == PER_RADIAN * expected, occupied
    for rule in rules:
        check_evidence(rule, rm, blocked, query, places)
    assert all(not (a.free <= b.free and a.cost <= b.cost) for a, b in itertools.permutations(rules, 2))
    assert [(r.cost, sorted(r.free)) for r in rules] == sorted((r.cost, sorted(r.free)) for r in rules)


@FEW
@given(problems())
def test_start_goal_is_the_all_occupied_path_and_never_beats_recursive(problem):
    rm, blocked, places, query = problem
    search = methods.RoadmapSearch(rm, blocked, places)
    sg, rec = start_goal(search, query, PER_RADIAN), recursive(search, query, PER_RADIAN)
    candidates = frozenset(places) - query.always - query.never
    expected = brute_force(rm, blocked, candidates | query.always, rm.anchors["s"], rm.anchors["t"])
    if math.isinf(expected):
        assert sg == ()
    else:
        assert [(r.free, r.cost) for r in sg] == [(frozenset(), PER_RADIAN * expected)]
        check_evidence(sg[0], rm, blocked, query, places)
    for occupied in subsets(candidates):
        assert bound(rec, occupied) <= bound(sg, occupied)


# The arch: the only way to the support at l2 passes where the top (l3) will stand.
ARCH = roadmap(3, [(0, 1), (1, 2)], [1, 1], {"home": 0, "l2/top": 2})
ARCH_BLOCKED = [frozenset(), frozenset({"l3"})]


def test_arch_needs_the_recursive_method():
    query = Query("home", "l2/top", always=frozenset({"l2"}))  # transit: the block stands at l2
    search = methods.RoadmapSearch(ARCH, ARCH_BLOCKED, ["l1", "l2", "l3"])
    assert start_goal(search, query, PER_RADIAN) == ()
    rules = recursive(search, query, PER_RADIAN)
    assert rules == (rule(4.0, "l3"),)
    assert rules[0].path == (config(0), config(1), config(2))


# A short motion past l2 (1 + 2) and a detour that touches nothing (3 + 4),
# plus a path past both l1 and l2 (2 + 2) that no rule should use.
DETOUR = roadmap(5, [(0, 1), (1, 2), (0, 3), (3, 2), (0, 4), (4, 2)], [1, 2, 3, 4, 2, 2],
                 {"home": 0, "l1/top": 2})
DETOUR_BLOCKED = [frozenset(), frozenset({"l2"}), frozenset(), frozenset(), frozenset({"l1", "l2"}),
                  frozenset()]


def test_detour_gives_two_rules():
    search = methods.RoadmapSearch(DETOUR, DETOUR_BLOCKED, ["l1", "l2", "l3"])
    rules = recursive(search, Query("home", "l1/top"), 1.0)
    assert rules == (rule(3.0, "l2"), rule(7.0))
    assert [r.path for r in rules] == [(config(0), config(1), config(2)), (config(0), config(3), config(2))]
    assert start_goal(search, Query("home", "l1/top"), 1.0) == (rule(7.0),)


def test_never_places_are_ignored_and_always_places_avoided():
    search = methods.RoadmapSearch(DETOUR, DETOUR_BLOCKED, ["l1", "l2", "l3"])
    # l2 is the target of a transfer: never occupied, the short path is free.
    rules = recursive(search, Query("home", "l1/top", never=frozenset({"l2"})), 1.0)
    assert rules == (rule(3.0),) and rules[0].path == (config(0), config(1), config(2))
    # l2 always occupied: only the detour, and l2 is in no rule.
    assert recursive(search, Query("home", "l1/top", always=frozenset({"l2"})), 1.0) == (rule(7.0),)


def test_roadmap_without_edges():
    rm = roadmap(2, [], [], {"home": 0, "l1/top": 1})
    search = methods.RoadmapSearch(rm, [], ["l1"])
    for method in METHODS.values():
        assert method(search, Query("home", "l1/top"), 1.0) == ()
        assert method(search, Query("l1/top", "l1/top"), 1.0) == (rule(0.0),)


def test_motion_to_the_same_anchor_costs_nothing():
    rm = roadmap(2, [(0, 1)], [1], {"home": 1, "l1/top": 0})
    for method in METHODS.values():
        search = methods.RoadmapSearch(rm, [frozenset({"l1"})], ["l1"])
        rules = method(search, Query("home", "home", always=frozenset({"l1"})), PER_RADIAN)
        assert rules == (rule(0.0),) and rules[0].path == (config(1),)


def test_undominated_keeps_one_of_equal_rules_and_drops_supersets():
    # {b, c} sorts before {c} by name: it must still lose to it at equal cost.
    rules = [rule(3.0, "b", "c"), rule(3.0, "c"), Rule(frozenset({"c"}), 3.0, ((1.0,),)),
             rule(1.0, "a"), rule(2.0, "a", "d"), rule(5.0), rule(3.0, "b", "d")]
    kept = undominated(rules)
    # by cost, then by sorted free
    assert kept == (rule(1.0, "a"), rule(3.0, "b", "d"), rule(3.0, "c"), rule(5.0))
    assert kept[2].path is None  # the first of two equal rules


def count_searches(monkeypatch):
    calls = []
    real = methods.dijkstra

    def counting(graph, **kwargs):
        calls.append(kwargs["indices"])
        return real(graph, **kwargs)

    monkeypatch.setattr(methods, "dijkstra", counting)
    return calls


def test_one_search_per_source_and_obstacle_set(monkeypatch):
    calls = count_searches(monkeypatch)
    anchors = {"home": 0, "l1/top": 2, "x": 1, "y": 3, "z": 4}
    rm = Roadmap(DETOUR.configs, DETOUR.edges, DETOUR.lengths, anchors)
    # Interleaved sources: grouped by start, so one Dijkstra per start.
    queries = [Query("home", "l1/top"), Query("x", "y"), Query("home", "y"), Query("x", "z"),
               Query("home", "z")]
    result = costmap_for_mode(Mode(), rm, DETOUR_BLOCKED, queries, "sg", ["l1", "l2", "l3"])
    assert sorted(calls) == [0, 1]
    assert list(result) == [("empty", q.start, q.goal) for q in queries]
    # Recursive from home: obstacle sets {} and {l2} serve both goals.
    calls.clear()
    costmap_for_mode("empty", rm, DETOUR_BLOCKED, [Query("home", "l1/top"), Query("home", "x")],
                     "recursive", ["l1", "l2", "l3"])
    assert calls == [0, 0]


def random_roadmap(seed, n=60, k=6, places=("l1", "l2", "l3", "e1", "e2")):
    """A k-nearest-neighbour roadmap in the unit square; a place blocks the
    edges whose midpoint is within 0.2 of its centre."""
    rng = np.random.default_rng(seed)
    points = rng.random((n, 2))
    centres = rng.random((len(places), 2))
    near = np.argsort(np.linalg.norm(points[:, None] - points[None], axis=2), axis=1)[:, 1:k + 1]
    edges = sorted({(min(i, j), max(i, j)) for i in range(n) for j in near[i].tolist()})
    lengths = [float(np.linalg.norm(points[i] - points[j])) for i, j in edges]
    mids = np.array([(points[i] + points[j]) / 2 for i, j in edges])
    blocked = [frozenset(x for x, c in zip(places, centres) if np.linalg.norm(m - c) < 0.2) for m in mids]
    anchors = {f"q{a}": a for a in range(0, n, 7)}
    return Roadmap(points, np.array(edges), np.array(lengths), anchors), blocked, places


def test_same_input_same_output_whatever_the_batch():
    def run(queries):
        rm, blocked, places = random_roadmap(seed=3)
        result = costmap_for_mode("w1/top", rm, blocked, queries, "recursive", places, per_radian=1.5)
        return json.dumps(Costmap(result).to_json())

    rm, _, _ = random_roadmap(seed=3)
    queries = [Query(s, t, always=frozenset({"l1"})) for s in rm.anchors for t in rm.anchors]
    first = run(queries)
    assert first == run(queries) == run(list(reversed(queries)))
    batch = json.loads(first)["motions"]
    assert any(len(m["rules"]) > 1 for m in batch)  # the recursion had work to do
    for q in queries[::7]:  # a query answered alone gets the same rules and paths
        alone = json.loads(run([q]))["motions"]
        assert alone == [m for m in batch if (m["from"], m["to"]) == (q.start, q.goal)]


@pytest.mark.parametrize("change, message", [
    (dict(queries=[Query("home", "nowhere")]), "anchor 'nowhere' is not in the roadmap"),
    (dict(blocked=[frozenset({"l9"}), frozenset()]), "edge 0 is blocked by ['l9']"),
    (dict(queries=[Query("home", "l2/top", frozenset({"l1"}), frozenset({"l1"}))]), "both always and never"),
    (dict(queries=[Query("home", "l2/top", frozenset({"l7"}))]), "always names ['l7']"),
    (dict(method="astar"), "unknown costmap method 'astar' (known: sg, recursive)"),
    (dict(per_radian=-1.0), "per_radian must be"),
    (dict(queries=[Query("home", "l2/top"), Query("home", "l2/top", frozenset({"l1"}))]), "asked twice"),
    (dict(roadmap=roadmap(3, [(0, 1), (1, 0)], [1, 1], {"home": 0})), "edge twice"),
    (dict(roadmap=roadmap(3, [(0, 1), (1, 1)], [1, 1], {"home": 0})), "edge 1 is a loop"),
    (dict(roadmap=roadmap(3, [(0, 1), (1, 2)], [1, -1], {"home": 0})), "finite and >= 0"),
    (dict(roadmap=roadmap(3, [(0, 1), (1, 2)], [1], {"home": 0})), "2 edges but 1 lengths"),
])
def test_bad_input_is_named(change, message):
    args = dict(mode=Mode(), roadmap=ARCH, blocked=ARCH_BLOCKED, queries=[Query("home", "l2/top")],
                method="recursive", places=["l1", "l2", "l3"], per_radian=1.0)
    args.update(change)
    with pytest.raises(PlannerError) as caught:
        costmap_for_mode(**args)
    assert message in str(caught.value)
