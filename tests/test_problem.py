"""The application layer (`symsynth.problem`): a problem composed once,
solved by name and simulated, as the command line and comparison runs use
it."""

from __future__ import annotations

import json

import pytest

from support.paper import SCENES
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.game.strategy import read_strategy
from symsynth.logic import parser as parser_module
from symsynth.problem import CostmapRequest, load_problem, simulate, solve, with_costmap, with_strategy
from symsynth.scene import load_scene, write_costmap


def test_the_toy_problem_has_its_hand_solved_values():
    """scenes/toy.yaml's comments: E_p = 50 with its k = 1, 17 with k = 0."""
    problem = load_problem(SCENES / "toy.yaml")
    assert problem.task == problem.scene.task and problem.obtained is None
    assert {name: solve(problem, name).cost_bound for name in ("symbolic", "explicit", "forward")} == {
        "symbolic": 50, "explicit": 50, "forward": 50}
    assert solve(problem, k=0).cost_bound == solve(load_problem(SCENES / "toy.yaml", k=0)).cost_bound == 17


def test_a_task_is_checked_against_the_scene_with_its_source():
    with pytest.raises(InputError, match="--task: .*unknown"):
        load_problem(SCENES / "toy.yaml", task="F(at(purple, l1))")
    problem = load_problem(SCENES / "toy.yaml", task="F(at(black, l2))")
    assert solve(problem, k=0).cost_bound is not None


def test_an_unknown_solver_names_the_installed_ones():
    with pytest.raises(InputError, match="unknown solver 'simplex'; installed solvers: andor, auto, compiled, explicit, forward, symbolic"):
        solve(load_problem(SCENES / "toy.yaml"), "simplex")


# -- simulate(problem, ...) --------------------------------------------------------------

@pytest.fixture
def parsed(monkeypatch):
    """The texts the LTLf parser reads from now on (every parse_ltlf call
    goes through `parser._parser(...).parse`)."""
    texts = []
    real = parser_module._parser

    class Counting:
        def __init__(self, parser):
            self.parser = parser

        def parse(self, text):
            texts.append(text)
            return self.parser.parse(text)

    monkeypatch.setattr(parser_module, "_parser", lambda semantics: Counting(real(semantics)))
    return texts


@pytest.fixture(scope="module")
def line_file(paper_line, tmp_path_factory):
    """scenes/line.yaml next to its (small, recursive) costmap, as files."""
    folder = tmp_path_factory.mktemp("line")
    write_costmap(paper_line[1]["recursive"], folder / "line.costmap.json")
    text = (SCENES / "line.yaml").read_text(encoding="utf-8")
    (folder / "line.yaml").write_text(text + "\ncostmap: line.costmap.json\n", encoding="utf-8")
    return folder / "line.yaml"


def test_a_simulated_problem_parses_its_task_once(line_file, parsed):
    """The scene loader parses the task; making the problem, solving it,
    exploring the strategy for the adversary and simulating parse nothing
    more (before the application layer did: 3 parses of it)."""
    problem = load_problem(line_file)
    simulation = simulate(problem, "adversarial", seed=1)
    assert parsed == [problem.task]
    assert simulation.positions and simulation.guarantee and simulation.ok
    assert simulation.runs[0].completed and simulation.runs[0].cost <= simulation.bound + 1e-6


def test_a_simulated_problem_compiles_its_dfa_once(line_file, monkeypatch):
    """Solving with the explicit solver, exploring the strategy for the
    adversary and simulating read one DFA of the problem's task (before:
    one compilation each, 3 in all)."""
    from symsynth.automata import shared

    compiled = []
    real = shared.compile_ltlf
    monkeypatch.setattr(shared, "compile_ltlf", lambda formula: compiled.append(formula) or real(formula))
    problem = load_problem(line_file)
    simulation = simulate(problem, "adversarial", seed=1, solver="explicit")
    assert compiled == [problem.formula]
    assert simulation.positions and simulation.ok and simulation.runs[0].completed


def test_a_strategy_files_task_is_parsed_once(line_file, tmp_path, parsed):
    """With a strategy file, its task is parsed when its header is checked,
    and certifying it before the runs reads that formula (before: 3 parses
    of it, the scene's own task at load besides)."""
    strategy = tmp_path / "s.json"
    assert main(["solve", str(line_file), "--k", "1", "-o", str(strategy)]) == 0
    scene = load_scene(line_file)
    parsed.clear()
    problem = with_costmap(with_strategy(scene, strategy), CostmapRequest())
    simulation = simulate(problem, "random", seed=2)
    assert parsed == [problem.task] and problem.scene.k == 1
    assert simulation.positions == len(read_strategy(strategy).positions) and simulation.ok


def test_the_commands_runs_are_simulate_on_the_loaded_problem(line_file, capsys):
    """`symsynth simulate --json` reports the runs `simulate` makes on the
    problem `load_problem` composes from the same file (same seeds; all but
    the wall-clock seconds)."""
    assert main(["simulate", "--world", "kinematic", str(line_file), "--human", "random", "--runs", "2",
                 "--seed", "4", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    problem = load_problem(line_file)
    simulation = simulate(problem, "random", runs=2, seed=4, progress=False)
    assert shown["cost_bound"] == simulation.bound and shown["guarantee"] is simulation.guarantee is True
    clocks = ("seconds", "cpu_seconds")
    untimed = [{key: value for key, value in run.items() if key not in clocks} for run in shown["runs"]]
    assert untimed and untimed == [{key: value for key, value in r.to_json(problem.scene.object_names).items()
                                    if key not in clocks} for r in simulation.runs]


def test_simulate_refuses_what_it_cannot_run(line_file):
    with pytest.raises(InputError, match="abstract .* no world to simulate"):
        simulate(load_problem(SCENES / "toy.yaml"))
    with pytest.raises(InputError, match="unknown human 'alien'; installed humans: .*adversarial"):
        simulate(load_problem(line_file), "alien")
    stopped = simulate(load_problem(line_file), budget=1.0)
    assert not stopped.runs and not stopped.ok and stopped.stopped.startswith("No guarantee: E_p = ")
