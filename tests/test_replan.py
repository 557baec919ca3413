"""The replanning strategy and its bound (symsynth/solvers/replan.py): on
generated scenes the bound is exactly what the strategy pays against the worst
human (followed through every human behaviour), so never below E_p; and an
anytime answer whose upper end it supplies holds the exact value."""

from __future__ import annotations

import dataclasses
import itertools
import math

from symsynth.cli.solve import _report_value
from symsynth.logic import parse_ltlf
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.replan import replanning_bound
from support.games import cut_answer, enumerated_bounds, planning_scene, worst_case_of


def _scene(seed):
    return planning_scene(seed, 8000)


def test_the_bound_is_what_the_strategy_pays_and_never_below_e_p():
    finite = 0
    for seed, scene, k, formula, bound in enumerated_bounds(range(72), 8000):
        exact = solve_explicit(scene, k=k)
        assert bound.certified and bound.complete
        if exact.units is None or bound.upper == math.inf:
            assert bound.upper == math.inf or exact.units is not None, seed  # σ never wins a lost game
            continue
        finite += 1
        assert exact.units <= bound.upper, seed
        followed = dataclasses.replace(exact, strategy=bound.strategy)
        assert worst_case_of(scene, followed, formula) == bound.upper, seed
        assert sum(s.cost for s in bound.principal) == bound.upper, seed
    assert finite >= 15, finite


def test_a_tail_below_the_enumerated_levels_is_conditional():
    scene = _scene(1)
    bound = replanning_bound(scene, parse_ltlf(scene.task), 2, levels=1, tail=50)
    assert not bound.certified and bound.tail == 50
    assert replanning_bound(scene, parse_ltlf(scene.task), 2, levels=1, tail=50, tail_proven=True).certified


def test_the_replanning_upper_end_holds_the_exact_value(monkeypatch, capsys):
    """The search cut by a ticking clock, the replanning bound given a share of
    1e12 of the limit (so it always finishes): the answer is exact, or an
    interval that holds E_p, and where σ gives the upper end it pays at most that
    and `solve` names it as the strategy behind the upper end."""
    replanned = 0
    for (chunk, limit), seed in itertools.product([(10, 3), (40, 9)], (s for s in range(40) if s % 4)):
        scene = _scene(seed)
        k = 1 + seed % 3
        exact = solve_explicit(scene, k=k).units
        found = cut_answer(monkeypatch, scene, k, chunk, limit, REPLAN_SHARE=1e12)
        if found.exact:
            assert found.units == exact, seed
            continue
        assert exact is None or found.lower_units <= exact, seed
        if found.stats.get("upper_by") == "replanning":
            replanned += 1
            assert exact is not None and exact <= found.units, seed
            assert worst_case_of(scene, found, parse_ltlf(scene.task)) <= found.units, seed
            _report_value(scene, found)
            assert "upper end guaranteed by the replanning strategy" in capsys.readouterr().out, seed
    assert replanned >= 3, replanned


def test_the_no_human_value_keeps_the_deadline(monkeypatch):
    """Under a deadline, V_0's own searches stop at it too (they had none: one
    V_0 at sorting 8 x 12 took 111 s of a 15 s share): with the clock past the
    deadline and the search's questions cut every 16 steps (64 / 4 under a
    deadline), the bound gives up before V_0 at the start is proven (52 steps
    there), which it then reports unknown."""
    import sys
    from pathlib import Path

    from symsynth.solvers import andor, replan
    from support.games import TickClock

    sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench"))
    from gamefamily import pattern_scene

    scene = pattern_scene(4, 6, k=2)
    formula = parse_ltlf(scene.task)
    andor.prepare()
    monkeypatch.setattr(replan, "ORACLE_CHUNK", 64)
    monkeypatch.setattr(andor.time, "perf_counter", TickClock())
    bound = replanning_bound(scene, formula, 2, deadline=0.0)
    assert not bound.complete and bound.upper is None and math.isnan(bound.v0)


def test_the_no_human_value_is_exact_where_the_rounds_give_up(monkeypatch):
    """V_0 at the start equals the explicit solver's k = 0 value with the
    search's rounds cut to one (`MAX_ROUNDS`): where they give up, the value is
    found by doubling the budget (it raised `_TooManyRounds` to the caller
    before).  Scenes with contacts have no lower bound (lo starts at 0), so the
    first budget tried, 2 lo + 64, is short and the doubling is reached; where
    V_0 is infinite there, the trap check after the first no ends it (held back
    to the 8th question, the budget, and the search's depth, grew 2^8-fold)."""
    from symsynth.game.abstraction import initial_state
    from symsynth.game.solution import OutOfReach
    from symsynth.solvers import andor, replan

    andor.prepare()
    monkeypatch.setattr(andor, "MAX_ROUNDS", 1)
    asked: list[int] = []  # the questions each doubling asked
    doubling = [False]
    real_doubled, real_ask = replan.NoHumanValue._doubled, replan.NoHumanValue.ask

    def counted_doubled(self, i):
        asked.append(0)
        doubling[0] = True
        try:
            return real_doubled(self, i)
        finally:
            doubling[0] = False

    def counted_ask(self, i, b):
        if doubling[0]:
            asked[-1] += 1
        return real_ask(self, i, b)

    monkeypatch.setattr(replan.NoHumanValue, "_doubled", counted_doubled)
    monkeypatch.setattr(replan.NoHumanValue, "ask", counted_ask)
    compared = 0
    for seed in range(60):
        scene = _scene(seed)
        try:
            oracle = replan.NoHumanValue(scene, parse_ltlf(scene.task))
            v = initial_state(scene)
            value = oracle.value(v, oracle.start(v))
        except OutOfReach:  # a zero-cost move
            continue
        exact = solve_explicit(scene, k=0).units
        assert value == (math.inf if exact is None else exact), seed
        compared += 1
    assert compared >= 40 and len(asked) >= 5, (compared, asked)
    assert max(asked) <= 2, asked
