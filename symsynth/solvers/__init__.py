"""The solvers of the game that `symsynth.game` defines, above it: the
explicit one (`explicit`: Dijkstra over the positions of `game.graph`),
the forward search with its lower bound (`forward`, `bound`) and the
symbolic one (`symbolic`, on the BDD encoding in `bdd/`).

By name, for the command line and for comparison runs, through the
entry-point group `symsynth.solvers` (`plugins`), where symsynth's own
three register like any other.

Every solver has the signature of `Solver` and returns a `Solution` whose
value is semantics §6's `E_p`; they differ in how they compute it.  A
third-party solver is checked against the same contract by
`tests/test_game_solvers.py` once it is registered.
"""

from __future__ import annotations

from typing import Protocol

from symsynth import plugins
from symsynth.errors import InputError
from symsynth.game.solution import Solution
from symsynth.logic import ast
from symsynth.scene.model import Scene

GROUP = "symsynth.solvers"


class Solver(Protocol):
    def __call__(self, scene: Scene, formula: str | ast.Formula | None = None, *,
                 k: int | None = None, budget: float | None = None,
                 resolution: float = 1.0) -> Solution: ...


#: name -> solver, loaded when asked for.
SOLVERS = plugins.Registry(GROUP, "solver", InputError)
DEFAULT_SOLVER = "auto"
