"""What a solver returns (semantics §6, §8): the value, the verdict, a strategy and plays.

Shared by every solver (`symsynth.solvers`), so their answers compare
field by field.  Plays list robot actions and human moves; a human pass is
not a step (between two robot steps the human passed).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from decimal import Decimal
from dataclasses import dataclass, field
from typing import Any

from symsynth.automata.symbolic import State as DFAState
from symsynth.errors import InputError
from symsynth.game.abstraction import State, in_costmap_units, state_json, within
from symsynth.logic import ast, parse_ltlf
from symsynth.scene.model import Scene

#: A robot-turn position: (abstract state, DFA state, human moves left).
Position = tuple[State, DFAState, int]


@dataclass(frozen=True)
class Step:
    """One step of a play: who acted, the action, its quantized cost in
    costmap units (0 for the human), and the abstract state it produced."""

    who: str  # "robot" or "human"
    action: str
    cost: float
    state: State


@dataclass(frozen=True)
class Solution:
    """The solved game.

    - `cost_bound`: E_p in costmap units (`units * resolution`), None when infinite;
    - `realizable`: E_p <= budget (None without a budget);
    - `states`: game positions the solver represented;
    - `strategy`: the robot's action at every robot-turn position of finite value;
    - `principal_play`: the strategy against the human's worst replies, to the win;
    - `counter_play`: None unless the robot loses.  When E_p is infinite, a play
      in which it never wins: the human keeps to positions of infinite value, the
      robot takes its cheapest action, until the robot has no action or the play
      comes back to a position it has visited.  When E_p exceeds the budget, the
      principal play (the human's answers that cost the best strategy too much).
      None also when the robot loses but a time limit left no time to build the
      play (the compiled solver's hand-over: `stats["counter_play"]` says so).
    """

    cost_bound: float | None
    units: int | None
    resolution: float
    budget: float | Decimal | None  # a Decimal as written on the command line: compared exactly
    realizable: bool | None
    k: int
    states: int
    seconds: Mapping[str, float]
    strategy: Mapping[Position, str] = field(repr=False)
    principal_play: tuple[Step, ...] = ()
    counter_play: tuple[Step, ...] | None = None
    objects: tuple[str, ...] = ()  # names for `at`, in order, to print states
    stats: Mapping[str, Any] = field(default_factory=dict)  # solver-specific counters
    #: Set when a time limit stopped the solver before E_p was proven: then
    #: `lower_units <= E_p / resolution <= units` (lower proven by refutation,
    #: `units` by `strategy`, checked against every human reply; `units` None
    #: when no strategy was found in time), the plays follow that strategy,
    #: and `realizable` is None when the budget falls between the two.
    lower_units: int | None = None

    @property
    def exact(self) -> bool:
        """Whether `cost_bound` is E_p (and not an upper bound on it)."""
        return self.lower_units is None

    @property
    def lower_bound(self) -> float | None:
        """E_p's proven lower bound in costmap units: E_p itself when exact."""
        if self.lower_units is None:
            return self.cost_bound
        return math.inf if self.lower_units == math.inf else in_costmap_units(self.lower_units, self.resolution)

    def to_json(self) -> dict[str, Any]:
        """Spec §8's fields, the units and the plays."""
        out: dict[str, Any] = {
            "realizable": self.realizable, "cost_bound": self.cost_bound, "budget": json_number(self.budget),
            "k": self.k, "states": self.states, "seconds": dict(self.seconds),
            "units": self.units, "resolution": self.resolution, "stats": dict(self.stats),
            "principal_play": [self._step(s) for s in self.principal_play],
        }
        if not self.exact:  # a time limit stopped the solver: E_p in [lower_bound, cost_bound]
            out["exact"] = False
            out["lower_bound"] = None if self.lower_bound == math.inf else self.lower_bound
        out["counter_play"] = (None if self.counter_play is None
                               else [self._step(s) for s in self.counter_play])
        return out

    def _step(self, step: Step) -> dict[str, Any]:
        return {"who": step.who, "action": step.action, "cost": step.cost,
                "state": state_json(step.state, self.objects)}


def json_number(x: float | Decimal | None) -> float | None:
    """`x` for JSON: a Decimal as an int when whole (exact), else the float
    nearest it (JSON readers hold floats)."""
    if isinstance(x, Decimal):
        return int(x) if x == x.to_integral_value() else float(x)
    return x


class OutOfReach(InputError):
    """A game this solver cannot hold (its packing, its integers, its
    stack); the message names the limit.  `--solver auto` then tries the
    next solver; asked for by name, it is the user's error message."""


def won_at_start(scene: Scene, k: int, resolution: float, budget: float | None,
                 seconds: Mapping[str, float]) -> Solution:
    """The solution when ρ(v0) alone is accepted: E_p = 0, nothing to play."""
    return Solution(0.0, 0, resolution, budget, verdict(0, resolution, budget), k, 0, seconds,
                    {}, (), None, scene.object_names)


def check_parameters(scene: Scene, k: int | None, resolution: float) -> int:
    """The human's moves (default: the scene's k), after checking k and the resolution."""
    k = scene.k if k is None else k
    if k < 0:
        raise InputError(f"k must be >= 0, found {k}")
    if not resolution > 0 or math.isinf(resolution):
        raise InputError(f"resolution must be a positive number, found {resolution}")
    largest = largest_cost(scene)
    if resolution > largest > 0:
        raise InputError(
            f"resolution {resolution:g} is coarser than every action cost (the largest is {largest:g}): "
            f"each action would round up to one unit, and E_p would count actions instead of "
            f"measuring cost; use a resolution of at most {largest:g}")
    return k


def largest_cost(scene: Scene) -> float:
    """The largest finite cost an action of the scene can have: grab, drop,
    and every rule of its costmap (0 when there is none)."""
    costs = [scene.grab_cost, scene.drop_cost]
    if scene.costmap is not None:
        costs += [rule.cost for rule in scene.costmap.all_rules()]
    return max((c for c in costs if math.isfinite(c)), default=0.0)


def task_formula(scene: Scene, formula: str | ast.Formula | None) -> ast.Formula:
    """The formula to solve: `formula` (text or AST), or else the scene's task."""
    if formula is None:
        if scene.task is None:
            raise InputError(f"scene {scene.name!r} has no task: give one (task: FORMULA)")
        if scene.parsed is not None and scene.parsed[0] == scene.task:  # parsed by the loader
            return scene.parsed[1]
        formula = scene.task
    if isinstance(formula, str):
        return parse_ltlf(formula, source=f"{scene.name} (task)")
    return formula


def verdict(units: int | None, resolution: float, budget: float | Decimal | None) -> bool | None:
    """Whether E_p = units * resolution is within `budget` (`within`: exact
    on the decimals, so 3 units of 0.1 fit a budget of 0.3)."""
    if budget is None:
        return None
    return units is not None and within(units, resolution, budget)


def bracket_verdict(lower: int | None, upper: int | None, resolution: float,
                    budget: float | Decimal | None) -> bool | None:
    """`verdict` for an anytime answer `lower <= E_p <= upper` (`lower` None:
    `upper` is E_p): True when the upper end fits the budget, False when
    the lower end does not, None when the budget lies between them."""
    if lower is None:
        return verdict(upper, resolution, budget)
    if budget is None:
        return None
    if upper is not None and verdict(upper, resolution, budget):
        return True
    return False if not verdict(lower, resolution, budget) else None
