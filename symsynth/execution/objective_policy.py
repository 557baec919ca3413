"""An objective's strategy (semantics §9) followed in the world, with its
memory.

The expected-cost strategy of `--objective expected` is keyed by the
position *and* the budget left (units): `BudgetPolicy` keeps that counter
for the run, starting at B and lowered by the abstract cost (in units, as
the game charges it) of each action the robot carries out, and counts the
robot's turns; after `waiting` of them (where EX is only an infimum) it
plays the worst-case strategy the file carries.  A best-effort strategy
remembers nothing: a plain `Policy` of its positions follows it.

The run's bound is B: every play of the strategy costs at most B in the
abstraction, and a measured cost is at most the abstract one (or the run
reports a soundness divergence), so a run above B is a bug.

Against the adversary, `BudgetPolicy.still_to_pay` answers for a position
with the counter as it stands: the most the strategy may still pay from the
robot's turn there (`solvers.objectives.play.still_to_pay`, every turn a
play reaches).  The adversary takes the reply where that is largest, so it
plays against the strategy it meets, budget memory included, and drives
the run to the largest cost any human can force (at most B).
"""

from __future__ import annotations

from collections.abc import Mapping

from symsynth.execution.policy import Policy
from symsynth.game.abstraction import in_costmap_units
from symsynth.game.graph import GameGraph
from symsynth.game.objective_strategy import ObjectiveStrategyFile, robot_moves_at
from symsynth.game.solution import Position


class BudgetPolicy(Policy):
    """The expected-cost strategy of `table` (`symsynth.objective-strategy/1`,
    objective `expected`) on `game` (the same scene, task and resolution);
    `to_pay`: the most it may still pay (units) at each (position, budget
    left, count of robot turns) a play reaches, for `still_to_pay`."""

    def __init__(self, table: ObjectiveStrategyFile, game: GameGraph,
                 to_pay: Mapping[tuple[Position, int, int], int] | None = None) -> None:
        header = table.header
        if header["objective"] != "expected":
            raise ValueError(f"a budget counter is for the expected-cost strategy, not {header['objective']!r}")
        self.table, self.game = table, game
        self.budget_units: int = header["budget_units"]
        self.waiting: int | None = header["waiting"]
        super().__init__({}, {}, in_costmap_units(self.budget_units, header["resolution"]))
        self.left, self.turns = self.budget_units, 0
        self.to_pay = to_pay or {}

    def start(self) -> None:
        self.left, self.turns = self.budget_units, 0

    def action(self, position: Position) -> tuple[str, bool] | None:
        if self.waiting is not None and self.turns >= self.waiting:
            chosen = self.table.worst.get(position)
        else:
            chosen = self.table.positions.get((position, self.left))
        return None if chosen is None else (chosen, False)

    def moved(self, position: Position, action: str) -> None:
        self.left -= robot_moves_at(self.game, position)[action][1]
        self.turns += 1

    def memory(self) -> object:
        """The budget left and the count of robot turns the strategy keys by."""
        return self.left, self._count()

    def still_to_pay(self, position: Position) -> float | None:
        """The most the strategy may still pay (costmap units) from the
        robot's turn at `position` with the budget left now (None: no play
        of it reaches that turn)."""
        units = self.to_pay.get((position, self.left, self._count()))
        return None if units is None else in_costmap_units(units, self.table.header["resolution"])

    def _count(self) -> int:
        """The robot turns so far as the strategy counts them (`play.ExpectedStrategy.count`)."""
        return 0 if self.waiting is None else min(self.turns, self.waiting)
