"""`tidy(P)`: with a move left, the human clears an object away to Else
with probability P (uniformly among its legal moves to Else) and passes
otherwise; it never puts anything on a location.  Not uniform over all
moves, so the compiled solver hands it to the explicit one."""

from __future__ import annotations

from fractions import Fraction


class Tidy:
    def __init__(self, probability: Fraction):
        self.probability = probability
        self.name = f"tidy({probability.numerator}/{probability.denominator})"

    def distribution(self, v, h, moves):
        away = [m.location == "Else" for m in moves]
        if h == 0 or not any(away):
            return Fraction(1), tuple(Fraction(0) for _ in moves)
        share = self.probability / sum(away)
        return 1 - self.probability, tuple(share if a else Fraction(0) for a in away)


def tidy(*args: str) -> Tidy:
    if len(args) != 1:
        raise ValueError(f"tidy takes one argument, the probability P of tidying, found {len(args)}")
    try:
        p = Fraction(args[0])
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"tidy(P) needs a number 0 <= P <= 1, found {args[0]!r}") from None
    if not 0 <= p <= 1:
        raise ValueError(f"tidy(P) needs 0 <= P <= 1, found {args[0]}")
    return Tidy(p)
