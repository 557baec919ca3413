"""`solve --solver compiled --time-limit S` (symsynth/solvers/compiled.py,
packed/deadline.py): the layered solve when it is predicted to end in time
(then exact), else the AND-OR search on the same tables in the time left:
an interval [lower, upper] that holds the exact value (the explicit
solver's), with a strategy that pays at most upper against every human.
The clock ticks once per look (`TickClock`) and the AND-OR search's
questions are cut every few steps, so each limit stops the same way on
every machine; no test is timed."""

from __future__ import annotations

import itertools
import re
import sys
import weakref
from pathlib import Path

import numpy as np
import pytest
import yaml

from symsynth.cli import main
from symsynth.logic import parse_ltlf
from symsynth.solvers import andor, compiled
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.packed import deadline
from symsynth.testing.gamegen import alike_scene, random_scene
from support.games import TickClock, worst_case_of

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
from gamefamily import pattern_data  # noqa: E402


def _scene(seed):
    if seed % 4 == 0:
        return alike_scene(seed, contacts=seed % 8 == 0)
    return random_scene(5000 + seed, positive=True, contacts=seed % 3 == 0)


def _ticked(monkeypatch, chunk, replan_share=andor.REPLAN_SHARE):
    """Every clock a tick per look, the search's questions cut every `chunk`
    steps; `replan_share` of the time left goes to the replanning upper end."""
    andor.prepare()  # compiled before the clock is replaced
    monkeypatch.setattr(andor, "CHUNK", chunk)
    monkeypatch.setattr(andor, "REPLAN_SHARE", replan_share)
    monkeypatch.setattr(andor.time, "perf_counter", TickClock())


def test_layer_sizes_and_the_prediction_by_hand():
    # layers 3 and 2 closed (100 and 250 nodes), layer 2's human moves have seeded 30 of layer 1
    lo = np.array([0, 350, 100, 0])  # lo[0] unset yet
    sizes, passed = deadline.layer_sizes(2, 380, lo, 200)
    assert sizes == [100, 250, 30]
    assert passed == 2 * 100 + 250 + (200 - 100)  # layer 3 twice, layer 2's robot pass, half its human one
    # growth 2.5 from layer 3 to 2, its excess halving: 250 * 2.5 = 625, then 625 * 1.75
    assert deadline.predicted_sizes(sizes, 3) == [100, 250, 625, 1093.75]
    assert deadline.passes([100, 250, 625, 1093.75]) == 2 * (100 + 250 + 625) + 1093.75
    # layer 3 still closing: only what it holds, then FIRST_RATIO with its excess halving
    assert deadline.layer_sizes(3, 40, np.zeros(4, np.int64), 8) == ([40], 8)
    r = deadline.FIRST_RATIO
    assert deadline.predicted_sizes([40], 2) == [40, 40 * (1 + (r - 1) / 2), 40 * (1 + (r - 1) / 2) * (1 + (r - 1) / 4)]



def test_the_deadline_by_hand():
    """A limit of 10 s (ends at 9 s, the reserve left to the search): a
    batch past 9 s stops, one predicted past it stops, one predicted before
    it goes on; the solve is refused when exploring left too little for it."""
    def deadline_at(*times):
        return deadline.Deadline(10, clock=iter(times).__next__)  # start, then one time per look

    lo = np.zeros(4, np.int64)
    with pytest.raises(deadline.HandOver, match="was not done after 9.5 s"):
        deadline_at(0, 9.5).check(3, 10, lo, 1)
    # 100 nodes of layer 3 in 1 s: 100, 115, 123.6, 128.3 nodes, about 8.1 passes per node seen
    with pytest.raises(deadline.HandOver, match="was predicted to take about"):
        deadline_at(0, 1).check(3, 100, lo, 100)
    deadline_at(0, 0.1).check(3, 100, lo, 100)  # 0.1 s * 8.1 * 1.45: well before 9 s
    deadline_at(0, 2).check_solve(2.0, 100)  # 2 s + 0.45 * 2 s <= 9 s
    with pytest.raises(deadline.HandOver, match="too late to solve"):
        deadline_at(0, 7).check_solve(7.0, 100)

def test_in_time_the_layered_solve_answers_exactly():
    for seed in range(16):
        scene = _scene(seed)
        k = seed % 4
        got = compiled.solve_compiled(scene, k=k, time_limit=3600)
        assert got.exact and "handed_over" not in got.stats, seed
        assert got.units == solve_explicit(scene, k=k).units, seed


def test_intervals_hold_the_exact_value_when_it_hands_over(monkeypatch):
    """Limits of a few ticks: the layered solve runs out of them and hands
    the game to the search (or finishes, at the larger ones); every answer
    holds the explicit solver's value, and a strategy for upper (the
    replanning one where its share has no end) pays at most upper against
    every human behaviour."""
    kinds = {"layered": 0, "handed over, exact": 0, "interval": 0, "upper": 0}
    settings = [(10, 4, 0.25), (20, 12, 0.25), (40, 24, 0.25), (20, 60, 0.25), (80, 400, 0.25),
                (10, 12, 1e12), (40, 40, 1e12)]
    for (chunk, limit, share), seed in itertools.product(settings,
                                                         itertools.islice((s for s in range(60) if s % 4), 12)):
        scene = _scene(seed)
        k = 1 + seed % 3
        exact = solve_explicit(scene, k=k).units
        _ticked(monkeypatch, chunk, share)
        try:
            found = compiled.solve_compiled(scene, k=k, time_limit=limit)
        finally:
            monkeypatch.undo()
        if "handed_over" not in found.stats:
            kinds["layered"] += 1
            assert found.exact and found.units == exact, seed
            continue
        assert found.stats["handed_over"].startswith("the layered solve "), found.stats
        if found.exact:
            kinds["handed over, exact"] += 1
            assert found.units == exact, seed
            continue
        kinds["interval"] += 1
        assert exact is None or found.lower_units <= exact, seed
        if found.units is not None:
            kinds["upper"] += 1
            assert exact is not None and exact <= found.units, seed
            assert worst_case_of(scene, found, parse_ltlf(scene.task)) <= found.units, seed
    assert min(kinds.values()) >= 3, kinds


def test_a_prediction_beyond_the_limit_hands_over_at_once(monkeypatch):
    """A predicted size past the limit stops the layered solve at its first
    batch; the search, with the whole limit, proves the exact value."""
    monkeypatch.setattr(deadline, "predicted_sizes", lambda sizes, k: [1e15] * (k + 1))
    _hands_over_exactly("was predicted to take about")


def _hands_over_exactly(reason):
    """Scenes whose layered solve hands over for `reason` (the caller's patch),
    answered exactly by the search with the whole limit."""
    for seed in (1, 2, 5):
        scene = _scene(seed)
        got = compiled.solve_compiled(scene, k=2, time_limit=3600)
        assert reason in got.stats["handed_over"], got.stats
        assert got.exact and got.units == solve_explicit(scene, k=2).units, seed


def test_the_memory_prediction_by_hand(monkeypatch):
    """A million nodes in 100 MB (the process held 500 MB at the start,
    outside the memory then available), ten million predicted: 1 GB for
    the layers and 12 bytes a node to solve them, 1.12 GB in all; more than
    80 % of 1.2 GB hands over, within 80 % of 2 GB goes on; where the memory
    is not known, or before a million nodes, nothing is predicted."""
    def deadline_with(memory):
        resident = iter([500_000_000, 600_000_000]).__next__  # at the start, then at the check
        return deadline.Deadline(10, clock=lambda: 0.0, memory=memory, resident=resident)

    with pytest.raises(deadline.HandOver, match=r"need about 1\.1 GB for 10,000,000 nodes, more than 80% of the 1\.2 GB"):
        deadline_with(1_200_000_000)._check_memory(1_000_000, 10_000_000)
    deadline_with(2_000_000_000)._check_memory(1_000_000, 10_000_000)
    deadline_with(2_000_000_000)._check_memory(999_999, 10 ** 12)
    monkeypatch.setattr(deadline, "available_memory", lambda: None)
    deadline.Deadline(10, clock=lambda: 0.0)._check_memory(10 ** 6, 10 ** 12)


def test_a_game_past_the_memory_hands_over(monkeypatch):
    """The layered solve predicted to need more memory than the machine has
    (here: 1 byte available, less than the solve's own arrays for one node,
    predicted from the first node) hands the game to the search, whose
    answer holds the exact value, with the reason on the answer."""
    monkeypatch.setattr(deadline, "available_memory", lambda: 1)
    monkeypatch.setattr(deadline, "MEMORY_AFTER", 1)
    _hands_over_exactly("was predicted to need about")


def test_the_layered_arrays_are_gone_when_the_search_runs(monkeypatch):
    """Peak memory: the explored arrays go with the layered solve's frames
    before the search starts (`lo` stands for them)."""
    seen = []
    search = andor.search_tables

    def stop(self, h, nodes, lo, done):
        seen.append(weakref.ref(lo))
        raise deadline.HandOver("was stopped by the test")

    def searched(*args, **kwargs):
        assert seen and seen[0]() is None, "the layered arrays are still held"
        return search(*args, **kwargs)

    monkeypatch.setattr(deadline.Deadline, "check", stop)
    monkeypatch.setattr(andor, "search_tables", searched)
    got = compiled.solve_compiled(_scene(1), k=2, time_limit=3600)
    assert got.stats["handed_over"].startswith("the layered solve was stopped by the test")


def test_the_command_prints_the_interval_and_why(monkeypatch, capsys, tmp_path):
    """`symsynth solve --solver compiled --time-limit`: the solver line says
    the layered solve handed over and why, E_p is printed as the proven
    interval, and the interval holds the exact value."""
    from symsynth.scene import load_scene

    path = tmp_path / "pattern.yaml"
    path.write_text(yaml.safe_dump(pattern_data(2, 4, k=1)))
    exact = solve_explicit(load_scene(path)).cost_bound
    _ticked(monkeypatch, 10)
    assert main(["solve", str(path), "--solver", "compiled", "--time-limit", "20"]) == 0
    monkeypatch.undo()
    out = capsys.readouterr().out
    assert "\nsolver     compiled\n           the layered solve was predicted to take about " in out, out
    assert "the AND-OR search answered in the " in out
    lower, upper = map(int, re.search(r"^E_p\s+in \[(\d+), (\d+)\]: not proven within the time limit", out,
                                      re.M).groups())
    assert lower <= exact <= upper and lower < upper, out
    assert f"<= {upper}, the upper end" in out


def test_auto_gives_the_compiled_solver_the_limit(monkeypatch):
    """`auto` with a time limit picks the compiled solver for a game its
    tables hold, and passes the limit on: a prediction past it hands over."""
    from symsynth.solvers.auto import solve_auto

    monkeypatch.setattr(deadline, "predicted_sizes", lambda sizes, k: [1e15] * (k + 1))
    scene = _scene(5)
    got = solve_auto(scene, k=2, time_limit=3600)
    assert got.stats["auto"] == "compiled" and "handed_over" in got.stats, got.stats
    assert got.units == solve_explicit(scene, k=2).units
