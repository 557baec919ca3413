"""Work done once that was done again (issue 33, "repeated work found by
walking the data through"): each test counts the calls of the expensive
step over one command or one solve."""

from __future__ import annotations

import pytest

import symsynth.automata.compiler as compiler
import symsynth.automata.shared as shared
from support.paper import SCENES
from symsynth.cli import main
from symsynth.problem import load_problem, solve


@pytest.fixture
def compiles(monkeypatch) -> list:
    """Every DFA construction of a task (`compile_ltlf`'s work, wherever it is called from)."""
    made: list = []
    construct = compiler._compile

    def counted(formula, *options):
        made.append(formula)
        return construct(formula, *options)
    monkeypatch.setattr(compiler, "_compile", counted)
    shared._kept.clear()
    getattr(shared, "_ordered", {}).clear()
    return made


def test_solve_with_a_strategy_file_compiles_the_task_once(tmp_path, compiles):
    """`solve -o` parsed the task again for the strategy file and built its
    DFA a second time."""
    assert main(["solve", str(SCENES / "toy.yaml"), "--solver", "explicit", "-o", str(tmp_path / "s.json")]) == 0
    assert len(compiles) == 1


def test_the_symbolic_solver_compiles_the_task_once_over_the_horizons_it_tries(compiles):
    """k = 20 is solved by trying k = 8 and 16 first (`game.horizon`); each
    try built the DFA again in its own BDD manager."""
    problem = load_problem(SCENES / "toy.yaml")
    solution = solve(problem, "symbolic", k=20)
    assert len(compiles) == 1
    assert solution.units == solve(problem, "explicit", k=20).units


def test_the_costmap_options_are_one_declaration():
    """--method, --planner, the roadmap seed and --no-cache were declared in
    solve, costmap and simulate, with help that drifted apart and the seed
    spelled --seed in two and --costmap-seed in one."""
    from symsynth.cli import build_parser

    subcommands = {command: next(a for a in build_parser(command)._actions if a.dest == "command").choices[command]
                   for command in ("solve", "costmap", "simulate")}  # each parser in full

    def options(command):
        return {o: (a.dest, a.choices, a.default, a.help if o != "--planner" else None)
                for a in subcommands[command]._actions for o in a.option_strings
                if o in ("--method", "--planner", "--costmap-seed", "--no-cache")}
    assert options("solve") == options("costmap") == options("simulate")
    assert len(options("solve")) == 4
    # the older spelling still reads the roadmap seed where --seed means nothing else
    assert subcommands["solve"].parse_args(["x.yaml", "--seed", "3"]).costmap_seed == 3
    assert subcommands["simulate"].parse_args(["x.yaml", "--seed", "3"]).seed == 3
