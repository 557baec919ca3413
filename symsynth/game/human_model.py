"""Human models (semantics §9): at every human turn, a probability
distribution over the human's choices there, the pass and each legal move.

A model is a plugin, found through the entry-point group
`symsynth.human_models` like any third party's: the name maps to a factory
that takes the model's arguments as written (`random(0.3)`: the text
"0.3") and returns a `HumanModel`, or raises `ValueError` saying what the
arguments should be.  symsynth's own `random(P)` registers there too.

The solvers of `--objective expected` read `distribution`; the simulator's
`random` human draws from the same object (`draw`), so what is solved for
is what is simulated.  Probabilities are exact fractions: a model written
`random(0.3)` passes with probability 7/10, not with the float nearest it.
"""

from __future__ import annotations

import random
import re
from collections.abc import Callable, Sequence
from fractions import Fraction
from typing import Protocol, runtime_checkable

from symsynth import plugins
from symsynth.errors import InputError
from symsynth.game.abstraction import Move, State

GROUP = "symsynth.human_models"

#: `name`, `name(a, b)` (scene files) or `name:a,b` (the command line)
_SPEC = re.compile(r"^\s*([A-Za-z_][\w-]*)\s*(?:\((.*)\)|:(.*))?\s*$")


@runtime_checkable
class HumanModel(Protocol):
    """A distribution over the human's choices at each human turn."""

    #: the model as a scene file writes it, e.g. "random(0.3)"
    name: str

    def distribution(self, v: State, h: int, moves: Sequence[Move]) -> tuple[Fraction, tuple[Fraction, ...]]:
        """(probability of the pass, one probability per move of `moves`,
        in order) at a human turn in state `v` with `h` moves left; `moves`
        are the legal ones (empty when h = 0).  They sum to 1."""
        ...


class UniformModel(Protocol):
    """A model whose distribution depends on the number of legal moves alone,
    every move equally likely: the compiled solvers need only
    `pass_probability(count)` (the rest is split evenly among the moves)."""

    name: str

    def pass_probability(self, h: int, count: int) -> Fraction: ...


class RandomModel:
    """`random(P)`: with moves left and a non-empty set M of legal moves,
    pass with probability 1 - P and take each move of M with P / |M| (also
    when two moves lead to the same state); otherwise pass."""

    def __init__(self, probability: Fraction):
        if not 0 <= probability <= 1:
            raise ValueError(f"random(P) needs 0 <= P <= 1, found {_text(probability)}")
        self.probability = probability
        self.name = f"random({_text(probability)})"

    def pass_probability(self, h: int, count: int) -> Fraction:
        return Fraction(1) - self.probability if h > 0 and count > 0 else Fraction(1)

    def distribution(self, v: State, h: int, moves: Sequence[Move]) -> tuple[Fraction, tuple[Fraction, ...]]:
        stay = self.pass_probability(h, len(moves))
        each = (1 - stay) / len(moves) if moves else Fraction(0)
        return stay, (each,) * len(moves)

    def __repr__(self) -> str:
        return self.name


def random_model(*args: str) -> RandomModel:
    """The factory registered as `random`: one argument, the probability P
    that the human moves on a turn where it can, a decimal in [0, 1]."""
    if len(args) != 1:
        raise ValueError(f"random takes one argument, the move probability P (0 <= P <= 1), "
                         f"found {len(args)}")
    try:
        probability = Fraction(args[0].strip())
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"random(P) needs a number 0 <= P <= 1, found {args[0].strip()!r}") from None
    return RandomModel(probability)


def _text(x: Fraction) -> str:
    """A probability as a short decimal when it is one (3/10 -> 0.3)."""
    for digits in range(0, 13):
        if (x * 10 ** digits).denominator == 1:
            return f"{float(x):.{digits}f}" if digits else str(x.numerator)
    return f"{x.numerator}/{x.denominator}"


MODELS = plugins.Registry(GROUP, "human model", InputError)


def parse_model(text: str, where: str = "human model") -> HumanModel:
    """The model `text` names (`random(0.3)` or `random:0.3`); an
    `InputError` naming `where`, the installed models or what the
    arguments should be."""
    match = _SPEC.match(text)
    if match is None:
        raise InputError(f"{where}: expected NAME(ARGS) or NAME:ARGS (e.g. random(0.3) or random:0.3), "
                         f"found {text!r}")
    name, inner = match.group(1), match.group(2) if match.group(2) is not None else match.group(3)
    factory: Callable[..., HumanModel] = MODELS.get_or_fail(name)
    args = [] if inner is None or not inner.strip() else [a.strip() for a in inner.split(",")]
    try:
        model = factory(*args)
    except ValueError as error:
        raise InputError(f"{where}: {error}") from None
    if not isinstance(model, HumanModel):
        raise InputError(f"{where}: human model plugin {name!r} returned {model!r}, which has no "
                         "`name` and `distribution`")
    return model


def draw(model: HumanModel, rng: random.Random, v: State, h: int, moves: Sequence[Move]) -> Move | None:
    """One choice of the model's human (None: the pass), drawn with `rng`."""
    stay, each = model.distribution(v, h, moves)
    x = Fraction(rng.random())
    if x < stay or not moves:
        return None
    x -= stay
    for move, p in zip(moves, each):
        if x < p:
            return move
        x -= p
    return moves[-1]  # x lands on the upper end only by rounding of the last share
