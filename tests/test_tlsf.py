"""The TLSF reader (symsynth/synthesis/tlsf.py): hand-written snippets against
the LTLf formula they mean (syfco's binding and unrolling, written out by
hand), SYNTCOMP's chomp and Scutellà specifications against the verdicts
known for them (tests/data/tlsf-fin/README.md), and the errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from symsynth.automata import compile_ltlf
from symsynth.cli import main
from symsynth.logic import ast, parse_ltlf
from symsynth.synthesis import solve_realizability
from symsynth.synthesis.tlsf import TLSFError, parse_tlsf

DATA = Path(__file__).parent / "data" / "tlsf-fin"
CHOMP = (DATA / "chomp.tlsf").read_text()


def flat(f: ast.Formula):
    """`f` with its `&` and `|` chains as sorted tuples (the reader joins
    them as balanced trees, the LTLf parser as left-leaning ones)."""
    if isinstance(f, (ast.And, ast.Or)):
        items, stack = [], [f]
        while stack:
            g = stack.pop()
            if type(g) is type(f):
                stack += [g.left, g.right]
            else:
                items.append(flat(g))
        return (type(f).__name__, tuple(sorted(items, key=repr)))
    if isinstance(f, ast.UNARY):
        return (type(f).__name__, flat(f.arg))
    if isinstance(f, ast.BINARY):
        return (type(f).__name__, flat(f.left), flat(f.right))
    return f


def spec(main_body: str, global_body: str = "", semantics: str = "Mealy,Finite", **params):
    text = (f'INFO {{ TITLE: "t" DESCRIPTION: "d" SEMANTICS: {semantics} TARGET: Mealy }}\n'
            + (f"GLOBAL {{ {global_body} }}\n" if global_body else "")
            + f"MAIN {{ INPUTS {{ a; b; c; }} OUTPUTS {{ x[3]; y; }} {main_body} }}")
    return parse_tlsf(text, source="s.tlsf", parameters=params)


def guarantee(text: str, global_body: str = "", **params) -> ast.Formula:
    return spec(f"GUARANTEE {{ {text}; }}", global_body, **params).formula


def expect(ltlf: str):
    return flat(parse_ltlf(ltlf, next_semantics="weak"))


@pytest.mark.parametrize("tlsf, ltlf", [
    # binding as syfco's parser: the temporal binary operators are loosest, R the loosest of them
    ("a && b U c", "(a & b) U c"),
    ("a -> b U c", "(a -> b) U c"),
    ("a U b R c", "(a U b) R c"),
    ("a W b U c", "(a W b) U c"),
    ("a || b && c", "a | (b & c)"),
    ("a -> b -> c", "a -> (b -> c)"),
    ("!a && b", "!a & b"),
    # finite semantics: X weak, X[!] strong; X[n], G[a:b] and F[a:b] unrolled as syfco does
    ("X a && X[!] b", "WX a & X[!] b"),
    ("X[2] a", "WX WX a"),
    ("G[1:2] a", "WX (a & WX a)"),
    ("F[0:1] a", "a | WX a"),
    ("G (a -> F y)", "G (a -> F y)"),
    # buses and big operators
    ("&&[0 <= i < 3] x[i]", "x_0 & x_1 & x_2"),
    ("||[0 < i <= 2] x[i]", "x_1 | x_2"),
    ("&&[i IN {0, 2}] (a -> x[i])", "(a -> x_0) & (a -> x_2)"),
    ("&&[0 <= i < 2, i < j < 3] (x[i] -> !x[j])", "(x_0 -> !x_1) & (x_0 -> !x_2) & (x_1 -> !x_2)"),
    ("||[0 <= i < 0] a", "false"),
    ("&&[0 <= i < SIZEOF x] x[i] || y", "(x_0 & x_1 & x_2) | y"),
])
def test_snippets_read_as_the_formula_they_mean(tlsf, ltlf):
    assert flat(guarantee(tlsf)) == expect(ltlf)


def test_definitions_functions_cases_and_parameters():
    defs = ("PARAMETERS { N = 2; } DEFINITIONS { K = N + 1; S = {0, 1 .. K}; "
            "Later(s, n) = n == 0 : s  n > 0 : X Later(s, n - 1); "
            "Pick(bus, i) = bus[i % SIZEOF bus]; }")
    assert flat(guarantee("Later(a, N)", defs)) == expect("WX WX a")
    assert flat(guarantee("Later(a, N)", defs, N=0)) == expect("a")
    assert flat(guarantee("Pick(x, K + 1)", defs)) == expect("x_1")
    assert flat(guarantee("||[i IN S] Pick(x, i)", defs)) == expect("x_0 | x_1 | x_2 | x_0")  # i = 0 .. K = 3, taken mod 3
    assert flat(guarantee("x == x", defs)) == expect("(x_0 <-> x_0) & (x_1 <-> x_1) & (x_2 <-> x_2)")


def test_sections_combine_as_syfco_merges_them():
    read = spec("INITIALLY { a; } PRESET { x[0]; } REQUIRE { b; } ASSUME { F c; } "
                "ASSERT { y; x[1]; } GUARANTEE { F x[2]; }")
    assert flat(read.formula) == expect("a -> (x_0 & ((G b & F c) -> (G (y & x_1) & F x_2)))")
    assert read.partition.inputs == ("a", "b", "c")
    assert read.partition.outputs == ("x_0", "x_1", "x_2", "y")
    only = spec("ASSUME { F c; } GUARANTEES { F y; }")
    assert flat(only.formula) == expect("F c -> F y")


def test_mealy_lets_the_environment_move_first_and_moore_the_agent():
    assert spec("GUARANTEE { F y; }", semantics="Mealy,Finite").agent_first is False
    assert spec("GUARANTEE { F y; }", semantics="Finite,Moore").agent_first is True


@pytest.mark.parametrize("n, m", [(1, 1), (1, 2), (2, 1), (2, 2), (2, 3)])
def test_chomp_is_won_by_the_first_player_on_every_board_but_1x1(n, m):
    read = parse_tlsf(CHOMP, source="chomp.tlsf", parameters={"N": n, "M": m})
    assert read.partition.outputs[:2] == ("ox_0", "ox_1") if n > 1 else True
    game = solve_realizability(compile_ltlf(read.formula), read.partition, agent_first=read.agent_first)
    assert game.realizable == ((n, m) != (1, 1))


def test_scutella_is_realizable():
    read = parse_tlsf((DATA / "scutella_pb_1_pe_.tlsf").read_text())
    game = solve_realizability(compile_ltlf(read.formula), read.partition, agent_first=read.agent_first)
    assert game.realizable


@pytest.mark.parametrize("text, message", [
    ("MAIN { INPUTS { a; } GUARANTEE { a && ; } }", "s.tlsf:1:39: syntax error: unexpected ';'; expected a formula"),
    ('INFO { SEMANTICS: Mealy } MAIN { GUARANTEE { true; } }', "expected 'Mealy,Finite' or 'Moore,Finite'"),
    ("MAIN { GUARANTEE { true; } }", "no 'SEMANTICS: Mealy,Finite'"),
])
def test_errors_name_the_place_and_what_was_expected(text, message):
    with pytest.raises(TLSFError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        parse_tlsf(text, source="s.tlsf")


@pytest.mark.parametrize("body, message", [
    ("GUARANTEE { x[3]; }", r"s.tlsf:2:\d+: x\[3\]: the bus has 3 signals, indexed 0 to 2"),
    ("GUARANTEE { z; }", r"s.tlsf:2:\d+: 'z' is not defined"),
    ("GUARANTEE { a + 1; }", "expected a number, found the signal a"),
    ("GUARANTEE { &&[i == 2] a; }", "expected a binding such as 'a <= i < b'"),
])
def test_evaluation_errors_name_the_line(body, message):
    with pytest.raises(TLSFError, match=message):
        spec(body)


def test_an_unknown_parameter_is_refused():
    with pytest.raises(TLSFError, match=r"no parameter K .*\(it declares: M, N\)"):
        parse_tlsf(CHOMP, source="chomp.tlsf", parameters={"K": 3})


def test_synth_reads_a_tlsf_file(capsys):
    assert main(["synth", str(DATA / "chomp.tlsf"), "--param", "N=1", "--param", "M=1"]) == 20
    assert main(["synth", str(DATA / "chomp.tlsf"), "--param", "N=2"]) == 10
    assert capsys.readouterr().out.split() == ["UNREALIZABLE", "REALIZABLE"]
    assert main(["synth", str(DATA / "chomp.tlsf"), "--part", "x.part"]) == 2
    assert "leave --part out" in capsys.readouterr().err


def test_a_spoilt_parser_cache_is_rebuilt(tmp_path, monkeypatch):
    """The parser's tables are cached in symsynth's cache directory; a file
    there that is not lark's (or of another grammar) is built again."""
    from symsynth.synthesis import tlsf
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    tlsf._parser.cache_clear()
    try:
        spec("GUARANTEE { G y; }")
        [table] = tmp_path.glob("tlsf-*")
        table.write_bytes(b"not a pickle\n")
        tlsf._parser.cache_clear()
        assert spec("GUARANTEE { F y; }").formula == ast.Eventually(ast.Atom("y"))
        assert table.read_bytes() != b"not a pickle\n"
    finally:
        tlsf._parser.cache_clear()


@pytest.mark.parametrize("tlsf, ltlf", [
    ("counter_pb_01_pe_.tlsf", "Single-Counter/counter_01"),
    ("uright_pb_05_pe_.tlsf", "Patterns/Uright/uright05"),
])
def test_a_syntcomp_tlsf_file_reads_as_the_dataset_formula_it_was_made_from(tlsf, ltlf):
    """SYNTCOMP's tlsf-fin files were written from the LTLf synthesis
    datasets' formulas and partitions: both read the same."""
    from support.reference import distinguishing_trace
    from symsynth.synthesis import read_partition
    read = parse_tlsf((DATA / tlsf).read_text())
    base = DATA.parent / "finite-synthesis" / ltlf
    given = compile_ltlf((base.parent / (base.name + ".ltlf")).read_text(), next_semantics="weak")
    partition = read_partition(base.parent / (base.name + ".part"))
    mine = compile_ltlf(read.formula)
    assert (set(read.partition.inputs), set(read.partition.outputs)) == (set(partition.inputs), set(partition.outputs))
    assert read.agent_first  # Finite,Moore: the datasets' System-first
    assert mine.num_states == given.num_states
    assert distinguishing_trace(mine, given, sorted(partition.inputs + partition.outputs)) is None


def test_long_chains_are_read_without_recursion():
    """The datasets' Nim specifications chain thousands of `&&` (each one a
    level of the parse tree): read without running out of Python's stack."""
    n = 5000
    body = " && ".join("(a -> X b)" for _ in range(n - 1)) + " && F y"
    kind, items = flat(guarantee(body))
    assert kind == "And" and len(items) == n
    assert set(items) == {expect("a -> X b"), expect("F y")}
