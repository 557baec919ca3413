"""Formulas nested deep or long: an answer or a clear error, never a
traceback (issue 16, row 5: 500 nested operators or 500 conjuncts were a
RecursionError through `dfa`, `solve --task` and a scene's `task:`).

The parser builds the formula as it parses (no recursion), long `&` and
`|` chains become balanced trees, and a formula nested deeper than
`parser.MAX_DEPTH` is refused with its depth."""

from __future__ import annotations

import json

import pytest
import yaml

from support.paper import SCENES
from support.reference import minimal_num_states
from symsynth.automata import compile_ltlf
from symsynth.cli import main
from symsynth.solvers import SOLVERS
from symsynth.logic import ast, parse_ltlf
from symsynth.logic.parser import MAX_DEPTH
from symsynth.logic.semantics import holds
from symsynth.scene import load_scene


def refused(capsys, argv, *expected):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    for text in expected:
        assert text in err, err


@pytest.mark.parametrize("make", [
    lambda n: "X " * n + "a",
    lambda n: "!" * n + "a",
    lambda n: "F " * n + "a",
    lambda n: "G(" * n + "a" + ")" * n,
    lambda n: " U (".join(f"p{i}" for i in range(n)) + ")" * (n - 1),
    lambda n: " -> ".join(f"p{i}" for i in range(n)),
])
@pytest.mark.parametrize("n", [500, 100_000])
def test_too_deep_is_refused_with_its_depth(tmp_path, capsys, make, n):
    path = tmp_path / "f.ltlf"
    path.write_text(make(n))
    refused(capsys, ["dfa", "-f", str(path)], "nests", f"symsynth reads at most {MAX_DEPTH}")


def test_deep_parentheses_are_read(tmp_path, capsys):
    """Parentheses add no operator: 100,000 of them around an atom is the atom."""
    path = tmp_path / "f.ltlf"
    path.write_text("(" * 100_000 + "a" + ")" * 100_000)
    assert main(["dfa", "-f", str(path)]) == 0
    assert "states     3 (minimal, complete)" in capsys.readouterr().out


def test_at_the_limit_the_answer_is_right():
    """X^(d-1) a at the depth limit: a DFA of d + 2 states (count letters to
    d, then accept iff a held there; a sink for each outcome), by the
    reference construction too."""
    n = MAX_DEPTH - 1
    formula = parse_ltlf("X " * n + "a")
    assert ast.depth(formula) == MAX_DEPTH
    dfa = compile_ltlf(formula)
    assert dfa.num_states == n + 3 == minimal_num_states(formula)
    trace = [set()] * n + [{"a"}]
    assert dfa.accepts(trace) and holds(formula, trace) and not dfa.accepts(trace[:-1])


@pytest.mark.parametrize("n", [500, 10_000])
def test_many_conjuncts_are_balanced_and_solved(tmp_path, capsys, n):
    """n conjuncts over two patterns: the same DFA as the two alone."""
    text = " & ".join(["F(p)", "G(!q)"] * (n // 2))
    formula = parse_ltlf(text)
    assert ast.depth(formula) <= 20
    assert compile_ltlf(formula).num_states == compile_ltlf("F(p) & G(!q)").num_states == 3
    path = tmp_path / "f.ltlf"
    path.write_text(" | ".join(["X X p"] * n))
    assert main(["dfa", "-f", str(path)]) == 0
    assert f"states     {compile_ltlf('X X p').num_states} (minimal, complete)" in capsys.readouterr().out


def test_short_chains_keep_their_shape():
    """Up to 32 operands `&` leans left as the grammar reads it (printed
    formulas and existing strategy files compare equal)."""
    a, b, c = (ast.Atom(x) for x in "abc")
    assert parse_ltlf("a & b & c") == ast.And(ast.And(a, b), c)
    assert parse_ltlf("a & (b & c)") == ast.And(a, ast.And(b, c))
    assert parse_ltlf("(a | b) & c") == ast.And(ast.Or(a, b), c)


@pytest.mark.parametrize("task", [
    " & ".join(["F(at(black, l3))", "G(!at(white, l1))"] * 5_000),
    "X " * 500 + "at(black, l3)",
])
def test_through_solve_and_a_scene(tmp_path, capsys, task):
    data = yaml.safe_load((SCENES / "toy.yaml").read_text())
    data["task"] = task
    data["costmap"] = str(SCENES / "toy.costmap.json")
    path = tmp_path / "toy.yaml"
    path.write_text(yaml.safe_dump(data))
    code = main(["solve", str(path), "--json"])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if task.startswith("X"):
        assert code == 2 and "nests 501 operators deep" in err
    else:  # the same game as the two conjuncts once
        assert code == 0
        scene = load_scene(SCENES / "toy.yaml")
        once = SOLVERS["explicit"](scene, "F(at(black, l3)) & G(!at(white, l1))")
        assert json.loads(out)["cost_bound"] == once.cost_bound


def test_too_many_atoms_is_refused(tmp_path, capsys):
    path = tmp_path / "f.ltlf"
    path.write_text(" & ".join(f"F(p{i})" for i in range(2000)))
    refused(capsys, ["dfa", "-f", str(path)], "the formula has 2000 atoms; symsynth compiles formulas of at most 1000")
