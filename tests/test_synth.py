"""`symsynth synth`: LTLf realizability against a brute-force game on an
independent explicit DFA (tests/support/reference.py), winning strategies played
against every environment, the datasets' sample with verdicts worked out
from the families' definitions, and bad input."""

from __future__ import annotations

import csv
import itertools
import json
import re
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import reference_dfa
from support.strategies import formulas
from symsynth.automata import compile_ltlf
from symsynth.automata.bdd import cofactor, lexmin
from symsynth.cli import main
from symsynth.logic import ast, parse_ltlf
from symsynth.synthesis import Partition, read_partition, solve_realizability
from symsynth.synthesis.machine import strategy_machine

DATA = Path(__file__).parent / "data" / "finite-synthesis"
ATOMS = ("a", "b", "c")


def brute_force(formula: ast.Formula, partition: Partition, agent_first: bool) -> bool:
    """The reachability game on the reference DFA, state by state: W grows
    by the states where the agent's choice (and the environment's every
    answer, in the order of the step) lands in Acc or W."""
    dfa = reference_dfa(formula)
    xs = [a for a in dfa.atoms if a in partition.inputs]
    ys = [a for a in dfa.atoms if a in partition.outputs]

    def subsets(names):
        return [frozenset(c) for r in range(len(names) + 1) for c in itertools.combinations(names, r)]
    win: set[int] = set()
    while True:
        good = dfa.accepting | win

        def lands(q, x, y):
            return dfa.step(q, x | y) in good
        if agent_first:
            new = {q for q in range(dfa.num_states)
                   if any(all(lands(q, x, y) for x in subsets(xs)) for y in subsets(ys))}
        else:
            new = {q for q in range(dfa.num_states)
                   if all(any(lands(q, x, y) for y in subsets(ys)) for x in subsets(xs))}
        if new <= win:
            return dfa.initial in win
        win |= new


partitions = st.lists(st.booleans(), min_size=3, max_size=3).map(
    lambda owners: Partition(tuple(a for a, o in zip(ATOMS, owners) if not o),
                             tuple(a for a, o in zip(ATOMS, owners) if o)))


@settings(max_examples=150, deadline=None)
@given(formula=formulas(max_depth=3), partition=partitions, agent_first=st.booleans())
def test_verdict_equals_the_brute_force_game(formula, partition, agent_first):
    game = solve_realizability(compile_ltlf(formula), partition, agent_first=agent_first)
    assert game.realizable == brute_force(formula, partition, agent_first)


@settings(max_examples=100, deadline=None)
@given(formula=formulas(max_depth=3), partition=partitions, agent_first=st.booleans())
def test_the_strategy_wins_against_every_environment(formula, partition, agent_first):
    """Every path of the machine ends in a win within the number of rounds,
    and the trace it reads is accepted by the reference DFA."""
    game = solve_realizability(compile_ltlf(formula), partition, agent_first=agent_first)
    if not game.realizable:
        return
    machine = strategy_machine(game)
    reference = reference_dfa(formula)
    stack = [(0, [])]
    while stack:
        state, trace = stack.pop()
        assert len(trace) < len(game.rounds) + 1, "a play longer than the initial state's rank"
        outputs = {json.dumps(m.output, sort_keys=True) for m in machine.moves[state]}
        if agent_first:
            assert len(outputs) == 1  # it speaks before it hears
        for move in machine.moves[state]:
            letter = {a for a, v in (move.input | move.output).items() if v}
            if move.next == "win":
                assert reference.accepts(trace + [letter])
            else:
                assert not reference.accepts(trace + [letter])
                stack.append((move.next, trace + [letter]))


def test_the_sample_families_are_varied():
    """Both verdicts occur in the hypothesis domain (not vacuous)."""
    a, b = ast.Atom("a"), ast.Atom("b")
    env_a = Partition(("a",), ("b",))
    assert solve_realizability(compile_ltlf(ast.Eventually(b)), env_a).realizable
    assert not solve_realizability(compile_ltlf(ast.Eventually(a)), env_a).realizable
    # who moves first matters: the agent must copy the environment's a into b
    same = ast.Equiv(a, b)
    assert not solve_realizability(compile_ltlf(same), env_a, agent_first=True).realizable
    assert solve_realizability(compile_ltlf(same), env_a, agent_first=False).realizable


def expected(path: Path) -> bool:
    """The verdicts of tests/data/finite-synthesis/README.md."""
    part = path.with_suffix(".part").read_text()
    inputs = re.search(r"\.inputs:(.*)", part)[1].split()
    name = path.stem
    if name.startswith("uright"):
        return f"p{int(name[-2:])}" not in inputs
    if name.startswith("gfand"):
        return not inputs
    return True  # the counters


SAMPLE = sorted(DATA.rglob("*.ltlf"))


@pytest.mark.parametrize("path", SAMPLE, ids=[p.stem for p in SAMPLE])
def test_the_datasets_sample(path, capsys):
    code = main(["synth", str(path), "--part", str(path.with_suffix(".part"))])
    out = capsys.readouterr().out
    want = expected(path)
    assert (code, out.splitlines()[0]) == ((10, "REALIZABLE") if want else (20, "UNREALIZABLE"))


def test_the_sample_has_both_verdicts():
    verdicts = [expected(p) for p in SAMPLE]
    assert len(SAMPLE) == 20 and 3 <= sum(verdicts) <= 17


def test_strategy_files(tmp_path, capsys):
    spec = DATA / "Patterns" / "Uright" / "uright04.ltlf"
    for suffix in (".json", ".dot"):
        out = tmp_path / f"s{suffix}"
        assert main(["synth", str(spec), "--part", str(spec.with_suffix(".part")), "-o", str(out)]) == 10
        text = out.read_text()
        assert ("digraph strategy" in text) if suffix == ".dot" else json.loads(text)["agent_first"] is True


def bad(capsys, argv, message):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("part, message", [
    (".inputs: a\n.outputs: a b\n", "s.part:2: a in both .inputs and .outputs (.outputs here, .inputs at line 1)"),
    (".outputs: b a\n\n.inputs: a\n", "s.part:3: a in both .inputs and .outputs (.inputs here, .outputs at line 1)"),
    (".inputs a b\n", "expected '.inputs: NAMES' or '.outputs: NAMES'"),
    (".inputs: a\n.inputs: b\n", ".inputs is given twice (first at line 1)"),
    ("", "empty: expected '.inputs:' and '.outputs:' lines"),
    (".inputs: a\n.outputs: c\n", "s.ltlf:1:7: b is in the formula but in neither list of"),
    ("# nothing\n\n", "empty: expected '.inputs:' and '.outputs:' lines"),
    (".inputs: a\n.outputs b\n", "s.part:2: expected '.inputs: NAMES' or '.outputs: NAMES', found '.outputs b'"),
    (b"\xff\xfe.inputs: a", "s.part is not UTF-8 text"),
    (".inputs: a 1x\n", "'1x' is not a variable name"),
])
def test_bad_partitions(tmp_path, capsys, part, message):
    (tmp_path / "s.ltlf").write_text("F(a & b)")
    if isinstance(part, bytes):
        (tmp_path / "s.part").write_bytes(part)
    else:
        (tmp_path / "s.part").write_text(part)
    bad(capsys, ["synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "s.part")], message)


def test_bad_formulas_and_files(tmp_path, capsys):
    (tmp_path / "s.part").write_text(".inputs: a\n.outputs: b\n")
    (tmp_path / "empty.ltlf").write_text("")
    bad(capsys, ["synth", str(tmp_path / "empty.ltlf"), "--part", str(tmp_path / "s.part")], "empty formula")
    bad(capsys, ["synth", str(tmp_path / "none.ltlf"), "--part", str(tmp_path / "s.part")], "cannot read")
    (tmp_path / "comment.ltlf").write_text("# a goal to come\n\n")
    bad(capsys, ["synth", str(tmp_path / "comment.ltlf"), "--part", str(tmp_path / "s.part")], "empty formula")
    (tmp_path / "s.ltlf").write_text("F(b)")
    bad(capsys, ["synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "none.part")],
        "cannot read partition file")
    bad(capsys, ["synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "s.part"), "-o", "x.txt"],
        "expected a file name ending in .json or .dot")
    bad(capsys, ["synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "s.part"), "-o", "x.dot",
                 "--strategy", "bdd"], "the BDDs are written as JSON")
    (tmp_path / "never.ltlf").write_text("F(a)")
    code = main(["synth", str(tmp_path / "never.ltlf"), "--part", str(tmp_path / "s.part"), "-o",
                 str(tmp_path / "x.json")])
    out, err = capsys.readouterr()
    assert code == 20 and out == "UNREALIZABLE\n"  # the verdict's code, as without -o
    assert "unrealizable, there is no winning strategy to write" in err and "Traceback" not in err
    assert not (tmp_path / "x.json").exists()


def test_the_sample_agrees_with_the_published_verdicts():
    """Two independent sources: the verdicts worked out from the families'
    definitions (README) and those of Nike's and LydiaSyft's integration tests
    (tests/data/synth-verdicts)."""
    published = {}
    with open(DATA.parent / "synth-verdicts" / "verdicts.csv") as file:
        for row in csv.DictReader(file):
            published[row["instance"].split("/")[-1]] = row["expected"]
    assert [published[p.name] for p in SAMPLE] == ["realizable" if expected(p) else "unrealizable" for p in SAMPLE]


@pytest.mark.parametrize("agent_first", [True, False])
def test_the_machine_follows_the_dfa_letter_by_letter(agent_first):
    """Double-Counter 02 (3 inputs, 9 outputs; machine.py lists the
    successors of all letters at once): each move's output is the least
    one (lexmin) leading one round closer to winning, and its next state is
    the DFA's step on the letter, evaluated one letter at a time."""
    spec = DATA / "Double-Counter" / "counters_02.ltlf"
    dfa = compile_ltlf(parse_ltlf(spec.read_text(), next_semantics="weak"))
    game = solve_realizability(dfa, read_partition(spec.with_suffix(".part")), agent_first=agent_first)
    machine = strategy_machine(game)
    bdd = dfa.bdd
    for state, moves in zip(machine.states, machine.moves):
        assert len(moves) == 2 ** len(game.inputs)
        choices = game.choices(game.rank(dfa.state_cube(state)), dict(zip(dfa.bits, state)))
        for move in moves:
            allowed = bdd.forall(set(game.inputs), choices) if agent_first else cofactor(bdd, move.input, choices)
            assert tuple(move.output.values()) == lexmin(bdd, allowed, game.outputs)
            after = dfa.step(state, {a for a, v in (move.input | move.output).items() if v})
            assert move.next == ("win" if dfa.is_accepting(after) else machine.states.index(after))
    assert len(machine.states) > 3


def test_the_progress_callback_counts_the_rounds():
    """`X X a` with the agent owning `a`: the agent wins within three
    letters and no fewer from the start (its rank is 3).  The callback
    (synth's progress bar) is told each round's count, and once more
    when the last round finds nothing new.  (W may grow a round past the
    start's rank: codes of no state, unreachable, lead to the start.)"""
    dfa = compile_ltlf(parse_ltlf("X X a"))  # (strong next: three letters)
    done: list[int] = []
    game = solve_realizability(dfa, Partition((), ("a",)), progress=done.append)
    assert game.realizable
    assert game.rank(dfa.state_cube(dfa.initial_assignment)) == 3
    assert done == list(range(1, len(game.rounds) + 1)) + [len(game.rounds)]
