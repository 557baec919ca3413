"""From a physical scene to a costmap and a game, with a planner simple
enough to solve by hand (tests/support/planar.py: a point robot in the unit square).

The expected values are worked out here from the geometry: grid distances,
which place blocks which gap, what the game must conclude."""

import dataclasses
import json
import math

import pytest

from support.planar import PlanarPlanner, planar_scene
from symsynth.errors import SymsynthWarning
from symsynth.solvers import SOLVERS
from symsynth.game.solution import task_formula
from symsynth.planning import cache
from symsynth.planning.anchors import anchor_configs, mode_queries
from symsynth.planning.build import compute_costmap, obtain_costmap
from symsynth.planning.methods import Query
from symsynth.planning.protocol import Mode, PlannerError
from symsynth.planning.verify import path_length, verify_costmap
from symsynth.scene.costmap import Costmap, Provenance
from support.planar import WALL, gap_scene

# A wall at y = 0.3 with a gap at x in [0.45, 0.55]; place P sits in the gap.
# South: home (0, 0), l2 (0.8, 0.18), l3 (0.35, 0.12) to park a, Else e1 (0.2, 0.18).  North: l1 (0.5, 0.58).
# Anchors lie 0.08 south of their place: l1/top at (0.5, 0.5), a grid vertex.


def build(scene, method):
    return compute_costmap(scene, method, "planar", progress=False, planner_factory=PlanarPlanner)[0]


def solve(scene, costmap, k=0):
    scene = dataclasses.replace(scene, costmap=costmap, k=k)
    return {name: solver(scene, task_formula(scene, None), k=k).cost_bound for name, solver in SOLVERS.items()}


def test_straight_motion_costs_its_grid_distance():
    scene = planar_scene(places={"l1": (0.5, 0.58), "l2": (0.2, 0.9)}, objects={"a": "l1"})
    costmap = build(scene, "recursive")
    # home (0, 0) to l1/top (0.5, 0.5): five grid diagonals of 0.1 * sqrt(2), 10 per radian.
    rule, = costmap.rules("empty", "home", "l1/top")
    assert rule.free == frozenset() and rule.cost == pytest.approx(10 * 5 * 0.1 * math.sqrt(2))
    # Holding a, l1/top to l2/top (0.2, 0.82): three diagonals to (0.2, 0.8), then 0.02.
    rule, = costmap.rules("a/top", "l1/top", "l2/top")
    assert rule.free == frozenset() and rule.cost == pytest.approx(10 * (3 * 0.1 * math.sqrt(2) + 0.02))
    assert rule.path[0] == pytest.approx((0.5, 0.5)) and rule.path[-1] == pytest.approx((0.2, 0.82))


def test_the_gap_start_goal_finds_nothing_recursive_asks_for_P_free():
    scene = gap_scene()
    sg, rec = build(scene, "sg"), build(scene, "recursive")
    # Holding b, from l2 (south) to l1 (north): the only way is through the gap at P.
    assert sg.rules("b/top", "l2/top", "l1/top") == ()
    rule, = rec.rules("b/top", "l2/top", "l1/top")
    assert rule.free == {"P"}
    # South of the wall nothing changes: both methods agree and need nothing free.
    assert sg.rules("a/top", "P/top", "l2/top") == rec.rules("a/top", "P/top", "l2/top")
    assert rec.rules("a/top", "P/top", "l2/top")[0].free == frozenset()


def test_start_goal_hovers_over_the_gap_recursive_goes_straight():
    """Start-goal has no motion from l2 to l1 holding b, but one through P
    holding b over P: while the hand holds over a location nobody can put
    anything there, so P is free on that leg.  The recursive costmap knows P is
    free once a is parked, and its bound is lower (never higher)."""
    scene = gap_scene()
    sg = solve(scene, build(scene, "sg"))
    rec = solve(scene, build(scene, "recursive"))
    assert sg["symbolic"] == sg["explicit"] is not None
    assert rec["symbolic"] == rec["explicit"] < sg["symbolic"]


def test_an_anchor_inside_another_place():
    """The arch's mechanism: the anchor l1/top lies where an object at P would
    be.  Arriving there needs P free: start-goal, which assumes P occupied, only
    arrives from over P itself (holding over P, P is free); recursive asks for P.
    Leaving it needs nothing of P: while the robot stands there, nothing can."""
    scene = planar_scene(places={"P": (0.5, 0.3), "l1": (0.5, 0.4), "l2": (0.8, 0.18)},
                         objects={"b": "l2"}, task="F(at(b, l1))")
    sg, rec = build(scene, "sg"), build(scene, "recursive")
    assert sg.rules("b/top", "l2/top", "l1/top") == ()
    assert [r.free for r in rec.rules("b/top", "l2/top", "l1/top")] == [{"P"}]
    assert len(sg.rules("b/top", "P/top", "l1/top")) == 1
    for costmap in (sg, rec):
        assert [r.free for r in costmap.rules("empty", "l1/top", "l2/top")] == [frozenset()]
    values = solve(scene, sg), solve(scene, rec)
    assert values[1]["symbolic"] == values[1]["explicit"] <= values[0]["symbolic"] == values[0]["explicit"]


def test_every_evidence_path_verifies_and_a_tampered_one_fails():
    scene = gap_scene()
    costmap = build(scene, "recursive")
    planner = PlanarPlanner(scene)
    checked, failures = verify_costmap(costmap, scene, planner, 0.005, progress=False)
    assert checked == sum(len(r) for r in costmap.motions.values()) > 0 and failures == []
    key = ("b/top", "l2/top", "l1/top")
    rule, = costmap.motions[key]
    lies = {key: (dataclasses.replace(rule, free=frozenset()),  # it does pass through P
                  dataclasses.replace(rule, cost=rule.cost + 1))}
    _, failures = verify_costmap(Costmap(lies), scene, planner, 0.005, progress=False)
    reasons = sorted(f.reason for f in failures)
    assert any("touches P" in r for r in reasons)
    assert any(r.startswith("cost ") for r in reasons)
    # a path that starts on P itself and goes straight up to l1: not from the anchor, and it still touches P
    path = ((0.5, 0.3), (0.5, 0.4), (0.5, 0.5))
    inside = dataclasses.replace(rule, free=frozenset(), path=path,
                                 cost=scene.geometry.per_radian * path_length(path))
    _, failures = verify_costmap(Costmap({key: (inside,)}), scene, planner, 0.005, progress=False)
    assert [f.reason for f in failures] == ["starts at (0.500, 0.300), not at anchor l2/top (0.800, 0.100)",
                                            "touches P, which the rule assumes may be occupied"]


def test_a_path_that_does_not_join_the_anchors_fails():
    """Holding b from l2/top (0.8, 0.1) to l1/top (0.5, 0.5) needs P free; a
    short path elsewhere, touching nothing, at its own cost, proves nothing."""
    scene = gap_scene()
    planner = PlanarPlanner(scene)
    key = ("b/top", "l2/top", "l1/top")
    rule, = build(scene, "recursive").motions[key]

    def priced(path):
        return dataclasses.replace(rule, free=frozenset(), path=path,
                                   cost=scene.geometry.per_radian * path_length(path))

    elsewhere = priced(((0.1, 0.1), (0.15, 0.1)))
    _, failures = verify_costmap(Costmap({key: (elsewhere,)}), scene, planner, 0.005, progress=False)
    assert [f.reason for f in failures] == ["starts at (0.100, 0.100), not at anchor l2/top (0.800, 0.100)",
                                            "ends at (0.150, 0.100), not at anchor l1/top (0.500, 0.500)"]
    # the built path with only its ends moved 1 cm (still clear of everything): both ends fail, nothing else
    shifted = [tuple(q) for q in rule.path]
    shifted[0], shifted[-1] = (0.81, 0.1), (0.5, 0.51)
    moved = dataclasses.replace(rule, path=tuple(shifted),
                                cost=scene.geometry.per_radian * path_length(shifted))
    _, failures = verify_costmap(Costmap({key: (moved,)}), scene, planner, 0.005, progress=False)
    assert [f.reason for f in failures] == ["starts at (0.810, 0.100), not at anchor l2/top (0.800, 0.100)",
                                            "ends at (0.500, 0.510), not at anchor l1/top (0.500, 0.500)"]


def test_motions_follow_the_spec():
    scene = gap_scene()
    empty = mode_queries(scene, Mode())
    anchors = ["P/top", "l1/top", "l2/top", "l3/top", "e1/top"]
    assert {(q.start, q.goal) for q in empty} == {(s, t) for s in ["home"] + anchors for t in anchors if s != t}
    assert all(q.always == {q.goal.split("/")[0]} and not q.never for q in empty)
    held = {(q.start, q.goal): q for q in mode_queries(scene, Mode("a", "top"))}
    # targets are locations of interest only; a start over a location is free, as is the target
    assert held[("l2/top", "l1/top")] == Query("l2/top", "l1/top", never=frozenset({"l1", "l2"}))
    assert held[("e1/top", "P/top")] == Query("e1/top", "P/top", never=frozenset({"P"}))
    assert ("l1/top", "e1/top") not in held and ("P/top", "P/top") not in held


def test_unreachable_and_colliding_anchors_are_named():
    scene = planar_scene(places={"l1": (0.5, 0.58), "far": (1.5, 0.5), "wall": (0.3, 0.38)},
                         objects={"a": "l1"}, obstacles={"w": (0.3, 0.3, 0.05, 0.05)})
    with pytest.raises(PlannerError) as caught:
        anchor_configs(PlanarPlanner(scene), scene)
    message = str(caught.value)
    assert "far/top: unreachable" in message
    assert "wall/top: the robot collides with itself or a static obstacle" in message
    assert "l1/top" not in message


def test_cache_same_seed_same_file(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    first = obtain_costmap(scene, "recursive", "planar", progress=False, planner_factory=PlanarPlanner)
    again = obtain_costmap(scene, "recursive", "planar", progress=False, planner_factory=PlanarPlanner)
    assert not first.cached and again.cached and again.path == first.path
    assert again.costmap == first.costmap
    assert [r.path for r in again.costmap.motions[("b/top", "l2/top", "l1/top")]] == \
        [r.path for r in first.costmap.motions[("b/top", "l2/top", "l1/top")]]
    other = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    assert not other.cached and other.path != first.path
    # the task and k do not change the costmap; geometry does
    retask = dataclasses.replace(scene, task="F(at(a, l1))", k=3)
    assert obtain_costmap(retask, "recursive", "planar", progress=False,
                          planner_factory=PlanarPlanner).cached
    moved = planar_scene(places={"P": (0.5, 0.3), "l1": (0.5, 0.6), "l2": (0.8, 0.18)},
                         objects={"a": "P", "b": "l2"}, obstacles=WALL, else_samples={"e1": (0.2, 0.18)})
    assert not obtain_costmap(moved, "recursive", "planar", progress=False,
                              planner_factory=PlanarPlanner).cached


def test_a_costmap_records_who_built_it():
    """The planar planner is no installed plugin: no version."""
    scene = gap_scene()
    settings = scene.geometry.planner
    assert build(scene, "sg").provenance == Provenance("planar", None, "sg", settings.seed, settings.roadmap_size,
                                                       None, settings.check_step)
    timed = compute_costmap(timed_scene(1.5), "recursive", "planar", seed=7, progress=False,
                            planner_factory=TimedPlanar)[0]
    assert timed.provenance == Provenance("planar", None, "recursive", 7, None, 1.5, settings.check_step)


def test_a_cached_costmap_without_a_record_gets_it_one_of_another_version_is_computed_again(tmp_path,
                                                                                          monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    first = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    data = json.loads(first.path.read_text())
    assert data["planner"]["name"] == "planar"
    recorded = data.pop("planner")
    data[cache.SUM_FIELD] = cache.checksum(data)
    first.path.write_text(json.dumps(data))  # as written before costmaps recorded their planner
    older = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    assert older.cached and older.costmap.provenance == first.costmap.provenance
    other_version = dict(data, planner=dict(recorded, version="9.9"))
    first.path.write_text(json.dumps(other_version | {cache.SUM_FIELD: cache.checksum(other_version)}))
    other = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    assert not other.cached and other.costmap.provenance == first.costmap.provenance
    assert json.loads(first.path.read_text())["planner"] == recorded  # overwritten


def test_a_damaged_cache_entry_is_computed_again(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    first = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    first.path.write_text("{not json")
    with pytest.warns(SymsynthWarning, match="is not used and is computed again: .*not JSON"):
        again = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    assert not again.cached and again.costmap == first.costmap
    assert obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner).cached


def test_an_unwritable_cache_is_said_before_the_work_and_the_result_kept(tmp_path, monkeypatch):
    """The cache folder cannot be made: a warning before the planning starts
    (not an error after it), and the costmap computed is returned, uncached."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("SYMSYNTH_CACHE", str(blocker / "cache"))  # a folder inside a file
    planned = []

    class Watched(PlanarPlanner):
        def roadmap(self, *args, **kwargs):
            planned.append(len(caught))
            return super().roadmap(*args, **kwargs)

    with pytest.warns(SymsynthWarning, match="costmap cache .* cannot be written .*SYMSYNTH_CACHE") as caught:
        got = obtain_costmap(gap_scene(), "sg", "planar", progress=False, planner_factory=Watched)
    assert planned and planned[0] == 1  # warned before the first roadmap
    assert got.path is None and not got.cached
    assert got.costmap == build(gap_scene(), "sg")



class TimedPlanar(PlanarPlanner):
    """The planar planner, recording the time limit it is given."""

    seen: list = []
    time_limited = True

    def roadmap(self, mode, anchors, size, seed, seconds=None):
        TimedPlanar.seen.append(seconds)
        return super().roadmap(mode, anchors, size, seed)


def timed_scene(seconds):
    scene = gap_scene()
    settings = dataclasses.replace(scene.geometry.planner, seconds=seconds)
    return dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))


def test_a_roadmap_time_limit_reaches_the_planner_and_the_cache_key(tmp_path, monkeypatch):
    TimedPlanar.seen.clear()
    compute_costmap(timed_scene(1.5), "sg", "planar", progress=False, planner_factory=TimedPlanar)
    assert TimedPlanar.seen and set(TimedPlanar.seen) == {1.5}
    TimedPlanar.seen.clear()
    compute_costmap(timed_scene(None), "sg", "planar", progress=False, planner_factory=TimedPlanar)
    assert TimedPlanar.seen and set(TimedPlanar.seen) == {None}
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    paths = {cache.cache_path(timed_scene(s), "sg", "planar", 0) for s in (None, 1.5, 2.0)}
    assert len(paths) == 3


def test_a_time_limit_with_a_planner_that_has_none_is_one_message():
    with pytest.raises(PlannerError, match="the planar planner has no roadmap time limit"):
        compute_costmap(timed_scene(1.5), "sg", "planar", progress=False, planner_factory=PlanarPlanner)


class CountedPlanar(PlanarPlanner):
    """The planar planner, counting how often it is built."""

    built = 0

    def __init__(self, scene):
        CountedPlanar.built += 1
        super().__init__(scene)


def test_a_time_limit_is_refused_before_the_planner_is_built(monkeypatch):
    """(the pybullet planner loads its URDF when built), and before the cache key is hashed"""
    CountedPlanar.built = 0
    with pytest.raises(PlannerError, match="the planar planner has no roadmap time limit"):
        compute_costmap(timed_scene(1.5), "sg", "planar", progress=False, planner_factory=CountedPlanar)
    monkeypatch.setattr(cache, "cache_path", lambda *args: pytest.fail("the cache key was computed"))
    with pytest.raises(PlannerError, match="the planar planner has no roadmap time limit"):
        obtain_costmap(timed_scene(1.5), "sg", "planar", progress=False, planner_factory=CountedPlanar)
    assert CountedPlanar.built == 0
