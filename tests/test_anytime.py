"""`solve --time-limit`: when the forward search is stopped before E_p is
proven, the answer is an interval [lower, upper] and a strategy that
guarantees upper.  Checked against the exact value (the explicit solver)
on generated scenes small enough to solve, with the deadline counted in
questions instead of seconds, so each limit stops the search at the same
place on every machine."""

from __future__ import annotations

import itertools

import pytest

from symsynth.logic import parse_ltlf
from symsynth.solvers import forward, forward_search
from symsynth.solvers.auto import choose
from symsynth.solvers.explicit import solve_explicit
from symsynth.testing.gamegen import alike_scene, random_scene
from support.games import worst_case_of


@pytest.fixture
def counted(monkeypatch):
    """The deadline clock advances one "second" per question asked."""
    ticks = itertools.count()
    monkeypatch.setattr(forward_search, "deadline_clock", lambda: next(ticks))
    monkeypatch.setattr(forward.Search, "check_mask", 0)


def test_intervals_contain_the_value(counted):
    kinds = {"exact": 0, "interval": 0, "lower only": 0}
    for seed in range(40):
        scene = random_scene(seed + 500) if seed % 2 else alike_scene(seed)
        formula = parse_ltlf(scene.task)
        exact = solve_explicit(scene, symmetric=False).units
        for limit in sorted({int(1.25 ** e) for e in range(3, 40)}):
            got = forward.solve_forward(scene, time_limit=limit)
            if got.exact:
                kinds["exact"] += 1
                assert got.units == exact, (seed, limit)
                continue
            assert exact is None or got.lower_units <= exact, (seed, limit)
            if got.units is None:
                kinds["lower only"] += 1
                continue
            kinds["interval"] += 1
            assert exact is not None and exact <= got.units, (seed, limit)
            assert got.lower_units < got.units
            assert worst_case_of(scene, got, formula) <= got.units
            assert sum(s.cost for s in got.principal_play) <= got.cost_bound
    # every kind of answer was exercised
    assert min(kinds.values()) >= 3, kinds


def test_verdicts_within_a_time_limit(counted):
    """A budget at or above the upper end is realizable, one below the lower
    end is not, one between is undecided (None), never a guess."""
    checked = 0
    for seed in range(40):
        scene = random_scene(seed + 500) if seed % 2 else alike_scene(seed)
        exact = solve_explicit(scene, symmetric=False).units
        for limit in sorted({int(1.25 ** e) for e in range(3, 40)}):
            got = forward.solve_forward(scene, time_limit=limit)
            if not got.exact and got.units is not None:
                break
        else:
            continue
        checked += 1
        for budget in range(0, got.units + 3):
            verdict = forward.solve_forward(scene, time_limit=limit, budget=budget).realizable
            if verdict is not None:
                assert verdict == (exact is not None and exact <= budget)
            else:
                assert got.lower_units <= budget < got.units
    assert checked >= 3


def test_auto_picks_by_time_limit_size_and_task():
    from symsynth.solvers import andor

    andor.prepare()  # (the choice with the kernels ready; run alone on a cold numba cache they are not)
    scene = random_scene(3)
    assert choose(scene, parse_ltlf("F(at(block, l1))"), time_limit=1.0)[0] == "compiled"  # a small game
    name, reason = choose(scene, parse_ltlf("F(at(block, l1))"), time_limit=1e-9, compiled_ready=True)
    assert name == "compiled" and "anytime" in reason  # with the limit: the AND-OR search when it must
    assert choose(scene, parse_ltlf("F(at(block, l1))"), time_limit=1e-9, refused={"compiled"})[0] == "forward"
    assert choose(scene, parse_ltlf("F(at(block, l1))"))[0] == "compiled"
    assert choose(scene, parse_ltlf("F(at(block, l1))"), refused={"compiled"})[0] == "forward"
    assert choose(scene, parse_ltlf("F(at(block, l1) & F(at(block, l2)))"), refused={"compiled"})[0] == "symbolic"


def test_auto_falls_back_when_the_compiled_solver_cannot_hold_the_game():
    """17 atoms: more than the compiled solver's table takes; auto says so
    and solves with the next rule (forward: the task is a conjunction)."""
    from symsynth.solvers import andor
    from symsynth.solvers.auto import solve_auto

    andor.prepare()  # (with the kernels cold, auto never considers the compiled solver)
    from support.games import make_scene

    names = [f"o{i}" for i in range(17)]
    motions = {("empty", "home", "l1/top"): 1}
    scene = make_scene({o: "Else" for o in names}, ["l1", "l2"], motions,
                       task="F(" + " & ".join(f"!at({o}, l2)" for o in names) + " & occupied(l1))")
    solution = solve_auto(scene)
    assert solution.stats["auto"] in ("forward", "symbolic")
    assert "at most 16 atoms" in solution.stats["auto_reason"]
    assert solution.units == solve_explicit(scene, symmetric=False).units


@pytest.mark.parametrize(("lower", "upper", "budget", "expected"), [
    (None, 10, 10.0, True), (None, 11, 10.0, False), (None, None, 10.0, False),  # exact E_p
    (8, 10, None, None),                                                       # no budget: no verdict
    (8, 10, 10.0, True), (8, 10, 9.0, None), (8, 10, 7.0, False),              # the budget above, in, below
    (8, None, 9.0, None), (8, None, 7.0, False),                               # no upper end proven
])
def test_the_verdict_of_an_anytime_answer_by_hand(lower, upper, budget, expected):
    """`bracket_verdict`, shared by the forward and AND-OR solvers' anytime
    answers and the replanning upper end: the budget against [lower, upper]."""
    from symsynth.game.solution import bracket_verdict

    assert bracket_verdict(lower, upper, 1.0, budget) is expected
