"""The replanning bound asked as a question (symsynth/solvers/replan_budget.py):
on generated scenes, "does σ pay at most T?" says yes exactly from the bound
the enumeration finds for the same σ (solvers/replan.py, sharing its oracle),
which is what σ pays against the worst human (followed through every human
behaviour) and never below E_p."""

from __future__ import annotations

import math

import numpy as np
import pytest

from symsynth.game.solution import OutOfReach
from symsynth.logic import parse_ltlf
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.packed import replies
from symsynth.solvers.replan import replanning_bound
from symsynth.solvers.replan_budget import BudgetedBound
from support.games import asked_least, enumerated_bounds, explicit_and_paid, planning_scene


def _scene(seed):
    return planning_scene(seed, 9100)


def test_the_question_says_yes_exactly_from_what_the_strategy_pays():
    finite = 0
    for seed, scene, k, formula, enumerated in enumerated_bounds(range(60), 9100):
        asked = BudgetedBound(scene, formula, k, oracle=enumerated.oracle)
        if enumerated.upper == math.inf:
            assert not asked.within(10 ** 6), seed
            continue
        finite += 1
        upper = int(enumerated.upper)
        assert asked.within(upper) and not asked.within(upper - 1), seed
        assert asked.least(0, upper + 50) == upper, seed
        e_p, paid = explicit_and_paid(scene, formula, k, enumerated.strategy)
        assert e_p <= upper and paid == upper, seed
    assert finite >= 15, finite


def test_the_question_alone_finds_what_its_strategy_pays():
    """Without the enumeration first (its own memo, so its own plans): bisection
    over the question gives what σ pays, checked against every human behaviour."""
    checked = 0
    for seed in range(1, 40, 3):
        scene = _scene(seed)
        k = 1 + seed % 3
        formula = parse_ltlf(scene.task)
        found = asked_least(scene, formula, k)
        if found is None:
            continue
        asked, upper = found
        checked += 1
        e_p, paid = explicit_and_paid(scene, formula, k, asked.strategy)
        assert paid == upper and e_p <= upper, seed
        play = asked.worst_play(int(upper))
        assert sum(step.cost for step in play) == upper and sum(step.who == "human" for step in play) <= k, seed
    assert checked >= 5, checked


def _replies_on_the_plan(seed):
    """(bound, the start's plan, [(turn, state after, DFA state after)]) for one
    generated scene at k = 1, None when it has no plan to look at."""
    scene = _scene(seed)
    formula = parse_ltlf(scene.task)
    try:
        asked = BudgetedBound(scene, formula, 1)
        if asked.v0 == math.inf or asked.t.accepting[asked.start[1]]:
            return None
    except OutOfReach:
        return None
    plan = asked._turns(*asked.start, True)
    count = asked._replies(*plan[:2])
    hb, qbits = asked.memo.hb, asked.t.qbits
    moves = [(j, key >> (hb + qbits), (key >> hb) & ((1 << qbits) - 1))
             for key, j in zip(asked._keys[:count].tolist(), asked._turn[:count].tolist()) if key >= 0]
    return asked, plan, moves


def test_a_repair_is_a_plan_back_so_it_bounds_the_rise():
    """packed.replies._repair's cost, wherever it finds one, is at least the rise
    of V_0 over the human move it undoes (V_0 from the k = 0 search, exact), and
    equal to it on some moves (so a repair that claimed less would be caught)."""
    found = tight = 0
    for seed in range(40):
        case = _replies_on_the_plan(seed)
        if case is None:
            continue
        asked, (xs, qs, _, _), moves = case
        memo = asked.memo
        for j, w, q2 in moves:
            x, q = int(xs[j]), int(qs[j])
            fix = int(replies._repair(np.int64(x), np.int64(q), np.int64(w), np.int64(q2), memo.P, memo.G, memo.S()))
            if fix < 0:
                continue
            found += 1
            rise = asked.value(w, q2) - asked.value(x, q)
            assert rise <= fix, (seed, x, w)
            tight += rise == fix
    assert found >= 50 and tight >= 5, (found, tight)


def test_the_plan_followed_after_a_move_bounds_its_value():
    """packed.replies._follow's bound, wherever it finds one, is at least V_0
    after the move, and equal to it on some moves."""
    found = tight = 0
    for seed in range(40):
        case = _replies_on_the_plan(seed)
        if case is None:
            continue
        asked, (xs, qs, left, codes), moves = case
        memo = asked.memo
        bases = left.astype(np.int64)
        for j, w, q2 in moves:
            bound = int(replies._follow(np.int64(j), np.int64(w), np.int64(q2), xs, qs, bases, codes,
                                        np.int64(1 << 40), memo.P, memo.G, memo.S()))
            if bound < 0:
                continue
            try:
                value = asked.value(w, q2)
            except OutOfReach:  # a zero-cost move after it: the k = 0 search does not answer
                break
            found += 1
            assert value <= bound, (seed, w)
            tight += value == bound
    assert found >= 50 and tight >= 20, (found, tight)


def test_the_question_and_its_no_human_searches_keep_the_deadline(monkeypatch):
    """Under a deadline, the question's own V_0 searches stop at it too (one V_0
    at sorting 8 x 12 took 111 s of a 15 s share): with the clock past the
    deadline and the searches' questions cut every 16 steps (64 / 4 under a
    deadline), `certified_upper` gives up before V_0 at the start is proven
    (52 steps there) and answers nothing; after it, the memo keeps no cutoff.
    Given time, the same question is answered."""
    import sys
    from pathlib import Path

    from symsynth.solvers import andor, replan, replan_budget
    from support.games import TickClock

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
    from gamefamily import pattern_scene

    scene = pattern_scene(4, 6, k=2)
    formula = parse_ltlf(scene.task)
    andor.prepare()
    assert replan_budget.certified_upper(scene, formula, 2, 1, None) is not None
    monkeypatch.setattr(replan, "ORACLE_CHUNK", 64)
    monkeypatch.setattr(andor.time, "perf_counter", TickClock())
    bound = BudgetedBound(scene, formula, 2)
    with pytest.raises(replan_budget.Deadline):
        with bound.limited(0.0):
            bound.v0
    assert bound.memo.cutoff is None and bound.deadline is None
    assert replan_budget.certified_upper(scene, formula, 2, 1, None, deadline=0.0) is None


def test_a_worst_play_past_the_deadline_falls_back_to_the_plan(monkeypatch):
    """The replanning upper end's principal play is σ against the worst human
    when that is found in time; past its grace, σ's plan with the human
    passing (robot steps only), and the answer keeps its upper end."""
    from symsynth.solvers import replan_budget
    from support.games import cut_answer

    def late(self, upper):
        raise replan_budget.Deadline

    monkeypatch.setattr(BudgetedBound, "worst_play", late)
    fell_back = 0
    for seed in (s for s in range(40) if s % 4):
        scene = _scene(seed)
        k = 1 + seed % 3
        found = cut_answer(monkeypatch, scene, k, 10, 3, REPLAN_SHARE=1e12)
        monkeypatch.setattr(BudgetedBound, "worst_play", late)  # (cut_answer undoes every patch)
        if found.stats.get("upper_by") != "replanning":
            continue
        fell_back += 1
        assert found.principal_play and all(step.who == "robot" for step in found.principal_play), seed
        assert found.units is not None and found.units >= solve_explicit(scene, k=k).units, seed
    assert fell_back >= 3, fell_back


def test_a_yes_at_one_move_left_holds_for_the_rise_its_certificates_showed():
    """At h = 1 a yes is kept for the largest rise of V_0 its certificates
    showed (`kept_within`), not only for the budget asked: asked once far above,
    that is never below B_1 (the enumeration's, what σ pays), and it is B_1
    itself on some games, so the question's later answers below the budget
    asked come for nothing (the hybrid's leaves read it)."""
    checked = tight = 0
    for seed in range(100):
        scene = _scene(seed)
        formula = parse_ltlf(scene.task)
        try:
            enumerated = replanning_bound(scene, formula, 1)
        except OutOfReach:
            continue
        if enumerated.upper == math.inf or enumerated.v0 == 0:
            continue
        asked = BudgetedBound(scene, formula, 1, oracle=enumerated.oracle)
        exact = enumerated.upper
        far = int(exact) + 200
        assert asked.within(far), seed
        kept = asked.kept_within(*asked.start, 1, human_first=True)
        checked += 1
        assert exact <= kept <= far, (seed, exact, kept)
        tight += kept == exact
    assert checked >= 12 and tight >= checked // 2, (checked, tight)
