"""The equivalence check of bench/ltlf_families.py (symsynth's DFA against
MONA's automaton over non-empty traces), on automata written by hand, so
that it needs no MONA: it finds equal languages equal and returns a
shortest distinguishing trace otherwise, by every letter or by sampling."""

from __future__ import annotations

import random

from bench.ltlf_automata import Auto
from bench.ltlf_families import equivalent
from symsynth.automata import compile_ltlf


def automaton(start, accepting, table):
    """`table`: state -> [(atoms that must hold, atoms that must not, target)]."""
    rows = {state: [((lambda letter, on=frozenset(on), off=frozenset(off): on <= letter and not off & letter), t)
                     for on, off, t in edges] for state, edges in table.items()}
    return Auto(start, set(accepting), rows, {}, "mona")


EVENTUALLY_A = automaton(0, {1}, {0: [({"a"}, set(), 1), (set(), {"a"}, 0)], 1: [(set(), set(), 1)]})
ALWAYS_A = automaton(0, {0}, {0: [({"a"}, set(), 0), (set(), {"a"}, 1)], 1: [(set(), set(), 1)]})


def test_equal_languages_are_found_equal():
    verdict, how = equivalent(compile_ltlf("F a"), EVENTUALLY_A, ["a"], 12, 100, random.Random(0))
    assert verdict is True and how == "exhaustive"


def test_a_shortest_distinguishing_trace_is_returned():
    verdict, how = equivalent(compile_ltlf("F a"), ALWAYS_A, ["a"], 12, 100, random.Random(0))
    # {} and {a} alone: both reject, then both accept; {} {a}: F a accepts, G a rejects
    assert how == "exhaustive" and verdict == (frozenset(), frozenset({"a"}))
    verdict, _ = equivalent(compile_ltlf("F a"), ALWAYS_A, ["a"], 0, 200, random.Random(0))
    assert verdict is not True  # found by sampling too
    assert compile_ltlf("F a").accepts(verdict) != ALWAYS_A.run(verdict)


def test_the_runs_paragraph_names_each_familys_commit(tmp_path):
    """Rows merged from two runs (`--from-csv`): the table says which commit
    each family was measured at, written from the rows, not by hand; a
    round trip through the CSV keeps the commits."""
    import argparse
    import csv

    from bench.ltlf_families import _typed, runs, write

    def row(family, instance, commit):
        return {"family": family, "instance": instance, "atoms": 1, "states": 2, "symsynth": 0.01,
                "symsynth_status": "ok", "mona": 0.02, "mona_status": "ok", "ltlf2dfa": None,
                "ltlf2dfa_status": "timeout", "equivalence": "equal (exhaustive)", "load": 1.0, "commit": commit}

    one = [row("Nim", "nim_01_01", "abc1234"), row("Nim", "nim_01_02", "abc1234")]
    assert runs(one) == ["symsynth at commit abc1234; every family in this one run.", ""]
    two = one + [row("Syft", "syft_1/001", "def5678")]
    assert runs(two)[0] == ("Runs (one family per run at most, so each row's tools ran side by side): "
                            "Nim at abc1234; Syft at def5678.")
    out = tmp_path / "families.md"
    write(two, argparse.Namespace(out=out, timeout=60.0, wall=180.0, load=[1.0]))
    assert "Nim at abc1234; Syft at def5678." in out.read_text()
    with open(out.with_suffix(".csv"), newline="") as rows:
        again = [_typed(r) for r in csv.DictReader(rows)]
    assert [r["commit"] for r in again] == ["abc1234", "abc1234", "def5678"]
    assert runs(again) == runs(two)
