"""The compiled solver (symsynth/solvers/compiled.py) against the explicit
one written in Python: the same positions explored, the same value, and a
strategy that wins within it against every human behaviour, on generated
scenes with and without contacts and with interchangeable objects."""

from __future__ import annotations

import pytest

from symsynth.errors import InputError
from symsynth.logic import parse_ltlf
from symsynth.solvers.compiled import solve_compiled
from symsynth.solvers.explicit import solve_explicit
from support.gamegen import alike_scene, random_scene
from support.games import make_scene, worst_case_of


@pytest.mark.parametrize("chunk", range(4))
def test_same_positions_and_value_as_the_explicit_solver(chunk):
    kinds = {"finite": 0, "infinite": 0}
    for seed in range(60 * chunk, 60 * (chunk + 1)):
        contacts = seed % 3 == 0
        scene = random_scene(3000 + seed, positive=seed % 2 == 0, contacts=contacts)
        k = seed % 4
        compiled = solve_compiled(scene, k=k, symmetric=False)
        explicit = solve_explicit(scene, k=k, symmetric=False)
        assert (compiled.units, compiled.states) == (explicit.units, explicit.states), (seed, k)
        kinds["infinite" if compiled.units is None else "finite"] += 1
        if compiled.units is not None and seed % 5 == 0:
            assert worst_case_of(scene, compiled, parse_ltlf(scene.task)) == compiled.units
            assert sum(s.cost for s in compiled.principal_play) == pytest.approx(compiled.cost_bound)
    assert kinds["finite"] >= 15 and kinds["infinite"] >= 10, kinds


@pytest.mark.parametrize("seed", range(30))
def test_interchangeable_objects(seed):
    """Canonical positions as game/symmetry.py orders them: the same count as
    the explicit solver's, the plain value, strategies in real objects."""
    scene = alike_scene(seed, contacts=seed % 2 == 0)
    plain = solve_explicit(scene, symmetric=False)
    reduced = solve_explicit(scene)
    compiled = solve_compiled(scene)
    assert (compiled.units, compiled.states) == (plain.units, reduced.states)
    if compiled.units is not None:
        assert worst_case_of(scene, compiled, parse_ltlf(scene.task)) == compiled.units


def test_too_many_atoms_is_an_input_error():
    motions = {("empty", "home", "l1/top"): 1}
    task = "F(" + " & ".join(f"(occupied(l1) | free(l2) | at(block, l{1 + i % 2}))" for i in range(9)) + ")"
    scene = make_scene({"a": "l1"}, ["l1", "l2"], motions, task=task)
    solve_compiled(scene)  # 3 atoms: fine
    atoms = " & ".join(f"at(o{i}, l1)" for i in range(17))
    scene = make_scene({f"o{i}": "Else" for i in range(17)}, ["l1"], motions, task=f"F({atoms})")
    with pytest.raises(InputError, match="at most 16 atoms"):
        solve_compiled(scene)
