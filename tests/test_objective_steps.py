"""The step-function sweep of `--objective expected` (solvers/objectives/steps.py)
on a game of the game family large enough that many events meet on one level
(the test games of test_objectives.py are not): EX and the strategy's value at
every (turn, budget) against a dense level-by-level iteration written here,
with the events' chunks of 32 and of 1 (a chain of chunks per list)."""

from __future__ import annotations

import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from symsynth.game.human_model import RandomModel
from symsynth.solvers.objectives import solve_objective, steps

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from bench.gamefamily import pattern_scene  # noqa: E402


def dense(arena, B):
    """X[b, i] and Y[b, t] for b = 0..B by levels, each level by layers
    (a human move leads one layer down; every move costs >= 1 here, so
    level b reads only levels below it and its own lower layers)."""
    n = arena.size
    src = np.repeat(np.arange(n), np.diff(arena.r_off))
    hsrc = np.repeat(np.arange(n), np.diff(arena.h_off))
    vh = arena.human_value()
    big = np.iinfo(np.int64).max // 4
    vt = np.where(arena.r_tgt >= 0, vh[np.maximum(arena.r_tgt, 0)], 0)
    X = np.full((B + 1, n), np.inf)
    Y = np.full((B + 1, n), np.inf)
    for b in range(B + 1):
        for h in range(int(arena.layer.max()) + 1):
            moves = arena.layer[src] == h
            c = arena.r_units
            ok = moves & (c + np.minimum(vt, big) <= b)
            val = np.full(len(c), np.inf)
            win = ok & (arena.r_tgt < 0)
            val[win] = c[win]
            go = ok & (arena.r_tgt >= 0)
            val[go] = c[go] + Y[b - c[go], arena.r_tgt[go]]
            np.minimum.at(X[b], src[go | win], val[go | win])
            human = (arena.layer == h) & (arena.hflag > 0) & (vh <= b)
            y = np.where(arena.stay > 0, arena.stay * X[b], 0.0)
            hm = human[hsrc] & (arena.h_tgt >= 0) & (arena.h_prob > 0)
            np.add.at(y, hsrc[hm], arena.h_prob[hm] * X[b, arena.h_tgt[hm]])
            Y[b, human] = y[human]
    return X, Y


@pytest.mark.parametrize("chunk", [32, 1])
def test_sweep_matches_a_dense_iteration(chunk, monkeypatch):
    monkeypatch.setattr(steps, "CHUNK", chunk)
    scene = pattern_scene(3, 4, k=2)
    got = solve_objective(scene, objective="expected", model=RandomModel(Fraction(3, 10)), solver="compiled")
    arena, B = got.arena, got.budget_units
    assert arena is not None and B is not None and got.attained
    X, Y = dense(arena, B)
    assert got.expected_cost == pytest.approx(Y[B, 0], abs=1e-9)
    table = got.tables  # the strategy's move at every (turn, budget) the sweep covers is worth X there
    checked = 0
    for i in range(arena.size):
        for k in range(int(table.xo[i]), int(table.xo[i + 1])):
            b = int(table.xlev[k])
            assert table.xval[k] == pytest.approx(X[b, i], abs=1e-9), (i, b)
            checked += 1
    assert checked > 1000
