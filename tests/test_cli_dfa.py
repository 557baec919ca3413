"""`symsynth dfa` through `symsynth.cli.main`, with captured output."""

from __future__ import annotations

import json
import re

import pytest
from hypothesis import given, settings

from support.reference import (JsonDFA, all_traces, distinguishing_trace, minimal_num_states, minimize,
                               reference_dfa)
from support.strategies import formulas
from symsynth.automata import compile_ltlf
from symsynth.cli import main
from symsynth.logic import atoms, holds, parse_ltlf, to_string


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def check_json_language(data, formula, max_length=4):
    """The printed JSON, simulated through its guards, accepts exactly the models."""
    simulated = JsonDFA(data)
    keys = {x.key for x in atoms(formula)}
    assert set(data["atoms"]) == keys
    for trace in all_traces(keys, max_length):
        assert simulated.accepts(trace) == holds(formula, trace), trace
    assert distinguishing_trace(simulated, reference_dfa(formula), keys) is None
    assert len(simulated.states) == minimal_num_states(formula)


def test_summary_reports_states_nodes_and_seconds(capsys):
    code, out, err = run(capsys, "dfa", "G(a -> F b)")
    assert code == 0
    assert err == ""
    assert re.search(r"states\D*\b3\b", out, re.I)   # initial, satisfied, pending
    assert re.search(r"nodes", out, re.I)
    assert re.search(r"seconds", out, re.I)


def test_summary_of_the_response_family(capsys):
    formula = " & ".join(f"G(a{i} -> F b{i})" for i in range(3))
    code, out, _ = run(capsys, "dfa", formula)
    assert code == 0
    assert re.search(r"states\D*\b9\b", out, re.I)   # 2^3 + 1


def test_a_backward_summary_describes_the_diagram_and_makes_no_bits(capsys, monkeypatch, tmp_path):
    """The backward construction's DFA is its numbered diagram; the summary
    and a batch line give its nodes over the atoms and make no transition
    bits (they would fail here).  a U b, counted by hand (atoms a above b):
    the pending state reads a, then b on each side (b: the accepting sink;
    else pending under a, the rejecting sink without): 3 nodes; the sinks'
    moves are their leaves."""
    import symsynth.automata.symbolic as symbolic

    def refused(*args):
        raise AssertionError("the transition bits were made")

    monkeypatch.setattr(symbolic, "bit_functions", refused)
    code, out, err = run(capsys, "dfa", "--construction", "backward", "a U b")
    assert code == 0 and err == ""
    assert re.search(r"^states +3 ", out, re.M) and re.search(r"^diagram +3 nodes over the atoms", out, re.M)
    assert "bdd nodes" not in out and re.search(r"^state bits +2$", out, re.M)
    spec = tmp_path / "formulas.txt"
    spec.write_text("a U b\n")
    code, out, _ = run(capsys, "dfa", "--construction", "backward", "--lines", str(spec))
    line = json.loads(out)
    assert code == 0 and line["states"] == 3 and line["diagram_nodes"] == 3 and "bdd_nodes" not in line


def test_a_backward_dfa_listed_reports_its_bdd_nodes_as_before(capsys, tmp_path):
    """--json needs the transition bits: a batch line then gives the BDD's
    nodes as before (those of the functions, made on first use), not the
    diagram's."""
    formula = "a U (b R c)"
    spec = tmp_path / "formulas.txt"
    spec.write_text(formula + "\n")
    code, out, _ = run(capsys, "dfa", "--construction", "backward", "--json", "--lines", str(spec))
    line = json.loads(out)
    dfa = compile_ltlf(formula, next_semantics="weak", construction="backward")
    assert not dfa.delta_made
    assert code == 0 and "diagram_nodes" not in line and line["bdd_nodes"] == dfa.num_nodes
    assert dfa.delta_made
    check_json_language(line["dfa"], parse_ltlf(formula))


def test_json_is_parsed_and_simulated(capsys):
    code, out, err = run(capsys, "dfa", "--json", "G(a -> F b) & F(c & last)")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert data["initial"] not in data["accepting"]
    check_json_language(data, parse_ltlf("G(a -> F b) & F(c & last)"))


def test_json_with_predicate_atoms(capsys):
    text = "F(at(black, top)) & G(occupied(l3) -> at(white, l1))"
    code, out, _ = run(capsys, "dfa", "--json", text)
    assert code == 0
    data = json.loads(out)
    assert set(data["atoms"]) == {"at(black, top)", "occupied(l3)", "at(white, l1)"}
    check_json_language(data, parse_ltlf(text), max_length=3)


def test_dot_file_is_written(capsys, tmp_path):
    target = tmp_path / "dfa.dot"
    code, out, _ = run(capsys, "dfa", "--dot", str(target), "F a & F b")
    assert code == 0
    dot = target.read_text(encoding="utf-8")
    assert "digraph" in dot
    assert dot.count("doublecircle") >= 1            # {a, b} seen is accepting
    # the same DFA as JSON: one DOT edge per transition, plus the entry arrow
    _, out, _ = run(capsys, "dfa", "--json", "F a & F b")
    data = json.loads(out)
    edges = [line for line in dot.splitlines() if "->" in line]
    assert len(edges) == len(data["transitions"]) + 1


def test_dot_and_json_together(capsys, tmp_path):
    target = tmp_path / "x.dot"
    code, out, _ = run(capsys, "dfa", "--json", "--dot", str(target), "X[!] true")
    assert code == 0
    check_json_language(json.loads(out), parse_ltlf("X[!] true"))
    assert "digraph" in target.read_text(encoding="utf-8")


def test_formula_from_a_file_with_comments_and_line_breaks(capsys, tmp_path):
    spec = tmp_path / "task.ltlf"
    spec.write_text("# respond to every request\nG(a ->\n  F b)  # eventually\n", encoding="utf-8")
    code, out, err = run(capsys, "dfa", "--json", "-f", str(spec))
    assert code == 0 and err == ""
    from_file = json.loads(out)
    check_json_language(from_file, parse_ltlf("G(a -> F b)"))
    code, out, _ = run(capsys, "dfa", "--file", str(spec))
    assert code == 0
    assert re.search(r"states\D*\b3\b", out, re.I)


def test_next_strong_changes_the_meaning_of_x(capsys):
    code, out, _ = run(capsys, "dfa", "--json", "--next", "strong", "X a")
    assert code == 0
    strong = JsonDFA(json.loads(out))
    code, default, _ = run(capsys, "dfa", "--json", "X a")  # weak by default, as `synth` reads it
    assert code == 0
    code, out, _ = run(capsys, "dfa", "--json", "--next", "weak", "X a")
    assert json.loads(out) == json.loads(default)
    weak = JsonDFA(json.loads(out))
    # a trace of length 1 has no next position: strong X fails, weak X holds
    assert not strong.accepts([{"a"}])
    assert weak.accepts([{"a"}])
    assert weak.accepts([set()])
    assert strong.accepts([set(), {"a"}]) and weak.accepts([set(), {"a"}])
    assert not weak.accepts([set(), set()])
    check_json_language(json.loads(out), parse_ltlf("WX a"))


def test_bad_formula_gives_exit_2_with_position_and_no_traceback(capsys):
    code, out, err = run(capsys, "dfa", "G(a -> F b")
    assert code == 2
    assert out == ""
    assert re.search(r":1:11\b", err)
    assert "^" in err
    assert "Traceback" not in err


def test_bad_formula_in_a_file_names_the_file_line_and_column(capsys, tmp_path):
    spec = tmp_path / "bad.ltlf"
    spec.write_text("# a comment\nG(a ->\n  F b c)\n", encoding="utf-8")
    code, out, err = run(capsys, "dfa", "-f", str(spec))
    assert code == 2
    assert f"{spec}:3:7" in err     # the stray atom `c`
    assert "Traceback" not in err
    assert len([line for line in err.splitlines() if "syntax error" in line]) == 1


def test_missing_file_is_a_user_error(capsys, tmp_path):
    code, _, err = run(capsys, "dfa", "-f", str(tmp_path / "nowhere.ltlf"))
    assert code == 2
    assert "nowhere.ltlf" in err
    assert "Traceback" not in err


def test_unwritable_dot_target_is_a_user_error(capsys, tmp_path):
    code, _, err = run(capsys, "dfa", "--dot", str(tmp_path / "no" / "such" / "dir.dot"), "F a")
    assert code == 2
    assert "Traceback" not in err


@pytest.mark.parametrize("argv", [
    ["dfa"],                                 # neither formula nor file
    ["dfa", "--next", "medium", "X a"],      # unknown convention
    ["dfa", "-f", "x.ltlf", "--lines", "y"],  # both files and lines
    ["dfa", "-f"],                           # no file
])
def test_bad_options_exit_with_2(capsys, argv):
    # argparse reports usage errors by raising SystemExit(2); returning 2 is as good
    try:
        code = main(argv)
    except SystemExit as stop:
        code = stop.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.strip()
    assert "Traceback" not in err


@settings(max_examples=60, deadline=None)
@given(formulas(max_depth=3))
def test_the_transitions_counted_are_the_minimal_dfas(formula):
    """`num_transitions` (one BDD, counted) against the (state, successor)
    pairs of the reference DFA minimized by brute force."""
    reference = minimize(reference_dfa(formula))
    expected = sum(len(set(row)) for row in reference.delta)
    dfa = compile_ltlf(formula)
    assert dfa.num_transitions() == expected, to_string(formula)
    done: list[int] = []
    assert len(dfa.to_explicit(progress=done.append).transitions) == expected
    assert done == list(range(1, dfa.num_states + 1))  # the progress bar's count: each state once


def test_a_dfa_past_the_transition_limit_is_refused_before_it_is_listed(capsys, tmp_path):
    """G(a -> X[!] b) & F c: 5 states, 15 transitions, counted by hand: the start
    reaches itself, 'c seen', 'b owed' and 'both' (4); 'c seen' itself and
    'both' (2); 'b owed' the sink and the start's 4 (5); 'both' the sink,
    'c seen' and itself (3); the sink itself (1)."""
    formula = "G(a -> X[!] b) & F c"
    expected = 15
    assert sum(len(set(row)) for row in minimize(reference_dfa(parse_ltlf(formula))).delta) == expected
    code, out, err = run(capsys, "dfa", "--json", "--max-transitions", str(expected - 1), formula)
    assert code == 2 and out == ""
    assert f"{expected:,} transitions (more than {expected - 1:,})" in err and "--max-transitions 0" in err
    assert "Traceback" not in err
    dot = tmp_path / "dfa.dot"
    code, out, err = run(capsys, "dfa", "--dot", str(dot), "--max-transitions", str(expected - 1), formula)
    assert code == 2 and not dot.exists()
    for limit in (expected, 0):  # at the limit, and no limit
        code, out, _ = run(capsys, "dfa", "--json", "--max-transitions", str(limit), formula)
        assert code == 0 and len(json.loads(out)["transitions"]) == expected


@pytest.mark.parametrize("value", ["-1", "many", "1.5"])
def test_a_bad_transition_limit_exits_with_2(capsys, value):
    try:
        code = main(["dfa", "--json", "--max-transitions", value, "F a"])
    except SystemExit as stop:
        code = stop.code
    err = capsys.readouterr().err
    assert code == 2 and "--max-transitions" in err and "Traceback" not in err


@pytest.mark.parametrize("formula, column, hint", [
    ("Fa", 1, "did you mean 'F a'?"),
    ("G(a -> Xb)", 8, "did you mean 'X b'?"),
    ("Ga", 1, "did you mean 'G a'?"),
    ("GFp1 & q", 1, "did you mean 'G F p1'?"),
    ("F(go) & Xpos & pos", 9, "did you mean 'X pos'?"),   # the rest is an atom of the formula
])
def test_an_operator_glued_to_an_atom_is_refused_with_a_hint(capsys, formula, column, hint):
    code, out, err = run(capsys, "dfa", formula)
    assert code == 2 and out == ""
    assert f"<formula>:1:{column}: syntax error: " in err and hint in err and "Traceback" not in err


@pytest.mark.parametrize("formula, atoms", [
    ("Found & Xpos", {"Found", "Xpos"}),       # a long name: an atom
    ("Gripper U heap_1_2", {"Gripper", "heap_1_2"}),
    ("F a & X[!] b", {"a", "b"}),
])
def test_names_that_only_start_like_an_operator_are_atoms(capsys, formula, atoms):
    code, out, _ = run(capsys, "dfa", "--json", formula)
    assert code == 0 and set(json.loads(out)["atoms"]) == atoms


def test_running_out_of_memory_is_one_message_and_exit_1(tmp_path):
    """A formula whose automaton outgrows the process's address-space limit
    (URright's chain of 14 atoms, whose construction alone peaks at 0.45 GB,
    under 250 MB) ends with one line on stderr and exit status 1, not a
    traceback.  (The chain of 13 fits now: its summary makes no transition
    bits, 2.2 M nodes.)"""
    import resource
    import subprocess
    import sys

    chain = "p14"
    for i in range(13, 0, -1):
        chain = f"p{i} {'U' if i % 2 else 'R'} ({chain})"
    spec = tmp_path / "urright14.ltlf"
    spec.write_text(chain + "\n")

    def limited():
        resource.setrlimit(resource.RLIMIT_AS, (250_000_000, 250_000_000))

    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "dfa", "-f", str(spec)], capture_output=True,
                          text=True, preexec_fn=limited, timeout=300)
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr
    # (CUDD itself writes a line when its allocation fails, before Python hears of it)
    said = [line for line in done.stderr.strip().splitlines() if line and not line.startswith("CUDD: unable to allocate")]
    assert len(said) == 1 and "out of memory" in said[0], done.stderr
