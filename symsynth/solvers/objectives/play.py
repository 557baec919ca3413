"""The strategies of semantics §9 played on their arena: what a strategy
does at a turn, every play it allows checked, and runs against humans.

- `ExpectedStrategy`: the expected-cost strategy with the budget left as
  its memory and, where EX is only an infimum, a count of its robot turns:
  after `waiting` of them it plays the worst-case strategy (B-safe then).
- `BestEffortStrategy`: the worst-case strategy at winning turns, the
  cheapest cooperative play's move at cooperative ones.
- `check_expected` follows a strategy through every human behaviour (each
  pass and move at each human turn) and returns the largest total cost
  (raising on a play that never wins), from `still_to_pay` (the most still
  to pay from every turn reached, which the world's adversary maximizes);
  `check_best_effort` checks that no robot move lowers the class.
- `run`: one play against a human (`model`: the arena's model; `worst`:
  the reply of largest V; `cooperative`: the reply on a cheapest cooperative
  play), its cost and whether it won.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from symsynth.solvers.objectives.arena import INF, Arena
from symsynth.solvers.objectives.steps import Steps
from symsynth.solvers.objectives.walk import Turns, expected_turns

Turn = tuple[int, int, int]  # node, budget left (units), robot turns so far


class Strategy(Protocol):
    arena: Arena

    def move(self, turn: Turn) -> int:
        """The robot's move (an edge index of the arena) at a robot turn."""
        ...

    def count(self, turns: int) -> int:
        """What the strategy remembers of its robot turns so far."""
        ...


@dataclass
class ExpectedStrategy:
    arena: Arena
    steps: Steps  # the move at each (turn, budget left)
    waiting: int | None  # None: never switch (the strategy is B-safe as it is)

    def count(self, turns: int) -> int:
        return 0 if self.waiting is None else min(turns, self.waiting)

    def move(self, turn: Turn) -> int:
        i, b, w = turn
        if self.waiting is not None and w >= self.waiting:
            return int(self.arena.wchoice[i])
        return self.steps.choice(i, b)


@dataclass
class BestEffortStrategy:
    arena: Arena
    cooperative: np.ndarray  # the cheapest cooperative play's move at each node

    def count(self, turns: int) -> int:
        return 0

    def move(self, turn: Turn) -> int:
        i = turn[0]
        return int(self.arena.wchoice[i] if self.arena.rval[i] < INF else self.cooperative[i])


def replies(arena: Arena, t: int) -> list[int]:
    """The robot turns the human turn at node t leads to (-1: won), the pass first."""
    return [t] + [int(j) for j in arena.h_tgt[arena.h_off[t]:arena.h_off[t + 1]]]


def check_expected(strategy: ExpectedStrategy, budget: int) -> int:
    """The largest total cost (units) of a play of `strategy` from the start
    with `budget` left, over every human behaviour; a `RuntimeError` when a
    play goes in circles or reaches a turn where the strategy has no move."""
    turns = still_to_pay(strategy, budget)
    start = (turns.budget == budget) & (turns.count == 0)
    return max((int(turns.worst[start & (turns.node == j)][0]) if j >= 0 else 0)
               for j in replies(strategy.arena, 0))


def still_to_pay(strategy: ExpectedStrategy, budget: int) -> Turns:
    """The most `strategy` may still pay (units) from each robot turn
    (node, budget left, its count) that a play of it from the start with
    `budget` reaches, over every human behaviour: what an adversary that
    knows the strategy maximizes (`walk.expected_turns`).  A `RuntimeError`
    as `check_expected`."""
    return expected_turns(strategy.arena, strategy.steps, strategy.waiting, budget)


def check_best_effort(strategy: BestEffortStrategy, classes: np.ndarray) -> int:
    """Every robot turn a play of `strategy` reaches (against every human):
    its move leads to a human turn of the same class (0 winning, 1
    cooperative, 2 losing; `classes` at human turns is the class there, at
    robot turns indexed by node + n); how many turns were checked.  A
    `RuntimeError` names the first that drops."""
    arena = strategy.arena
    n = arena.size
    seen: set[int] = set()
    todo = [j for j in replies(arena, 0) if j >= 0]
    while todo:
        i = todo.pop()
        if i in seen:
            continue
        seen.add(i)
        if classes[n + i] == 2:
            continue  # losing: nothing to keep
        e = strategy.move((i, 0, 0))
        t = int(arena.r_tgt[e])
        after = 0 if t < 0 else int(classes[t])
        if after > classes[n + i]:
            raise RuntimeError(f"the robot's move at node {i} drops the class from {classes[n + i]} to {after}")
        if t >= 0:
            todo += [j for j in replies(arena, t) if j >= 0]
    return len(seen)


def run(strategy: Strategy, budget: int, human: str, rng: random.Random, coop: np.ndarray | None = None,
        limit: int = 100_000) -> tuple[int, bool]:
    """One play from the start: (total cost in units, won).  `human`:
    `model`, `worst` or `cooperative` (needs `coop`, C at the robot turns).
    A play that reaches a losing turn, or `limit` robot turns, ends unwon."""
    arena = strategy.arena
    cost, b, w, t = 0, budget, 0, 0
    for _ in range(limit):
        j = _reply(arena, t, human, rng, coop)
        if j < 0:
            return cost, True
        if arena.rval[j] >= INF and (coop is None or coop[j] >= INF):
            return cost, False  # losing, or no strategy there
        e = strategy.move((j, b, w))
        if e < 0:
            return cost, False
        c = int(arena.r_units[e])
        cost, b, w, t = cost + c, b - c, w + 1, int(arena.r_tgt[e])
        if t < 0:
            return cost, True
    return cost, False


def _reply(arena: Arena, t: int, human: str, rng: random.Random, coop: np.ndarray | None) -> int:
    options = replies(arena, t)
    if human == "model":
        x = rng.random() - arena.stay[t]
        if x < 0 or len(options) == 1:
            return t
        for k, j in enumerate(options[1:]):
            x -= arena.h_prob[arena.h_off[t] + k]
            if x < 0:
                return j
        return options[-1]
    if human == "worst":
        return max(options, key=lambda j: -1 if j < 0 else arena.rval[j])
    if coop is None:
        raise ValueError("a cooperative human needs the cooperative costs")
    return min(options, key=lambda j: -1 if j < 0 else coop[j])


def exact(arena: Arena, node_choice: np.ndarray, finish: bool) -> float:
    """From the start, against the model, for a strategy that plays
    node_choice[i] at robot turn i (-1: none): the probability of winning
    (`finish`) or the expected cost (the strategy must win with probability 1)."""
    from symsynth.solvers.objectives.kernels import markov

    x = markov(node_choice, arena.stay, arena.r_tgt, arena.r_units, arena.h_off, arena.h_tgt, arena.h_prob, finish)
    y = arena.stay[0] * x[0]
    for e in range(int(arena.h_off[0]), int(arena.h_off[1])):
        j = int(arena.h_tgt[e])
        y += arena.h_prob[e] * (x[j] if j >= 0 else float(finish))
    return float(y)


def best_effort_choice(arena: Arena, coop: np.ndarray, rc: np.ndarray) -> np.ndarray:
    """The best-effort strategy as one move per node (-1 at losing turns)."""
    return np.where(arena.rval < INF, arena.wchoice, np.where(rc < INF, coop, -1)).astype(np.int64)
