"""`symsynth dfa`: compile an LTLf formula to its minimal DFA."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from symsynth.automata import compile_ltlf
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.symbolic import SymbolicDFA, TooManyTransitions
from symsynth.cli.options import count
from symsynth.cli.progress import bar as progress_bar
from symsynth.errors import InputError, read_text
from symsynth.files import write_atomic

#: Transitions `--json` and `--dot` list at most unless asked (JSON: ~80 bytes each).
MAX_TRANSITIONS = 200_000

HELP = "compile an LTLf formula to its minimal symbolic DFA"
DESCRIPTION = """\
Compile an LTLf formula (finite, non-empty traces) to its minimal complete DFA.

Syntax, tightest first: unary ! ~ X X[!] WX N F <> G []; then U, R (V), W
(right-associative); then & &&; then | ||; then -> => (right-associative);
then <-> <=>.  Atoms are identifiers or predicates such as at(black, top);
true, false and last are constants.

Plain X is weak next by default (true at the last position), as in the LTLf
synthesis datasets, Lydia and SYNTCOMP's TLSF, and as `symsynth synth` reads
it; X[!] is strong next and WX (N) weak next whatever --next says.  An atom
named like operators glued to an atom (Fa, Xb, GFa) is refused with a hint.

By default a summary is printed (states, BDD nodes, seconds).  --json prints
the explicit DFA: {"atoms", "initial", "accepting", "transitions": [{"from",
"to", "guard"}]} with guards over the atoms; --dot FILE writes Graphviz."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("dfa", help=HELP, description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("formula", nargs="?", help="the LTLf formula, quoted")
    source.add_argument("-f", "--file", type=Path, help="read the formula from FILE "
                        "('#' starts a comment)")
    parser.add_argument("--next", choices=("strong", "weak"), default="weak",
                        help="meaning of plain X (default: weak, as in the datasets, Lydia, TLSF and "
                             "`symsynth synth`; X[!] is always strong)")
    parser.add_argument("--json", action="store_true", help="print the explicit DFA as JSON")
    parser.add_argument("--dot", type=Path, metavar="FILE", help="write the DFA as Graphviz to FILE")
    parser.add_argument("--max-transitions", type=count, default=MAX_TRANSITIONS, metavar="N",
                        help="refuse --json and --dot for a DFA of more than N transitions "
                        f"(default {MAX_TRANSITIONS:,}; 0: no limit)")
    parser.set_defaults(run=run)


def _explicit(dfa: SymbolicDFA, limit: int | None) -> ExplicitDFA:
    """The explicit DFA, with a progress bar past a second; a DFA past
    `limit` transitions is refused before its guards are printed."""
    with progress_bar(total=dfa.num_states, desc="explicit DFA", unit=" states", delay=1.0) as bar:
        try:
            return dfa.to_explicit(limit, lambda done: bar.update(done - bar.n))
        except TooManyTransitions as error:
            raise InputError(f"{error}: too large to list as JSON or DOT; the summary (without "
                             f"--json and --dot) describes it, or --max-transitions 0 lifts "
                             f"the limit") from None


def read_formula(args: argparse.Namespace) -> tuple[str, str]:
    """(text, source name) from the positional formula or --file."""
    if args.file is None:
        return args.formula, "<formula>"
    return read_text(args.file, "formula file"), str(args.file)


def run(args: argparse.Namespace) -> int:
    text, source = read_formula(args)
    start = time.perf_counter()
    dfa = compile_ltlf(text, next_semantics=args.next, source=source)
    seconds = time.perf_counter() - start
    if args.json or args.dot:
        explicit = _explicit(dfa, args.max_transitions or None)
        if args.dot:
            write_atomic(args.dot, explicit.to_dot(title=text.strip()), "DOT file")
        if args.json:
            print(json.dumps(explicit.to_json(), indent=2))
            return 0
    print(f"formula    {source if args.file else text.strip()}")
    print(f"atoms      {len(dfa.atoms)}: {', '.join(dfa.atoms) or '-'}")
    print(f"states     {dfa.num_states} (minimal, complete)")
    print(f"bdd nodes  {dfa.num_nodes} (transition functions, acceptance, reachable set)")
    print(f"state bits {len(dfa.bits)}")
    print(f"seconds    {seconds:.4f}")
    if args.dot:
        print(f"wrote      {args.dot}")
    return 0
