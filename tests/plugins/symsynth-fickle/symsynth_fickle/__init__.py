"""`fickle`: on each turn, with the run's move probability, the move after
which the strategy may still have to spend the most (the strategy's
budgets, which it says it needs); otherwise it passes."""

import math
import random


class Fickle:
    name = "fickle"

    def __init__(self, context):
        self.rng = random.Random(f"fickle/{context.seed}")
        self.probability = context.probability
        self.budget = context.budget

    def choose(self, turn):
        if not turn.options or self.rng.random() >= self.probability:
            return None
        return max(turn.options, key=self._worth)  # the first of the dearest

    def _worth(self, option):
        if option.after is None:
            return -1.0  # the move would complete the task
        value = self.budget(option.after)
        return math.inf if value is None else value


def fickle(context):
    return Fickle(context)


fickle.needs = {"budgets"}
