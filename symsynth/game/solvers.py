"""The game solvers by name, for the command line and for comparison runs.

Every solver has the signature of `Solver` and returns a `Solution` whose
value is semantics §6's `E_p`; they differ in how they compute it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from symsynth.game.explicit import solve_explicit
from symsynth.game.forward import solve_forward
from symsynth.game.solution import Solution
from symsynth.game.symbolic import solve_symbolic
from symsynth.logic import ast
from symsynth.scene.model import Scene


class Solver(Protocol):
    def __call__(self, scene: Scene, formula: str | ast.Formula | None = None, *,
                 k: int | None = None, budget: float | None = None,
                 resolution: float = 1.0) -> Solution: ...


SOLVERS: dict[str, Callable[..., Solution]] = {
    "symbolic": solve_symbolic,
    "explicit": solve_explicit,
    "forward": solve_forward,
}
DEFAULT_SOLVER = "symbolic"
