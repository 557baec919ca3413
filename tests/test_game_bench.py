"""The game benchmark's command line refuses what it would silently ignore."""

from __future__ import annotations


import pytest


import argparse

from bench.game_bench import Cell, _target_speedup, main, parse_sizes, report


def test_sizes_parse():
    assert parse_sizes("4x6, 5X7,") == [(4, 6), (5, 7)]
    with pytest.raises(ValueError, match="'4-6' is not NxM"):
        parse_sizes("4x6,4-6")


@pytest.mark.parametrize("argv, message", [
    # a limit at a size that is not run would never stop the solver
    (["--sizes", "3x5,4x6", "--limit", "explicit=5x7"], "5x7 is not among the sizes (3x5, 4x6)"),
    (["--sizes", "3x5", "--limit", "explicit=big"], "--limit explicit=big: 'big' is not NxM"),
    (["--sizes", "3x5,four"], "--sizes: 'four' is not NxM"),
    (["--sizes", "3x5", "--limit", "nosuch=3x5"], "SOLVER among --solvers"),
    (["--sizes", "3x5,4x6", "--limit", "explicit=3x5,4x6"], "--limit explicit=3x5,4x6: expected one size"),
    (["--sizes", "3x5", "--limit", "explicit=,"], "--limit explicit=,: expected one size"),
    (["--sizes", "3x5,4x6", "--limit", "explicit=3x5", "--limit", "explicit=4x6"],
     "explicit is already limited to 3x5"),
    (["--sizes", ","], "--sizes and --solvers must each name at least one"),
    (["--sizes", "3x5", "--k", "-1"], "--k -1: expected a number of human moves >= 0"),
    (["--sizes", "3x5", "--timeout", "0"], "--timeout 0: expected a positive number"),
    (["--sizes", "3x5", "--mem-limit", "-2"], "--mem-limit -2: expected GB >= 0"),
    (["--sizes", "3x5", "--solvers", ","], "--sizes and --solvers must each name at least one"),
    (["--sizes", "3x5", "--time-limit", "-1"], "--time-limit -1: expected seconds >= 0"),
])
def test_bad_arguments_are_usage_errors(argv, message, capsys, tmp_path):
    # --out: should the check ever go, the run it lets through must not
    # overwrite bench/results/game.md
    with pytest.raises(SystemExit) as exit_:
        main(["--out", str(tmp_path / "game.md"), "--timeout", "5"] + argv)  # argv has the last word
    assert exit_.value.code == 2
    assert message in capsys.readouterr().err


def test_a_solver_limited_below_the_largest_size_is_no_failure():
    """--limit forward=1x2: the speed-up target has no forward cell at 2x3,
    where explicit finished last; it is skipped, as the size target is."""
    sizes = [(1, 2), (2, 3)]
    cells = {("explicit", 1, 2): Cell("explicit", 1, 2, 3, solve_s=1.0),
             ("explicit", 2, 3): Cell("explicit", 2, 3, 3, solve_s=2.0),
             ("forward", 1, 2): Cell("forward", 1, 2, 3, solve_s=0.05),
             ("forward", 2, 3): Cell("forward", 2, 3, 3, status="n/a")}
    status, message = _target_speedup(sizes, cells, ["explicit", "forward"], "forward")
    assert status == "SKIP" and "forward not run at 2x3" in message
    cells["forward", 2, 3] = Cell("forward", 2, 3, 3, solve_s=0.1)
    assert _target_speedup(sizes, cells, ["explicit", "forward"], "forward")[0] == "PASS"  # 20x
    cells["forward", 2, 3] = Cell("forward", 2, 3, 3, status="TO")
    assert _target_speedup(sizes, cells, ["explicit", "forward"], "forward")[0] == "FAIL"


def test_an_interval_that_misses_the_exact_value_is_a_mismatch():
    """With --time-limit, an anytime answer [lower, upper] is checked against
    an exact solver's value in the same row: holding it passes, missing it
    is a MISMATCH (as two different exact values are)."""
    args = argparse.Namespace(k=3, time_limit=1.0)
    cells = {("compiled", 2, 3): Cell("compiled", 2, 3, 3, solve_s=1.0, cost_bound=520),
             ("andor", 2, 3): Cell("andor", 2, 3, 3, solve_s=1.0, cost_bound=530, lower=510)}
    text, verdicts = report([(2, 3)], ["compiled", "andor"], cells, {}, args)
    assert "andor [510, 530] 1.039" in text and not any(v == "MISMATCH" for v, _ in verdicts)
    for lower, upper in ((521, 530), (500, 519), (500, None)):
        cells["andor", 2, 3] = Cell("andor", 2, 3, 3, solve_s=1.0, cost_bound=upper, lower=lower)
        text, verdicts = report([(2, 3)], ["compiled", "andor"], cells, {}, args)
        assert ("MISMATCH" in [v for v, _ in verdicts]) == (upper is not None), (lower, upper)
