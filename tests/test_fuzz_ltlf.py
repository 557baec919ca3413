"""The fuzzer's findings on `symsynth dfa` and `symsynth synth` (issue 33),
each a test now that it is fixed, and the batch mode of `symsynth dfa`
(issue 31).  Every refusal is one message, exit 2, no traceback, and
names the file."""

from __future__ import annotations

import json
import os
import threading

import pytest
from hypothesis import HealthCheck, given, settings

from support.reference import minimal_num_states
from support.strategies import formulas
from symsynth.cli import main
from symsynth.logic import parse_ltlf, to_string


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(capsys, argv, *expected):
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert "Traceback" not in err
    for text in expected:
        assert text in err, err


@pytest.fixture
def fifo(tmp_path):
    """A named pipe no one writes to: `open` blocks on it until a writer
    comes.  A thread opens it for writing after 20 s, so that a command
    that hangs in `open` fails the test instead of hanging it."""
    path = tmp_path / "pipe"
    os.mkfifo(path)
    done = threading.Event()

    def unblock():
        if not done.wait(20):
            with open(path, "w"):
                pass
    thread = threading.Thread(target=unblock, daemon=True)
    thread.start()
    yield path
    done.set()


def test_dfa_refuses_a_named_pipe(capsys, fifo):
    refused(capsys, ["dfa", "-f", fifo], f"formula file {fifo} is not a regular file")


def test_synth_refuses_a_named_pipe_as_partition_and_as_formula(capsys, fifo, tmp_path):
    (tmp_path / "s.ltlf").write_text("F b")
    (tmp_path / "s.part").write_text(".inputs: a\n.outputs: b\n")
    refused(capsys, ["synth", tmp_path / "s.ltlf", "--part", fifo], f"partition file {fifo} is not a regular file")
    refused(capsys, ["synth", fifo, "--part", tmp_path / "s.part"], f"formula file {fifo} is not a regular file")


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_dfa_refuses_a_device_without_reading_it(capsys, device):
    refused(capsys, ["dfa", "-f", device], f"formula file {device} is not a regular file")


def test_a_formula_file_past_the_byte_limit_is_refused_unread(capsys, tmp_path):
    path = tmp_path / "big.ltlf"
    text = " & ".join(f"F p{i}" for i in range(300))
    path.write_text(text)
    refused(capsys, ["dfa", "-f", path, "--max-bytes", "1000"],
            f"formula file {path} is {len(text):,} bytes: larger than the 1,000 symsynth reads", "--max-bytes")
    code, out, _ = run(capsys, "dfa", "-f", path, "--max-bytes", "0")  # no limit
    assert code == 0 and "atoms      300" in out


def nexts(n: int) -> str:
    """F(a & X X ... X b): its minimal DFA remembers the last n letters'
    a: 2^n + 1 states, all of them listed by the construction."""
    return "F(a & " + "X " * n + "b)"


def test_the_state_limit_refuses_a_formula_whose_automaton_explodes(capsys):
    # 2^12 + 1 = 4,097 states: past a limit of 4,000, within one of 4,097
    refused(capsys, ["dfa", "--max-states", "4000", nexts(12)], "passed 4,000 states", "--max-states")
    code, out, _ = run(capsys, "dfa", "--max-states", "4097", nexts(12))
    assert code == 0 and "states     4097 (minimal" in out


def test_the_state_limit_applies_to_synth_and_names_the_file(capsys, tmp_path):
    (tmp_path / "s.ltlf").write_text(nexts(10))
    (tmp_path / "s.part").write_text(".inputs: a\n.outputs: b\n")
    refused(capsys, ["synth", tmp_path / "s.ltlf", "--part", tmp_path / "s.part", "--max-states", "500"],
            f"{tmp_path / 's.ltlf'}: an automaton built for the formula passed 500 states")


def test_synth_names_the_formula_file_when_it_has_too_many_atoms(capsys, tmp_path):
    n = 501  # 1,002 atoms, past the 1,000 the compiler takes
    (tmp_path / "many.ltlf").write_text(" & ".join(f"G(p{i} -> F q{i})" for i in range(n)))
    (tmp_path / "many.part").write_text(".inputs: " + " ".join(f"p{i}" for i in range(n)) +
                                        "\n.outputs: " + " ".join(f"q{i}" for i in range(n)) + "\n")
    refused(capsys, ["synth", tmp_path / "many.ltlf", "--part", tmp_path / "many.part"],
            f"{tmp_path / 'many.ltlf'}: the formula has 1002 atoms")


def test_synth_o_on_an_unrealizable_spec_exits_with_the_verdict(capsys, tmp_path):
    (tmp_path / "s.ltlf").write_text("G(a -> X[!] b) & F a")  # the environment never sets a: b is never owed,
    (tmp_path / "s.part").write_text(".inputs: a\n.outputs: b\n")  # but F a is the environment's to grant
    code, out, err = run(capsys, "synth", tmp_path / "s.ltlf", "--part", tmp_path / "s.part",
                         "-o", tmp_path / "x.json")
    assert (code, out) == (20, "UNREALIZABLE\n")
    assert "no winning strategy" in err and not (tmp_path / "x.json").exists()


# -------------------------------------------------------------- batch mode


@settings(max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(batch=formulas(max_depth=3).map(to_string).flatmap(
    lambda first: formulas(max_depth=3).map(lambda second: [first, second])))
def test_batch_lines_give_each_formulas_minimal_dfa(tmp_path_factory, capsys, batch):
    """One JSON line per formula line, in order, each with the state count of
    the formula's minimal DFA computed by the reference construction."""
    texts = [batch[0], to_string(batch[1])]
    path = tmp_path_factory.mktemp("batch") / "formulas.txt"
    path.write_text(f"# two formulas\n{texts[0]}\n\n{texts[1]}  # the second\n")
    code, out, err = run(capsys, "dfa", "--lines", path, "--next", "strong")
    assert code == 0 and err == ""
    lines = [json.loads(line) for line in out.splitlines()]
    assert [r["line"] for r in lines] == [2, 4]
    for result, text in zip(lines, texts):
        assert result["states"] == minimal_num_states(parse_ltlf(text))


def test_batch_files_report_each_refusal_and_go_on(capsys, tmp_path):
    (tmp_path / "ok.ltlf").write_text("G(a -> F b)")
    (tmp_path / "bad.ltlf").write_text("G(a -> Fb)")
    code, out, _ = run(capsys, "dfa", "-f", tmp_path / "ok.ltlf", tmp_path / "bad.ltlf", tmp_path / "none.ltlf",
                       "/dev/zero", tmp_path / "ok.ltlf", "--json")
    assert code == 2
    lines = [json.loads(line) for line in out.splitlines()]
    assert [r["source"] for r in lines] == [str(tmp_path / n) for n in ("ok.ltlf", "bad.ltlf", "none.ltlf")] + \
        ["/dev/zero", str(tmp_path / "ok.ltlf")]
    assert lines[0]["states"] == lines[4]["states"] == 3 and lines[0]["dfa"]["initial"] == 0
    assert "did you mean 'F b'?" in lines[1]["error"] and lines[1]["error"].startswith(f"{tmp_path / 'bad.ltlf'}:1:8:")
    assert "cannot read formula file" in lines[2]["error"]
    assert "not a regular file" in lines[3]["error"]
