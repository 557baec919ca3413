"""The robot's side of a run: the action a strategy takes at a position,
and best effort where it has none."""

from __future__ import annotations

from collections.abc import Mapping

from symsynth.game.solution import Position


class Policy:
    """The robot's action at a position: the strategy's, or -- best effort,
    where the strategy has none -- the action of a strategy for fewer human
    moves left (`fallback`, e.g. a full `Solution.strategy`), as if the
    human had only h' < h moves left."""

    def __init__(self, actions: Mapping[Position, str], budgets: Mapping[Position, float | None],
                 bound: float | None, fallback: Mapping[Position, str] | None = None) -> None:
        self.actions, self.budgets, self.bound, self.fallback = actions, budgets, bound, fallback

    def action(self, position: Position) -> tuple[str, bool] | None:
        """(action, best effort?) or None."""
        try:  # one lookup: a lazy strategy searches on a miss
            return self.actions[position], False
        except KeyError:
            pass
        if self.fallback is None:
            return None
        v, q, h = position
        for fewer in range(h, -1, -1):
            try:
                return self.fallback[(v, q, fewer)], True
            except KeyError:
                continue
        return None

    def budget(self, position: Position) -> float | None:
        return self.budgets.get(position)

    def start(self) -> None:
        """A run begins (a policy with memory forgets the last run's)."""

    def moved(self, position: Position, action: str) -> None:
        """The robot carried out `action` at `position` (a policy with memory counts it)."""

    def memory(self) -> object:
        """What the policy remembers of the run now (None: nothing); a
        position the robot's turn comes back to with other memory is
        progress (a budget spent), not the world failing the abstraction."""
        return None
