"""The BDD strategy of `symsynth synth` (symsynth/synthesis/symbolic_strategy.py):
written to its file, read back into a fresh manager and played against
every environment behaviour on small specs (the plays judged by the
independent reference DFA), against random environments on specs too large
to list (judged by the trace semantics of symsynth.logic.semantics), and
compared with the listed machine, which picks the same outputs."""

from __future__ import annotations

import json
import random
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from support.reference import reference_dfa
from support.strategies import formulas
from symsynth.automata import compile_ltlf
from symsynth.cli import main
from symsynth.logic import parse_ltlf
from symsynth.logic.semantics import holds
from symsynth.synthesis import Partition, solve_realizability
from symsynth.synthesis.machine import strategy_machine
from symsynth.synthesis.preimage import Preimage
from symsynth.synthesis.symbolic_strategy import read_symbolic_strategy, symbolic_strategy, write_json

DATA = Path(__file__).parent / "data" / "finite-synthesis"
ATOMS = ("a", "b", "c")
partitions = st.lists(st.booleans(), min_size=3, max_size=3).map(
    lambda owners: Partition(tuple(a for a, o in zip(ATOMS, owners) if not o),
                             tuple(a for a, o in zip(ATOMS, owners) if o)))


def round_trip(strategy, tmp_path):
    path = tmp_path / "strategy.json"
    path.write_text(write_json(strategy))
    return read_symbolic_strategy(path)


def letters(names):
    return [{n: bool(bits >> i & 1) for i, n in enumerate(names)} for bits in range(2 ** len(names))]


@settings(max_examples=100, deadline=None)
@given(formula=formulas(max_depth=3), partition=partitions, agent_first=st.booleans(),
       relation=st.booleans())
def test_the_bdd_strategy_wins_against_every_environment(formula, partition, agent_first, relation,
                                                         tmp_path_factory):
    """Depth-first over every input sequence: each play is accepted by the
    reference DFA exactly when the strategy's state is accepting, and every
    play is won within the initial state's rank (the preimages by
    substitution, or by the transition relation one cluster per bit:
    symsynth/synthesis/preimage.py)."""
    dfa = compile_ltlf(formula)
    preimage = Preimage(dfa, limit=0, steps=0) if relation else Preimage(dfa, steps=10**18)
    game = solve_realizability(dfa, partition, agent_first=agent_first, preimage=preimage)
    if not game.realizable:
        return
    strategy = round_trip(symbolic_strategy(game), tmp_path_factory.mktemp("s"))
    reference = reference_dfa(formula)
    rank = strategy.rank(strategy.initial)
    assert rank is not None and rank <= len(game.rounds)
    stack = [(strategy.initial, [])]
    while stack:
        state, trace = stack.pop()
        assert len(trace) < rank, "a play longer than the initial state's rank"
        for x in letters(strategy.inputs):
            y = strategy.move(state, x)
            if agent_first:
                assert y == strategy.move(state, {a: not v for a, v in x.items()})  # it speaks before it hears
            letter = x | y
            after = strategy.step(state, letter)
            played = trace + [{a for a, v in letter.items() if v}]
            assert strategy.is_accepting(after) == reference.accepts(played)
            if not strategy.is_accepting(after):
                stack.append((after, played))


@settings(max_examples=60, deadline=None)
@given(formula=formulas(max_depth=3), partition=partitions, agent_first=st.booleans())
def test_the_bdd_strategy_picks_the_machines_outputs(formula, partition, agent_first):
    """Both pick, state by state, the least allowed output (module docs)."""
    game = solve_realizability(compile_ltlf(formula), partition, agent_first=agent_first)
    if not game.realizable:
        return
    strategy, machine = symbolic_strategy(game), strategy_machine(game)
    for state, moves in zip(machine.states, machine.moves):
        bits = dict(zip(strategy.bits, state))
        for move in moves:
            assert strategy.move(bits, move.input) == move.output


def copy_spec(n: int) -> tuple[str, Partition]:
    """The agent repeats each of n inputs one step later, and may stop (set
    e) from the third step on: realizable, 2^n memories; with the agent
    first it needs them, with the environment first too (y_i answers the
    previous step's x_i)."""
    text = " & ".join(f"G(x{i} -> WX(y{i}))" for i in range(n)) + " & F(e) & !e & WX(!e)"
    return text, Partition(tuple(f"x{i}" for i in range(n)), tuple(f"y{i}" for i in range(n)) + ("e",))


def part_text(partition: Partition) -> str:
    return f".inputs: {' '.join(partition.inputs)}\n.outputs: {' '.join(partition.outputs)}\n"


def random_plays(strategy, formula, rng: random.Random, plays: int) -> int:
    """Play against random environments; every play must end won, judged on
    the trace by the semantics.  Returns the longest play."""
    longest = 0
    for _ in range(plays):
        state, trace = strategy.initial, []
        while True:
            assert len(trace) < len(strategy.rounds), "no win within the rounds"
            x = {a: rng.random() < 0.5 for a in strategy.inputs}
            letter = x | strategy.move(state, x)
            trace.append({a for a, v in letter.items() if v})
            state = strategy.step(state, letter)
            if strategy.is_accepting(state):
                break
            assert not holds(formula, trace)
        assert holds(formula, trace)
        longest = max(longest, len(trace))
    return longest


@pytest.mark.parametrize("agent_first", [True, False])
def test_a_spec_too_large_to_list(tmp_path, capsys, agent_first):
    """13 inputs: `-o` writes the BDDs (the machine is refused), and random
    environments lose to them; the plays need the third step (e)."""
    text, partition = copy_spec(13)
    spec, part, out = tmp_path / "copy.ltlf", tmp_path / "copy.part", tmp_path / "s.json"
    spec.write_text(text)
    part.write_text(part_text(partition))
    argv = ["synth", str(spec), "--part", str(part), "-o", str(out)] + ([] if agent_first else ["--env-first"])
    assert main(argv) == 10
    assert "writing its BDDs" in capsys.readouterr().err
    assert json.loads(out.read_text())["format"] == "symsynth.strategy-bdd/1"
    strategy = read_symbolic_strategy(out)
    assert random_plays(strategy, parse_ltlf(text, next_semantics="weak"), random.Random(17), 100) == 3


def test_the_committed_counters(tmp_path):
    """The datasets' Double-Counter 02 (3 inputs, 9 outputs) as BDDs against random environments."""
    spec = DATA / "Double-Counter" / "counters_02.ltlf"
    out = tmp_path / "s.json"
    argv = ["synth", str(spec), "--part", str(spec.with_suffix(".part")), "-o", str(out), "--strategy", "bdd"]
    assert main(argv) == 10
    formula = parse_ltlf(spec.read_text(), next_semantics="weak")
    assert random_plays(read_symbolic_strategy(out), formula, random.Random(5), 100) >= 2


def test_machine_refused_when_asked_for(tmp_path, capsys):
    text, partition = copy_spec(13)
    (tmp_path / "s.ltlf").write_text(text)
    (tmp_path / "s.part").write_text(part_text(partition))
    argv = ["synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "s.part"), "-o", str(tmp_path / "s.json"),
            "--strategy", "machine"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "13 inputs" in err and "--strategy bdd" in err and "Traceback" not in err


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(format="other"), "key 'format': expected 'symsynth.strategy-bdd/1'"),
    (lambda d: d["nodes"].append(["nowhere", 0, 1]), "key 'nodes["),
    (lambda d: d["roots"].pop("output"), "key 'roots.output': expected a dict"),
    (lambda d: d["roots"]["delta"].update({"q": 10 ** 6}), "key 'roots.delta.q': expected a node reference"),
])
def test_bad_strategy_files(tmp_path, change, message):
    text, partition = copy_spec(2)
    data = symbolic_strategy(solve_realizability(compile_ltlf(parse_ltlf(text, next_semantics="weak")),
                                                 partition)).to_json()
    change(data)
    path = tmp_path / "s.json"
    path.write_text(json.dumps(data))
    with pytest.raises(Exception) as caught:
        read_symbolic_strategy(path)
    assert type(caught.value).__name__ == "InputError" and message in str(caught.value)
