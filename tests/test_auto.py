"""`--solver auto` does not pay the compiled solver's cold compile (about
20 s) for a game the explicit solver finishes sooner, and says why."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

from symsynth.game.solution import task_formula
from symsynth.scene import load_scene
from symsynth.solvers.auto import choose, position_bound
from symsynth.solvers.compiled import compile_kernels
from symsynth.testing.gamegen import random_scene

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
from gamefamily import pattern_scene  # noqa: E402


def test_a_small_game_with_cold_kernels_goes_to_the_explicit_solver():
    scene = load_scene(ROOT / "scenes" / "arch-abstract.yaml")
    formula = task_formula(scene, None)
    name, reason = choose(scene, formula, compiled_ready=False)
    assert name == "explicit"
    assert "not compiled yet" in reason and f"at most {position_bound(scene, formula, scene.k):,} positions" in reason
    assert choose(scene, formula, compiled_ready=True)[0] == "compiled"
    assert choose(scene, formula, compiled_ready=False, refused={"explicit"})[0] == "compiled"


def test_a_large_game_pays_the_compile():
    """Pattern family 6 x 8 x k = 3: 7.4 million positions (docs/benchmarks.md),
    minutes for the explicit solver, seconds for the compiled one."""
    scene = pattern_scene(6, 8)
    name, reason = choose(scene, task_formula(scene, None), compiled_ready=False)
    assert name == "compiled" and "compiled first" in reason


def test_the_position_bound_holds():
    """The bound is never below the positions the explicit solver meets
    (counted by it, without the reduction by interchangeable objects)."""
    from symsynth.solvers.explicit import solve_explicit

    for seed in range(40):
        scene = random_scene(4000 + seed, contacts=seed % 3 == 0)
        k = seed % 4
        states = solve_explicit(scene, k=k, symmetric=False).states
        assert states <= position_bound(scene, task_formula(scene, None), k), seed


def test_the_cache_state_is_read_from_numba_cache():
    """With an empty cache folder the kernels are cold, and `auto` solves the
    toy with the explicit solver, saying why, without compiling; with the
    project's cache (the test session compiled it) they are warm."""
    script = ("from symsynth.solvers.compiled import kernels_cached\n"
              "from symsynth.scene import load_scene\n"
              "from symsynth.solvers.auto import solve_auto\n"
              "import symsynth.solvers.compiled as c\n"
              "ready = kernels_cached()\n"
              "s = solve_auto(load_scene('scenes/toy.yaml'))\n"
              "print(ready, s.stats['auto'], s.units, c._compiled)\n")
    with tempfile.TemporaryDirectory() as empty:
        cold = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=ROOT,
                              env=os.environ | {"NUMBA_CACHE_DIR": empty}, timeout=300)
    assert cold.returncode == 0, cold.stderr
    assert cold.stdout.split() == ["False", "explicit", "50", "False"]  # the toy's hand-solved value
    compile_kernels()  # (written to the cache by now when the suite runs whole, not when this file runs alone)
    warm = subprocess.run([sys.executable, "-c", "from symsynth.solvers.compiled import kernels_cached; "
                           "print(kernels_cached())"], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert warm.stdout.strip() == "True", warm.stderr


def test_a_time_limit_goes_to_an_exact_solver_when_the_game_fits_it():
    """With a time limit, the exact solver when it is expected to take at
    most half of it (the compile included when the kernels are cold), else
    the compiled solver with the limit (its layered solve, or the AND-OR
    search it hands over to) where the compiled tables hold the game and the
    kernels are ready (or compile in half the limit), the forward search
    otherwise."""
    small = load_scene(ROOT / "scenes" / "arch-abstract.yaml")
    formula = task_formula(small, None)
    assert choose(small, formula, time_limit=10, compiled_ready=True)[0] == "compiled"
    assert choose(small, formula, time_limit=30, compiled_ready=False)[0] == "explicit"
    assert choose(small, formula, time_limit=0.5, compiled_ready=False)[0] == "forward"
    large = pattern_scene(6, 8)
    name, reason = choose(large, task_formula(large, None), time_limit=10, compiled_ready=True)
    assert name == "compiled" and "anytime" in reason and "AND-OR search on the same tables" in reason
    name, reason = choose(large, task_formula(large, None), time_limit=60, compiled_ready=False)
    assert name == "compiled" and "compiled first" in reason
    name, reason = choose(large, task_formula(large, None), time_limit=10, compiled_ready=False)
    assert name == "forward" and "anytime" in reason  # no time to compile the kernels first
    assert choose(large, task_formula(large, None), time_limit=10, compiled_ready=True,
                  refused={"compiled"})[0] == "forward"
    name, reason = choose(large, task_formula(large, None), time_limit=3600, compiled_ready=True)
    assert name == "compiled" and "well above" in reason


def test_the_search_kernels_counted_ready_include_the_replanning_replies(monkeypatch):
    """`kernels_cached(andor=True)` asks numba's cache for every kernel a
    limit may run: the AND-OR search's and the replanning bound's replies
    (`packed.replies`); one of the latter missing is a compile to come."""
    from symsynth.solvers import andor, compiled
    from symsynth.solvers.packed import replies

    missing = replies._settle
    monkeypatch.setattr(compiled, "_compiled", False)
    monkeypatch.setattr(andor, "_prepared", False)
    monkeypatch.setattr(compiled, "_cached", lambda kernel: kernel is not missing)
    assert compiled.kernels_cached() and not compiled.kernels_cached(andor=True)


def test_the_search_kernels_are_ready_once_the_search_has_warmed_up():
    """After `andor.prepare` (the search's and the replies' kernels compiled
    and cached), a new process finds every one of them in numba's cache, the
    kernels inlined into their callers too, which have no entry of their own
    (counting them made `auto` expect a compile on every run)."""
    from symsynth.solvers import andor

    andor.prepare()
    ready = subprocess.run([sys.executable, "-c", "from symsynth.solvers.compiled import kernels_cached; "
                            "print(kernels_cached(andor=True))"], capture_output=True, text=True, cwd=ROOT,
                           timeout=300)
    assert ready.stdout.strip() == "True", ready.stderr
