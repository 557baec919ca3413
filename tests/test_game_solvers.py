"""The solver suite (`symsynth.testing.solver`: hand-solved games and the
properties of every solution) once per solver registered in the
entry-point group `symsynth.solvers`, by the line a plugin's own
repository uses (`symsynth.testing.conformance`)."""

from __future__ import annotations

from symsynth.solvers import SOLVERS
from symsynth.testing import conformance

TestSolvers = conformance("solver", *SOLVERS)


def test_every_built_in_solver_is_covered():
    """The tests run once per registered solver: losing a built-in's entry
    point must not go unseen (an installed third-party one comes on top)."""
    assert set(SOLVERS) >= {"auto", "compiled", "explicit", "forward", "symbolic"}
