"""The compiled search's assignment bound (`solvers.packed.lower`, applied by
`search._tighten`): at every position reachable with k human moves, at either
turn, never above the explicit solver's value, on the pattern family with
its costmap redrawn at random (costs, conditional rules, missing motions,
two grasps); and a bound made one unit too high is caught by the same check."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from bench.gamefamily import pattern_data
from symsynth.game.abstraction import initial_state
from symsynth.game.graph import GameGraph, Node
from symsynth.logic import parse_ltlf
from symsynth.scene import scene_from_data
from symsynth.solvers import andor
from symsynth.solvers.explicit import _dijkstra
from symsynth.solvers.packed import search as sk
from symsynth.solvers.packed.lower import BoundTables
from symsynth.solvers.packed.tables import Tables


def _scene(seed: int):
    """A small pattern scene whose costmap is redrawn: each motion keeps a
    random 1-2 rules (costs 0-12, conditions on random places) or goes
    missing now and then; grab and drop 1-6; one scene in four without Else samples."""
    rng = random.Random(seed)
    n = rng.randint(2, 3)
    data = pattern_data(n, rng.randint(n + 1, 4), k=1, seed=seed, grasps=("top", "side")[:rng.randint(1, 2)])
    data["primitives"] = {"grab": rng.randint(1, 6), "drop": rng.randint(1, 6)}
    if rng.random() < 0.25:  # no Else samples: an object at Else cannot be reached
        data["else_samples"] = []
    places = data["locations"] + data["else_samples"]
    motions = []
    for motion in data["costmap"]["motions"]:
        ends = {motion["from"].split("/")[0], motion["to"].split("/")[0]} - {"home"}
        if rng.random() < 0.08 or not ends <= set(places):
            continue
        rules = [{"free": rng.sample(places, rng.randint(0, 2)), "cost": rng.randint(0, 12)}
                 for _ in range(rng.randint(1, 2))]
        motions.append(motion | {"rules": rules})
    data["costmap"] = data["costmap"] | {"motions": motions}
    return scene_from_data(data)


def _violations(scene, k: int, tamper=None) -> tuple[int, int, int]:
    """(positions checked, where the tightened bound is above the value,
    where it is above the bound a node is made with), at every position
    reachable with k human moves; `tamper` edits the bound's tables first."""
    formula = parse_ltlf(scene.task)
    game = GameGraph(scene, formula, 1.0)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    if game.accepts(q0):
        return 0, 0, 0
    nodes, edges = game.explore(Node(v0, q0, k, False))
    value, _ = _dijkstra(nodes, edges)
    tables = Tables(scene, formula, 1.0, None, k)
    bound = BoundTables(tables, formula)
    if tamper is not None:
        tamper(bound)
    memo = andor.Memo(tables, bound, k)
    memo.tighten()
    checked = above = raised = 0
    for i, node in enumerate(nodes):
        if i == 0 or game.accepts(node.q):
            continue
        j = memo.node(memo.key2(tables.pack(node.v), tables.dfa_index[node.q], node.h))
        made = memo.rec[j, sk.LO_R] if node.robot else memo.lo_h(j)
        sk._tighten(np.int64(j), sk.INF, memo.P, memo.B, memo.rec, memo.S()[10])
        b = memo.rec[j, sk.LO_R] if node.robot else memo.lo_h(j)
        checked += 1
        above += b > value.get(i, math.inf)
        raised += b > made
    return checked, above, raised


@pytest.mark.parametrize("chunk", range(4))
def test_never_above_the_value_on_random_costmaps(chunk):
    checked = raised = 0
    for seed in range(10 * chunk, 10 * chunk + 10):
        scene = _scene(seed)
        c, above, r = _violations(scene, 1)
        assert above == 0, scene.name
        checked += c
        raised += r
    assert checked > 300 and raised > 0  # the bound is on, and tighter than `_node`'s somewhere


def test_never_above_the_value_on_the_family():
    from bench.gamefamily import pattern_scene
    checked, above, raised = _violations(pattern_scene(3, 4, k=1), 1)
    assert above == 0 and checked > 1000 and raised > 100


def _one_unit_more(bound: BoundTables) -> None:
    """D one unit too long between any two places: inadmissible wherever
    the assignment is tight."""
    off = ~np.eye(bound.dist.shape[1], dtype=bool)
    bound.dist[:-1][off] += 1


def test_a_bound_one_unit_too_high_is_caught():
    """The check above is not vacuous: with every place distance one unit
    longer, some position's bound exceeds its value."""
    from bench.gamefamily import pattern_scene
    assert _violations(pattern_scene(3, 4, k=1), 1, _one_unit_more)[1] > 0


def test_off_when_a_location_has_two_candidates():
    """Interchangeable blocks (the sorting variant): the assignment of
    `packed.lower` needs one candidate per location, so it stays off."""
    scene = scene_from_data(pattern_data(3, 4, k=1, colours=2))
    formula = parse_ltlf(scene.task)
    assert not BoundTables(Tables(scene, formula, 1.0, None, 1), formula).assign
