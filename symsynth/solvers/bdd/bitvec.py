"""Bounded integers as bit-vectors of BDD variables, and their arithmetic.

A `Domain` variable with `size` values uses bits `name_0, name_1, ...`
(lowest first), each declared next to its primed copy `name_i'`.  Its range
invariant `0 <= x < size` is part of every set over it: the unused bit
patterns are real states unless they are excluded.

Arithmetic works on *vectors of functions* (lists of BDDs, lowest bit
first), so `e - c` can be substituted into a set with one vector compose.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from symsynth.automata.bdd import BDD, Function, lexmin
from symsynth.automata.symbolic import prime

Vector = list[Function]


@dataclass(frozen=True)
class Domain:
    """A variable over `0..size-1`, with its bits and primed bits."""

    name: str
    size: int
    bits: tuple[str, ...]

    @property
    def primed(self) -> tuple[str, ...]:
        return tuple(prime(b) for b in self.bits)

    @classmethod
    def declare(cls, bdd: BDD, name: str, size: int, *, primed: bool = True) -> Domain:
        """Declare the bits at the bottom of the order, each followed by its
        primed copy unless `primed` is false (counters that are only ever
        substituted, such as costs and budgets)."""
        if size < 1:
            raise ValueError(f"domain {name} needs at least one value")
        bits = tuple(f"{name}_{i}" for i in range((size - 1).bit_length()))
        for b in bits:
            bdd.declare(*((b, prime(b)) if primed else (b,)))
        return cls(name, size, bits)

    def least(self, bdd: BDD, u: Function) -> int | None:
        """The least value of x in the set `u` (over x alone, or with other
        variables existentially quantified); None when `u` is empty."""
        if u == bdd.false:
            return None
        others = bdd.support(u) - set(self.bits)
        if others:
            u = bdd.exist(others, u)
        high_first = lexmin(bdd, u, reversed(self.bits))
        return sum(1 << i for i, bit in enumerate(reversed(high_first)) if bit)

    def assignment(self, value: int, primed: bool = False) -> dict[str, bool]:
        """The bit values of x = value (x' = value when `primed`), for `let`."""
        names = self.primed if primed else self.bits
        return {b: bool(value >> i & 1) for i, b in enumerate(names)}

    def eq(self, bdd: BDD, value: int, primed: bool = False) -> Function:
        """x = value  (x' = value when `primed`)."""
        if not 0 <= value < self.size:
            raise ValueError(f"{value} outside the domain of {self.name} (size {self.size})")
        return bdd.cube(self.assignment(value, primed)) if self.bits else bdd.true

    def unchanged(self, bdd: BDD) -> Function:
        """x' = x."""
        result = bdd.true
        for b, p in zip(self.bits, self.primed):
            result &= bdd.apply("<=>", bdd.var(b), bdd.var(p))
        return result

    def invariant(self, bdd: BDD, primed: bool = False) -> Function:
        """0 <= x < size."""
        return less_than(bdd, self.vector(bdd, primed), self.size)

    def vector(self, bdd: BDD, primed: bool = False) -> Vector:
        return [bdd.var(b) for b in (self.primed if primed else self.bits)]

    def decode(self, assignment: dict[str, bool], primed: bool = False) -> int:
        names = self.primed if primed else self.bits
        return sum(1 << i for i, b in enumerate(names) if assignment.get(b, False))


def constant(bdd: BDD, value: int, width: int) -> Vector:
    if value < 0 or value >> width:
        raise ValueError(f"{value} does not fit in {width} bits")
    return [bdd.true if value >> i & 1 else bdd.false for i in range(width)]


def less_than(bdd: BDD, x: Sequence[Function], bound: int) -> Function:
    """x < bound for a constant bound (true when bound exceeds every value)."""
    if bound >> len(x):
        return bdd.true
    return less(bdd, x, constant(bdd, bound, len(x)))


def less(bdd: BDD, x: Sequence[Function], y: Sequence[Function]) -> Function:
    """x < y, unsigned, equal widths; scanned from the lowest bit up."""
    result = bdd.false
    for xi, yi in zip(x, y):
        # at this bit: x < y iff (!xi & yi) or (xi == yi and lower bits say x < y)
        result = (~xi & yi) | (bdd.apply("<=>", xi, yi) & result)
    return result


def less_equal(bdd: BDD, x: Sequence[Function], y: Sequence[Function]) -> Function:
    return ~less(bdd, y, x)


def subtract(bdd: BDD, x: Sequence[Function], y: Sequence[Function]) -> Vector:
    """The bits of x - y modulo 2^width (meaningful where y <= x)."""
    borrow = bdd.false
    out = []
    for xi, yi in zip(x, y):
        out.append(bdd.apply("xor", bdd.apply("xor", xi, yi), borrow))
        # borrow' = (!xi & yi) | (!(xi ^ yi) & borrow)
        borrow = (~xi & yi) | (~bdd.apply("xor", xi, yi) & borrow)
    return out

