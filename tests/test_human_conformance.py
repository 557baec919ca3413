"""The human suite (`symsynth.testing.human`) for the built-in humans, by
the line a plugin's own repository uses; and the suite itself refuses a
human that answers with a move it was not offered, or differently for the
same seed."""

from __future__ import annotations

import dataclasses
import itertools

import pytest

from symsynth.execution.human import RandomHuman
from symsynth.testing import conformance
from symsynth.testing import human as human_suite

TestHumans = conformance("human", "none", "random", "adversarial")


class Registry:
    def __init__(self, factory):
        self.factory = factory

    def get_or_fail(self, name):
        return self.factory


class Cheat:
    """Answers with an option the turn does not hold: the first one's move
    under another action name."""

    name = "cheat"

    def choose(self, turn):
        if not turn.options:
            return None
        first = turn.options[0]
        return dataclasses.replace(first, action=first.action + "!")


class Unseeded(RandomHuman):
    """A random human whose generator is not the context's."""

    counter = itertools.count()

    def __init__(self, seed, probability):
        super().__init__(next(self.counter), probability)


@pytest.mark.parametrize("factory, test", [
    (lambda context: Cheat(), "test_it_answers_with_what_is_offered"),
    (lambda context: Unseeded(context.seed, 0.5), "test_the_same_context_gives_the_same_answers"),
])
def test_the_suite_refuses_a_human_that_breaks_the_contract(monkeypatch, factory, test):
    monkeypatch.setattr(human_suite, "HUMANS", Registry(factory))
    monkeypatch.setattr(human_suite, "human_needs", lambda name: frozenset())
    case = human_suite.HumanConformance()
    case.name = "broken"
    with pytest.raises(AssertionError):
        getattr(case, test)()
