"""The suite every simulated-human plugin must pass (`execution.human`):
`conformance("human", NAME)` (`symsynth.testing`) runs it on a registered
human.  The human plays the human's turns of small hand-made games
(`testing.games`) against the explicit solver's strategy, in the
abstraction (no simulator: the options are the game's human moves, as the
simulator offers them; their poses are not read here), and

- its factory makes a `Human` from a `HumanContext` (a `name`, a `choose`),
  and declares only needs symsynth provides (`execution.human.NEEDS`);
- on every turn it answers None (a pass), one of the options offered (the
  same object), or a `Request` naming an object of the scene, and with no
  option offered (no moves left) nothing but a pass or a request;
- made again from the same context it gives the same answers.

A human that needs "budgets" is given the strategy's budget of every
position, as in a simulation (`problem.simulate`); others get None.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from typing import Any

from symsynth.execution.human import HUMANS, HumanContext, Option, Request, Turn, human_needs
from symsynth.game.abstraction import initial_state, legal_human_moves, robot_moves
from symsynth.game.graph import GameGraph
from symsynth.game.solution import Position, Solution
from symsynth.game.strategy import strategy_table
from symsynth.logic import parse_ltlf
from symsynth.scene.geometry import Pose
from symsynth.scene.model import Scene
from symsynth.solvers.explicit import solve_explicit
from symsynth.testing import Conformance
from symsynth.testing.gamegen import random_scene
from symsynth.testing.games import pick

SEEDS = range(6)
PROBABILITIES = (0.0, 0.3, 1.0)


#: Generated games the robot wins against a human with moves to make
#: (`testing.gamegen`: 3 objects and k = 1; 2 objects and k = 1; 3 and k = 2).
GENERATED = (5, 17, 30)


@functools.cache
def games() -> tuple[Scene, ...]:
    """Games with something for a human to do: the pick game with two
    human moves, and generated ones."""
    return (pick(k=2),) + tuple(random_scene(seed) for seed in GENERATED)


def _solved(scene: Scene) -> tuple[Any, Solution, dict[Position, float | None]]:
    """The game's formula, the explicit solver's solution and its budgets
    (kept for the scenes of `games`, which are kept)."""
    if id(scene) in _SOLVED:
        return _SOLVED[id(scene)]
    assert scene.task is not None, f"{scene.name}: a suite game without a task"
    formula = parse_ltlf(scene.task)
    solution = solve_explicit(scene, formula)
    assert solution.cost_bound is not None, f"{scene.name}: a suite game the robot cannot win"
    solved = formula, solution, dict(strategy_table(scene, scene.task, solution, formula=formula).budgets)
    if any(scene is game for game in games()):
        _SOLVED[id(scene)] = solved
    return solved


_SOLVED: dict[int, tuple[Any, Solution, dict[Position, float | None]]] = {}


class HumanConformance(Conformance):
    """The human suite; `self.name` is the registered human under test."""

    def test_it_is_made_from_a_context(self):
        needs = human_needs(self.name)  # also: only needs symsynth knows
        assert isinstance(needs, frozenset)
        human = HUMANS.get_or_fail(self.name)(HumanContext(0, 0.3, lambda position: None))
        assert isinstance(human.name, str) and callable(human.choose)

    def test_it_answers_with_what_is_offered(self):
        for scene in games():
            for seed in SEEDS:
                for probability in PROBABILITIES:
                    for turn, answer in play(self.name, scene, seed, probability):
                        if turn.options:
                            assert answer is None or isinstance(answer, Request) \
                                or answer in turn.options, answer
                        else:
                            assert answer is None or isinstance(answer, Request), answer
                        if isinstance(answer, Request):
                            assert answer.obj in scene.object_names, answer

    def test_the_same_context_gives_the_same_answers(self):
        for scene in games():
            for seed in SEEDS:
                first = [_key(a) for _, a in play(self.name, scene, seed, 0.5)]
                assert [_key(a) for _, a in play(self.name, scene, seed, 0.5)] == first


def _key(answer: Any) -> Any:
    return answer if answer is None or isinstance(answer, Request) else (answer.action, answer.after)


def play(name: str, scene: Scene, seed: int, probability: float) -> Iterator[tuple[Turn, Any]]:
    """The human `name`'s turns and answers in one play of `scene` against
    the explicit solver's strategy (which wins every game here); a request
    is taken as a pass (the simulator resolves it against the world)."""
    formula, solution, budgets = _solved(scene)
    needed = "budgets" in human_needs(name)
    human = HUMANS.get_or_fail(name)(HumanContext(seed, probability, budgets.get if needed else lambda p: None))
    game = GameGraph(scene, formula, solution.resolution)
    v = initial_state(scene)
    q, h, actions, last = game.read(game.dfa.initial, v), solution.k, 0, None
    for _ in range(100):  # the strategy wins within a few actions; a runaway play is a bug here
        options = tuple(_options(scene, game, v, q, h))
        turn = Turn((v, q, h), actions, last, options)
        answer = human.choose(turn)
        yield turn, answer
        if isinstance(answer, Option):
            if answer.after is None:
                return  # the human's move completed the task
            v, q, h = answer.after
        action = solution.strategy[(v, q, h)]
        (w, _), = [(w, c) for a, w, c in robot_moves(scene, v) if a == action and math.isfinite(c)]
        v, q, actions, last = w, game.read(q, w), actions + 1, action
        if game.accepts(q):
            return
    raise AssertionError(f"{scene.name}: the play did not end")


def _options(scene: Scene, game: GameGraph, v: Any, q: Any, h: int) -> Iterator[Option]:
    if h <= 0:
        return
    for move in legal_human_moves(scene, v):
        q2 = game.read(q, move.after)
        yield Option(move.action, move.obj, Pose(), None if game.accepts(q2) else (move.after, q2, h - 1))
