"""Boolean substitution without CUDD's `Cudd_Cofactor`.

dd.cudd's `let` with Boolean values is `Cudd_Cofactor`, which on long runs
leaves CUDD's count of dead nodes wrong and the process then aborts at a
garbage collection (found on Random/Syft's syft_2/001 through `symsynth dfa
--json`; docs/ltlf.md, "A CUDD abort").  symsynth substitutes Booleans with
`bdd.cofactor` instead, and prints guards with cofactors read off the nodes.

- `cofactor` and `isop` against truth tables worked out by brute force.
- A manager whose `_cofactor` (dd.cudd's one route to `Cudd_Cofactor`)
  raises: compiling, printing, minimizing, synthesizing with a strategy,
  and solving and certifying a game never reach it.
"""

from __future__ import annotations

import itertools
import random
from pathlib import Path

import pytest
from dd import cudd

from symsynth.automata import compile_ltlf
from symsynth.automata.bdd import cofactor, isop, new_manager
from symsynth.cli import main

NAMES = ("a", "b", "c", "d", "e")
SCENES = Path(__file__).resolve().parents[1] / "scenes"


def table_function(bdd, table):
    """The BDD true exactly on the rows of `table` (a set of 0/1 tuples)."""
    u = bdd.false
    for row in table:
        cube = bdd.true
        for name, bit in zip(NAMES, row):
            cube &= bdd.var(name) if bit else ~bdd.var(name)
        u |= cube
    return u


def evaluate(bdd, u, row):
    for name, bit in zip(NAMES, row):
        u = (u & bdd.var(name) if bit else u & ~bdd.var(name))
    return u != bdd.false


@pytest.mark.parametrize("seed", range(20))
def test_cofactor_fixes_the_given_variables(seed):
    rng = random.Random(seed)
    bdd = new_manager()
    bdd.declare(*NAMES)
    rows = list(itertools.product((0, 1), repeat=len(NAMES)))
    table = {row for row in rows if rng.random() < 0.5}
    u = table_function(bdd, table)
    fixed = {name: rng.random() < 0.5 for name in rng.sample(NAMES, rng.randint(0, 3))}
    result = cofactor(bdd, fixed, u)
    assert not set(bdd.support(result)) & set(fixed)
    for row in rows:
        moved = tuple(int(fixed[n]) if n in fixed else bit for n, bit in zip(NAMES, row))
        assert evaluate(bdd, result, row) == (moved in table), (fixed, row)


@pytest.mark.parametrize("seed", range(20))
def test_isop_covers_exactly_and_irredundantly(seed):
    rng = random.Random(100 + seed)
    bdd = new_manager()
    bdd.declare(*NAMES)
    rows = list(itertools.product((0, 1), repeat=len(NAMES)))
    table = {row for row in rows if rng.random() < 0.4}
    u = table_function(bdd, table)
    cubes = isop(bdd, u)

    def covered(row, cube):
        values = dict(zip(NAMES, row))
        return all(values[var] == int(value) for var, value in cube)

    for row in rows:
        assert any(covered(row, c) for c in cubes) == (row in table), row
    for i, cube in enumerate(cubes):  # no cube can be dropped
        others = cubes[:i] + cubes[i + 1:]
        assert any(covered(row, cube) and not any(covered(row, c) for c in others) for row in table)
        for j in range(len(cube)):  # no literal can be dropped
            wider = cube[:j] + cube[j + 1:]
            assert any(covered(row, wider) and row not in table for row in rows)


class NoCofactor(cudd.BDD):
    def _cofactor(self, f, values):
        raise AssertionError(f"Cudd_Cofactor reached with {values}")


@pytest.fixture
def no_cofactor(monkeypatch):
    monkeypatch.setattr(cudd, "BDD", NoCofactor)
    bdd = new_manager()
    bdd.declare("x")
    with pytest.raises(AssertionError, match="Cudd_Cofactor reached"):  # the guard is in place
        bdd.let({"x": True}, bdd.var("x"))


def test_the_dfa_and_its_printing_never_call_cudd_cofactor(no_cofactor, tmp_path, capsys):
    spec = tmp_path / "spec.ltlf"
    spec.write_text("G (a -> X (b | c)) & F (c & !a) & (a U (b | F d))")
    assert main(["dfa", "-f", str(spec), "--json"]) == 0
    dfa = compile_ltlf(spec.read_text())
    explicit = dfa.to_explicit()
    assert explicit.num_states == dfa.minimize().to_explicit().num_states
    assert dfa.accepts([{"b", "c"}]) and not dfa.accepts([{"a"}])


@pytest.mark.parametrize("agent_first", [True, False])
def test_synthesis_and_its_strategies_never_call_cudd_cofactor(no_cofactor, tmp_path, agent_first):
    spec = tmp_path / "spec.ltlf"
    spec.write_text("G (req -> X grant) & F done")
    spec.with_suffix(".part").write_text(".inputs: req\n.outputs: grant done\n")
    flag = "--agent-first" if agent_first else "--env-first"
    for out in ("strategy.json", "strategy.dot"):
        assert main(["synth", str(spec), "--part", str(spec.with_suffix(".part")), flag,
                     "-o", str(tmp_path / out)]) == 10


def test_the_symbolic_game_solver_never_calls_cudd_cofactor(no_cofactor, capsys):
    """Solving, reading the strategy's moves back and certifying it."""
    assert main(["solve", str(SCENES / "toy.yaml"), "--solver", "symbolic", "--k", "1"]) == 0
    assert "E_p" in capsys.readouterr().out
