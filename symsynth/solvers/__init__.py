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
`symsynth.testing.solver`, which tests/test_game_solvers.py runs on every
registered one.

A solver with work to do once per process rather than per game (the
compiled solver's kernels are compiled, or loaded from numba's cache, on
first use) says so with a `prepare` attribute, a function of no arguments
that does it (what it returns is ignored); `prepare(name)` runs it and
times it, so that comparison runs start their clock after it.
"""

from __future__ import annotations

import time
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


def prepare(name: str) -> float:
    """Run the registered solver's once-per-process set-up (its `prepare`
    attribute, when it has one) and return the seconds it took."""
    hook = getattr(SOLVERS[name], "prepare", None)
    if hook is None:
        return 0.0
    clock = time.perf_counter()
    hook()
    return time.perf_counter() - clock
