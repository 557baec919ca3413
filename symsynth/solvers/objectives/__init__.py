"""Objectives beyond the worst case (semantics §9): the guaranteed expected
cost `EX_μ(B)` (`expected`) and best effort (`best-effort`), on the game
whose worst-case value `E_p` the solvers of `symsynth.solvers` compute.

Both build one `Arena` (the position graph as arrays with V at every
robot turn) with the explicit or the compiled solver's exploration
(`arena.py`), then run `kernels.py` on it:

- best effort: the class of the initial position from V (winning) and
  the cooperative cost C: where the start is winning, a forward search
  from it stopped at the win (the strategy is then the worst-case one);
  else a Dijkstra backwards from the win, robot and human choosing
  together, gives C and a cooperative move at every turn;
- expected: the worst-case values as the safety filter (a move a is
  allowed with budget b when cost(a) + V(after a) <= b), value iteration
  per budget level b = 0..B, from above on the zero-cost moves; the
  budgets a turn can be reached with are bounded below by V and above by
  B minus the least cost of reaching it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from symsynth.errors import InputError
from symsynth.game.human_model import HumanModel
from symsynth.game.solution import OutOfReach, check_parameters, json_number, task_formula
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.objectives.arena import INF, Arena, budget_units, from_compiled, from_explicit
from symsynth.solvers.objectives.play import BestEffortStrategy, ExpectedStrategy, Strategy, still_to_pay
from symsynth.solvers.objectives.walk import Turns

OBJECTIVES = ("worst", "expected", "best-effort")
#: the solvers that compute the objectives of §9 (the others: worst only)
SOLVERS = ("auto", "compiled", "explicit")
#: default precision of the waiting bound n(ε), in costmap units
EPSILON = 1e-6
#: the most (turn, budget) pairs the check for waiting reads (games with zero-cost moves; 5 bytes each)
MAX_ENTRIES = 150_000_000
CLASSES = ("winning", "cooperative", "losing")


@dataclass(frozen=True)
class ObjectiveSolution:
    """What `solve_objective` found; costs in costmap units.

    - `cost_bound`: E_p (None: infinite); `budget`: B (expected only);
    - `expected_cost`: EX_μ(B), None when undefined (B < E_p or E_p infinite);
    - `attained`: whether the expected-cost strategy is B-safe as it is
      (False: EX is an infimum that waiting on zero-cost moves approaches;
      then `waiting` is n(ε) and `waiting_bound` the expected cost that
      stopping after n robot turns guarantees, within `epsilon` of EX);
    - `position_class` and `cooperative_cost` (best effort).
    """

    objective: str
    k: int
    resolution: float
    cost_bound: float | None
    states: int
    seconds: dict[str, float]
    solver: str
    human_model: str | None = None
    budget: float | None = None
    budget_units: int | None = None
    expected_cost: float | None = None
    attained: bool | None = None
    waiting: int | None = None
    waiting_bound: float | None = None
    epsilon: float | None = None
    position_class: str | None = None
    cooperative_cost: float | None = None
    realizable: bool | None = None
    stats: dict[str, Any] = field(default_factory=dict)
    arena: Arena | None = field(default=None, repr=False, compare=False)
    #: expected: the `Steps`; best effort: (rc, hc, cooperative move, vh), or None until `tables` is asked
    #: for (the start winning: its strategy is the worst-case one, and C(p0) was found without them)
    solved: Any = field(default=None, repr=False, compare=False)
    #: expected: the turns its strategy reaches from the start (`reached`), once asked for; not
    #: an argument, so that `dataclasses.replace` (another waiting bound, say) walks again
    walked: Turns | None = field(default=None, init=False, repr=False, compare=False)

    @property
    def tables(self) -> Any:
        """What the strategy is made of: for `expected` the `Steps`; for
        best effort (rc, hc, choice, vh): C at each robot turn and human
        turn, the move of a cheapest cooperative play at each robot turn,
        and V at each human turn (computed now if the solve did not need
        them)."""
        if self.solved is None and self.objective == "best-effort" and self.arena is not None:
            object.__setattr__(self, "solved", _best_effort_tables(self.arena))
        return self.solved

    def strategy(self) -> Strategy:
        """The strategy of the objective (`play.py`), on `arena`."""
        if self.arena is None or self.tables is None:
            raise ValueError("no strategy: the objective is undefined here, or nothing is left to do")
        if self.objective == "best-effort":
            return BestEffortStrategy(self.arena, self.tables[2])
        return ExpectedStrategy(self.arena, self.tables, None if self.attained else self.waiting)

    def reached(self) -> Turns:
        """The turns the expected-cost strategy reaches from the start with
        the budget, its move and the most it may still pay at each
        (`play.still_to_pay`), walked once: the strategy table and the
        world's adversary both read them."""
        if self.walked is None:
            strategy = self.strategy()
            assert isinstance(strategy, ExpectedStrategy), "only the expected-cost strategy keeps a budget"
            object.__setattr__(self, "walked", still_to_pay(strategy, int(self.budget_units or 0)))
        assert self.walked is not None
        return self.walked

    def classes(self) -> np.ndarray:
        """Best effort: the class (0 winning, 1 cooperative, 2 losing) of each
        human turn (node i) and robot turn (node n + i) of `arena`."""
        assert self.arena is not None and self.tables is not None
        rc, hc, _, vh = self.tables
        n = self.arena.size
        out = np.full(2 * n, 2, np.int64)
        out[:n] = np.where(vh < INF, 0, np.where(hc < INF, 1, 2))
        out[n:] = np.where(self.arena.rval < INF, 0, np.where(rc < INF, 1, 2))
        return out

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "objective": self.objective, "cost_bound": self.cost_bound, "k": self.k,
            "states": self.states, "seconds": dict(self.seconds), "resolution": self.resolution,
            "solver": self.solver}
        if self.objective == "expected":
            out |= {"human_model": self.human_model, "budget": json_number(self.budget),
                    "expected_cost": self.expected_cost, "realizable": self.realizable, "attained": self.attained,
                    "waiting": self.waiting, "waiting_bound": self.waiting_bound, "epsilon": self.epsilon}
        else:
            out |= {"class": self.position_class, "cooperative_cost": self.cooperative_cost,
                    "realizable": None, "budget": None}
        return out


def solve_objective(scene: Scene, formula: str | ast.Formula | None = None, *, objective: str,
                    model: HumanModel | None = None, k: int | None = None, budget: float | None = None,
                    resolution: float = 1.0, solver: str = "auto", epsilon: float = EPSILON) -> ObjectiveSolution:
    """EX_μ(B) (`expected`, default B = E_p) or the class and C of the
    initial position (`best-effort`; a `model` there only gives the arena
    its probabilities, for runs), with the explicit or the compiled
    solver's graph (`auto`: the compiled one, the explicit one when the game
    is out of the compiled solver's reach or the model is not uniform)."""
    from symsynth.solvers.objectives import kernels  # numba: loaded when solving, not with the command line

    _check(objective, solver, model, budget)
    k = check_parameters(scene, k, resolution)
    formula = task_formula(scene, formula)
    if solver in ("auto", "compiled"):
        from symsynth.solvers.compiled import compile_kernels

        compile_kernels()  # once per process, before the clock (as `prepare` does for comparison runs)
    clock = time.perf_counter()
    use, arena = _arena(scene, formula, k, resolution, model, solver)
    seconds = {"arena": time.perf_counter() - clock}
    base: dict[str, Any] = dict(objective=objective, k=k, resolution=resolution, solver=use,
                human_model=None if model is None or objective != "expected" else model.name)
    if arena is None:  # ρ(v0) alone is accepted: nothing to pay
        extra: dict[str, Any] = ({"position_class": "winning", "cooperative_cost": 0.0} if objective == "best-effort"
                                 else {"budget": 0.0 if budget is None else budget, "expected_cost": 0.0,
                                       "budget_units": 0, "attained": True})
        return ObjectiveSolution(cost_bound=0.0, states=0, seconds=seconds, **base, **extra)
    if arena.seconds:  # the exploration and V, inside the arena's time
        seconds["arena"] -= sum(arena.seconds.values())
        seconds |= arena.seconds
    vh = kernels.human_values(arena.rval, arena.h_off, arena.h_tgt)
    top = int(vh[0])
    cost_bound = None if top >= INF else top * resolution
    states = arena.size + int(np.count_nonzero(arena.hflag))
    if objective == "best-effort":
        clock = time.perf_counter()
        if top < INF:  # winning: the strategy is the worst-case one, C(p0) a search from the start
            tables = None
            c0 = int(kernels.cooperative_start(arena.hflag, arena.r_off, arena.r_tgt, arena.r_units, arena.h_off,
                                               arena.h_tgt))
        else:  # the strategy needs the cheapest cooperative move at every turn it may reach
            tables = _best_effort_tables(arena, vh)
            c0 = int(tables[1][0])
        seconds["cooperative"] = time.perf_counter() - clock
        cls = "winning" if top < INF else "cooperative" if c0 < INF else "losing"
        return ObjectiveSolution(cost_bound=cost_bound, states=states, seconds=seconds,
                                 position_class=cls, cooperative_cost=None if c0 >= INF else c0 * resolution,
                                 arena=arena, solved=tables, **base)
    return _expected(arena, vh, top, cost_bound, states, seconds, base, budget, resolution, epsilon)


def _check(objective: str, solver: str, model: HumanModel | None, budget: float | None) -> None:
    """`solve_objective`'s arguments, refused with what was expected."""
    if objective not in ("expected", "best-effort"):
        raise InputError(f"objective must be expected or best-effort here, not {objective!r}")
    if solver not in SOLVERS:
        raise InputError(f"--objective {objective} is computed by the solvers {', '.join(SOLVERS)}, "
                         f"not {solver!r}")
    if objective == "expected" and model is None:
        raise InputError("--objective expected needs a human model: give --human-model random:P, or "
                         "human: {k: K, model: random(P)} in the scene")
    if budget is not None and (not budget >= 0 or math.isinf(budget)):
        raise InputError(f"budget must be a number >= 0, found {budget}")


def _arena(scene: Scene, formula: ast.Formula, k: int, resolution: float, model: HumanModel | None,
           solver: str) -> tuple[str, Arena | None]:
    """The solver used and its arena: the compiled solver's graph for
    `auto` and `compiled`, the explicit one's when `auto` finds the game
    out of the compiled solver's reach."""
    if solver in ("auto", "compiled"):
        try:
            return "compiled", from_compiled(scene, formula, k, resolution, model)
        except OutOfReach:
            if solver == "compiled":
                raise
    return "explicit", from_explicit(scene, formula, k, resolution, model)


def _expected(arena: Arena, vh: np.ndarray, top: int, cost_bound: float | None, states: int,
              seconds: dict[str, float], base: dict[str, Any], budget: float | None, resolution: float,
              epsilon: float) -> ObjectiveSolution:
    from symsynth.solvers.objectives import kernels
    from symsynth.solvers.objectives import steps as kernel
    from symsynth.solvers.objectives.steps import Steps, dense_choice, expected_steps

    if top >= INF:  # undefined: no strategy wins against every human
        return ObjectiveSolution(cost_bound=None, states=states, seconds=seconds, budget=budget,
                                 realizable=None if budget is None else False, **base)
    units = top if budget is None else budget_units(budget, resolution)
    shown = top * resolution if budget is None else budget
    if units < top:  # B < E_p: undefined
        return ObjectiveSolution(cost_bound=cost_bound, states=states, seconds=seconds, budget=shown,
                                 budget_units=units, realizable=False, **base)
    clock = time.perf_counter()
    dr, dh = kernels.distances(arena.hflag, arena.r_off, arena.r_tgt, arena.r_units, arena.h_off, arena.h_tgt)
    vh_human = np.where(arena.hflag > 0, vh, INF)
    pairs = _entries(arena.rval, dr, units) + _entries(vh_human, dh, units)
    xorder = np.lexsort((arena.rval, arena.layer)).astype(np.int64)
    yorder = np.lexsort((vh_human, arena.layer)).astype(np.int64)
    yorder = yorder[arena.hflag[yorder] > 0]
    steps = Steps(*expected_steps(np.int64(units), arena.layer, arena.hflag, arena.r_off, arena.r_tgt,
                                  arena.r_units, arena.rval, vh, dr, dh, arena.stay, arena.h_off, arena.h_tgt,
                                  arena.h_prob, xorder, yorder, np.int64(kernel.CHUNK)))
    value = steps.y(0, units)
    seconds["expected"] = time.perf_counter() - clock
    waits = False
    waiting = bound = None
    if len(arena.r_units) and int(arena.r_units.min()) == 0:  # only zero-cost moves let a play go in circles
        clock = time.perf_counter()
        if pairs > MAX_ENTRIES:
            raise OutOfReach(f"checking whether the expected-cost strategy waits reads {pairs} (position, budget) "
                             f"pairs, more than {MAX_ENTRIES}; give a budget closer to E_p or a coarser "
                             "--resolution")
        xlo = arena.rval
        xo = np.zeros(arena.size + 1, np.int64)
        reached = (xlo < INF) & (dr < INF)
        xo[1:] = np.cumsum(np.where(reached, np.maximum(0, units - dr - np.where(reached, xlo, 0) + 1), 0))
        choice = dense_choice(steps.xo, steps.xlev, steps.xch, xo, xlo)
        waits = kernels.has_cycle(np.int64(units), arena.hflag, arena.r_tgt, arena.r_units, arena.h_off,
                                  arena.h_tgt, choice, xo, xlo)
        if waits:
            n, reach = kernels.truncated(np.int64(units), 1_000_000, arena.hflag, arena.r_tgt, arena.r_units,
                                         arena.rval, arena.stay, arena.h_off, arena.h_tgt, arena.h_prob, choice,
                                         xo, xlo, value + epsilon / resolution)
            waiting, bound = (None if n < 0 else int(n)), float(reach) * resolution
        seconds["waiting"] = time.perf_counter() - clock
    stats = {"pairs": int(pairs), "breakpoints": steps.breakpoints}
    return ObjectiveSolution(cost_bound=cost_bound, states=states, seconds=seconds, budget=shown,
                             budget_units=units, realizable=True, expected_cost=value * resolution, attained=not waits,
                             waiting=waiting, waiting_bound=bound, epsilon=epsilon if waits else None,
                             stats=stats, arena=arena, **base, solved=steps)


def _best_effort_tables(arena: Arena, vh: np.ndarray | None = None) -> tuple:
    """(rc, hc, choice, vh) of `ObjectiveSolution.tables`, by the backward
    Dijkstra of `kernels.cooperative`."""
    from symsynth.solvers.objectives import kernels

    rc, hc, coop = kernels.cooperative(arena.hflag, arena.r_off, arena.r_tgt, arena.r_units, arena.h_off,
                                       arena.h_tgt)
    return rc, hc, coop, arena.human_value() if vh is None else vh


def _entries(low: np.ndarray, dist: np.ndarray, units: int) -> int:
    """How many budgets low..units - dist there are, summed over the turns."""
    ok = (low < INF) & (dist < INF)
    return int(np.maximum(0, units - dist[ok] - low[ok] + 1).sum())


def prepare() -> None:
    """Compile (or load from numba's cache) the kernels of both objectives by
    solving a two-location game once: comparison runs call it before their
    clock starts, as `symsynth.solvers.prepare` does for the solvers."""
    from fractions import Fraction

    from symsynth.game.human_model import RandomModel
    from symsynth.scene.load import scene_from_data

    anchors = ["home", "l1/top", "l2/top", "e1/top"]
    for wait in (0, 1):  # a zero-cost move or none: both ways of computing the expectation
        motions: list[dict[str, Any]] = [
            {"mode": mode, "from": a, "to": b, "rules": [{"free": [], "cost": wait if a == "e1/top" else 2}]}
            for mode in ("empty", "b/top") for a in anchors for b in anchors[1:] if a != b]
        scene = scene_from_data({"name": "prepare-objectives", "objects": {"b": {"at": "l1"}},
                                 "locations": ["l1", "l2"], "else_samples": ["e1"], "grasps": ["top"],
                                 "human": {"k": 1}, "task": "F(at(b, l2))",
                                 "costmap": {"format": "symsynth.costmap/1", "motions": motions}})
        for solver in ("explicit", "compiled"):
            solve_objective(scene, objective="expected", model=RandomModel(Fraction(1, 2)), solver=solver)
            solve_objective(scene, objective="best-effort", solver=solver)
