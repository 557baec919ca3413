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
"""

from __future__ import annotations

from symsynth.execution.simulate import Policy
from symsynth.game.abstraction import in_costmap_units
from symsynth.game.graph import GameGraph
from symsynth.game.objective_strategy import ObjectiveStrategyFile, robot_moves_at
from symsynth.game.solution import Position


class BudgetPolicy(Policy):
    """The expected-cost strategy of `table` (`symsynth.objective-strategy/1`,
    objective `expected`) on `game` (the same scene, task and resolution)."""

    def __init__(self, table: ObjectiveStrategyFile, game: GameGraph) -> None:
        header = table.header
        if header["objective"] != "expected":
            raise ValueError(f"a budget counter is for the expected-cost strategy, not {header['objective']!r}")
        self.table, self.game = table, game
        self.budget_units: int = header["budget_units"]
        self.waiting: int | None = header["waiting"]
        super().__init__({}, {}, in_costmap_units(self.budget_units, header["resolution"]))
        self.left, self.turns = self.budget_units, 0

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
