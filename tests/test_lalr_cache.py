"""The LALR tables of the shipped grammars are built once and then read from
symsynth's cache directory (symsynth/logic/lalr.py): read back, not built
again; rebuilt from a spoilt or half-written file; built in every run when
the folder cannot be made; and several processes starting at once on an
empty cache all parse."""

from __future__ import annotations

import subprocess
import sys

import lark
import pytest

from symsynth.logic import ast, lalr, parser


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    parser._parser.cache_clear()
    yield tmp_path / "cache"
    parser._parser.cache_clear()


EXPECTED = ast.Until(ast.Atom("a"), ast.WeakNext(ast.Atom("b")))


def test_the_tables_are_read_back_not_built_again(cache, monkeypatch):
    assert parser.parse_ltlf("a U X b", next_semantics="weak") == EXPECTED
    [table] = cache.glob("ltlf-lalr-*.cache")
    parser._parser.cache_clear()

    def no_analysis(*args, **kwargs):
        raise AssertionError("the grammar was analysed again")
    monkeypatch.setattr(lark.lark, "load_grammar", no_analysis)
    assert parser.parse_ltlf("a U X b", next_semantics="weak") == EXPECTED
    assert parser.parse_ltlf("a U X b", next_semantics="strong") == ast.Until(ast.Atom("a"), ast.Next(ast.Atom("b")))


@pytest.mark.parametrize("spoilt", [b"not a pickle\n", "half"])
def test_a_spoilt_or_half_written_table_file_is_built_again(cache, spoilt):
    parser.parse_ltlf("a", next_semantics="weak")
    [table] = cache.glob("ltlf-lalr-*.cache")
    whole = table.read_bytes()
    table.write_bytes(whole[: len(whole) // 2] if spoilt == "half" else spoilt)
    assert lalr.read_tables(table) is None
    parser._parser.cache_clear()
    assert parser.parse_ltlf("a U X b", next_semantics="weak") == EXPECTED
    assert lalr.read_tables(table) is not None  # (written again whole; two builds need not give the same bytes)


def test_a_cache_folder_that_cannot_be_made_costs_time_only(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("")
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "file" / "cache"))  # a folder inside a file
    parser._parser.cache_clear()
    try:
        assert parser.parse_ltlf("a U X b", next_semantics="weak") == EXPECTED
    finally:
        parser._parser.cache_clear()


@pytest.mark.parametrize("start", ["empty", "half-written"])
def test_processes_starting_at_once_all_parse(tmp_path, start):
    """Six `symsynth dfa` at once on an empty cache folder, or on one whose
    table file was left half written (a run killed while writing it without
    write_atomic): each builds or reads the tables while the others write
    them, and all answer alike.  (With the digest check gone, every process
    reads the half file and fails.)"""
    cache = tmp_path / "cache"
    env = {"SYMSYNTH_CACHE": str(cache), "PATH": "/usr/bin:/bin"}
    command = [sys.executable, "-m", "symsynth.cli", "dfa", "--json", "G(a -> X b) & F c"]
    if start == "half-written":
        subprocess.run(command, env=env, capture_output=True, check=True)
        [table] = cache.glob("ltlf-lalr-*.cache")
        whole = table.read_bytes()
        table.write_bytes(whole[: len(whole) // 2])
    runs = [subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            for _ in range(6)]
    outputs = [run.communicate(timeout=120) for run in runs]
    assert [run.returncode for run in runs] == [0] * 6, [err for _, err in outputs]
    assert len({out for out, _ in outputs}) == 1
    assert [err for _, err in outputs] == [""] * 6
    [table] = cache.glob("ltlf-lalr-*.cache")
    assert lalr.read_tables(table) is not None
