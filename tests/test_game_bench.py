"""The game benchmark's command line refuses what it would silently ignore."""

from __future__ import annotations


import pytest


from bench.game_bench import Cell, _target_speedup, main, parse_sizes


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
