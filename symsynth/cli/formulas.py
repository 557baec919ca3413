"""Formulas for `symsynth dfa` and `symsynth synth`: read from regular files
only and up to a size, parsed and compiled with progress on a terminal and
under a state limit, each refusal one message naming the source."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import get_args

from symsynth.automata import SymbolicDFA, compile_ltlf
from symsynth.automata.compiler import Construction
from symsynth.automata.growth import StateLimitReached, watched
from symsynth.cli.options import count
from symsynth.cli.progress import bar
from symsynth.errors import InputError, read_text
from symsynth.logic import ast, parse_ltlf
from symsynth.logic.parser import NextSemantics

#: Bytes of a formula file read at most unless asked: 5 times the largest
#: formula of the public LTLf synthesis datasets (Nim nim_20_20, 0.7 MB).
#: The parser reads about 0.3 MB a second.
MAX_BYTES = 4_000_000
#: States of an explicit automaton built for a formula at most unless asked
#: (about 4 GB of guards at that size; the datasets' largest is 65,000).
MAX_STATES = 1_000_000


def add_limits(parser: argparse.ArgumentParser) -> None:
    """--max-bytes, --max-states and --construction."""
    parser.add_argument("--construction", choices=get_args(Construction), default="auto",
                        help="how the DFA is built: compositional (a minimal DFA per part, combined), progression "
                             "of the whole formula from its start (only the states reachable there: faster when the "
                             "parts are large alone and small together, as in SYNTCOMP's chomp; slower on counters), "
                             "backward (the formula evaluated backwards, its reverse determinized: minimal as built, "
                             "no minimization; fastest on alternating until/release chains), "
                             "or auto (default): compositional for an equivalence with a next operand or temporal "
                             "parts over disjoint atoms, else progression while it stays under 200,000 edges "
                             "(and 64 successors per state over its first 16), compositional past that (docs/ltlf.md)")
    parser.add_argument("--max-states", type=count, default=MAX_STATES, metavar="N",
                        help="refuse a formula once an automaton built for it passes N states "
                             f"(default {MAX_STATES:,}; 0: no limit)")
    parser.add_argument("--max-bytes", type=count, default=MAX_BYTES, metavar="N",
                        help=f"refuse a formula file of more than N bytes (default {MAX_BYTES:,}; 0: no limit)")


def read_formula_file(path: Path, max_bytes: int) -> str:
    """The text of a formula file: a regular file (a named pipe would block
    until a writer comes; a device may never end) of at most `max_bytes`."""
    try:
        return read_text(path, "formula file", limit=max_bytes or None, regular=True)
    except InputError as error:
        if "symsynth reads" in str(error) and "regular" not in str(error):
            raise InputError(f"{error}; --max-bytes N raises the limit, 0 lifts it") from None
        raise


def parse(text: str, source: str, next_semantics: NextSemantics) -> ast.Formula:
    """`parse_ltlf`, with a progress bar on a long text."""
    with bar(total=len(text), desc=f"parsing {source}", unit=" chars", unit_scale=True, delay=1.0) as shown:
        return parse_ltlf(text, source=source, next_semantics=next_semantics,
                          progress=lambda done: shown.update(done - shown.n))


def compile_formula(formula: ast.Formula, source: str, max_states: int,
                    construction: Construction = "auto") -> SymbolicDFA:
    """`compile_ltlf`, refused past `max_states` explicit states (0: no
    limit), with a count of the states built on a terminal."""
    with bar(desc=f"building the DFA of {source}", unit=" states", unit_scale=True, delay=1.0) as shown, \
            watched(max_states or None, lambda built: shown.update(built - shown.n)):
        try:
            return compile_ltlf(formula, source=source, construction=construction)
        except StateLimitReached as error:
            raise InputError(f"{source}: {error}; --max-states N raises the limit, 0 lifts it") from None
