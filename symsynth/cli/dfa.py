"""`symsynth dfa`: compile an LTLf formula to its minimal DFA."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.symbolic import SymbolicDFA, TooManyTransitions
from symsynth.cli import formulas
from symsynth.cli.options import count
from symsynth.cli.progress import bar as progress_bar
from symsynth.cli.stopping import killable
from symsynth.errors import InputError, SymsynthError
from symsynth.files import write_atomic

#: Transitions `--json` and `--dot` list at most unless asked (JSON: ~80 bytes each).
MAX_TRANSITIONS = 200_000

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

By default a summary is printed (states, BDD nodes, seconds; where the
backward construction built the DFA, the nodes of its diagram over the
atoms with the states at the leaves, and the state bits' transition
functions are not made).  --json prints
the explicit DFA: {"atoms", "initial", "accepting", "transitions": [{"from",
"to", "guard"}]} with guards over the atoms; --dot FILE writes Graphviz.

Many formulas in one process: -f FILE FILE ... (a formula per file) or
--lines FILE (a formula per line) print one JSON line per formula:
{"source", "line" (with --lines), "atoms", "states", "bdd_nodes" (or
"diagram_nodes", as in the summary), "seconds"} and, with --json, "dfa";
a formula that is refused gives {"source", "line", "error"} and the
others go on (exit status 2 at the end).

Formula files must be regular files (not pipes or devices) of at most
--max-bytes; an automaton built for a formula past --max-states states is
refused.  SIGTERM and Ctrl-C end the command at once."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("dfa", help=COMMANDS["dfa"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("formula", nargs="?", help="the LTLf formula, quoted")
    source.add_argument("-f", "--file", type=Path, nargs="+", metavar="FILE",
                        help="read the formula from FILE ('#' starts a comment); several FILEs: one "
                             "JSON line each")
    source.add_argument("--lines", type=Path, nargs="+", metavar="FILE",
                        help="read one formula per line of each FILE (blank lines and '#' comments "
                             "skipped): one JSON line each")
    parser.add_argument("--next", choices=("strong", "weak"), default="weak",
                        help="meaning of plain X (default: weak, as in the datasets, Lydia, TLSF and "
                             "`symsynth synth`; X[!] is always strong)")
    parser.add_argument("--json", action="store_true", help="print the explicit DFA as JSON (in a JSON "
                        "line, under \"dfa\")")
    parser.add_argument("--dot", type=Path, metavar="FILE", help="write the DFA as Graphviz to FILE")
    parser.add_argument("--max-transitions", type=count, default=MAX_TRANSITIONS, metavar="N",
                        help="refuse --json and --dot for a DFA of more than N transitions "
                        f"(default {MAX_TRANSITIONS:,}; 0: no limit)")
    formulas.add_limits(parser)
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


def run(args: argparse.Namespace) -> int:
    if args.formula is None and (args.lines or len(args.file) > 1):
        if args.dot:
            raise InputError("--dot writes one DFA: give one formula or one -f FILE")
        return _batch(args)
    if args.formula is not None:
        text, source = args.formula, "<formula>"
    else:
        text, source = formulas.read_formula_file(args.file[0], args.max_bytes), str(args.file[0])
    with killable():
        start = time.perf_counter()
        dfa = formulas.compile_formula(formulas.parse(text, source, args.next), source, args.max_states,
                                       args.construction)
        if args.json or args.dot:
            dfa.make_delta()  # (listing needs them: timed with the construction, as always)
        seconds = time.perf_counter() - start
        explicit = _explicit(dfa, args.max_transitions or None) if args.json or args.dot else None
    if explicit is not None:
        if args.dot:
            write_atomic(args.dot, explicit.to_dot(title=text.strip()), "DOT file")
        if args.json:
            print(json.dumps(explicit.to_json(), indent=2))
            return 0
    print(f"formula    {source if args.file else text.strip()}")
    print(f"atoms      {len(dfa.atoms)}: {', '.join(dfa.atoms) or '-'}")
    print(f"states     {dfa.num_states} (minimal, complete)")
    size = _size(dfa)
    if "bdd_nodes" in size:
        print(f"bdd nodes  {size['bdd_nodes']} (transition functions, acceptance, reachable set)")
    else:
        print(f"diagram    {size['diagram_nodes']} nodes over the atoms, the states at its leaves (each state's "
              f"moves; the state bits' functions not made)")
    print(f"state bits {len(dfa.bits)}")
    print(f"seconds    {seconds:.4f}")
    if args.dot:
        print(f"wrote      {args.dot}")
    return 0


def _batch(args: argparse.Namespace) -> int:
    """One JSON line per formula (module description); exit status 2 when
    any formula or file was refused, 0 otherwise."""
    failed = False
    with killable():
        for source, line, text in _formulas(args):
            result: dict = {"source": source}
            if line is not None:
                result["line"] = line
            try:
                if text is None:  # (the file could not be read: its message is the error)
                    text = formulas.read_formula_file(Path(source), args.max_bytes)
                start = time.perf_counter()
                dfa = formulas.compile_formula(formulas.parse(text, source, args.next), source,
                                               args.max_states, args.construction)
                if args.json:
                    dfa.make_delta()  # (as in `run`)
                seconds = time.perf_counter() - start
                explicit = _explicit(dfa, args.max_transitions or None) if args.json else None
                result.update(atoms=list(dfa.atoms), states=dfa.num_states, **_size(dfa),
                              seconds=round(seconds, 6))
                if explicit is not None:
                    result["dfa"] = explicit.to_json()
            except SymsynthError as error:
                failed = True
                result["error"] = str(error)
            print(json.dumps(result), flush=True)
    return 2 if failed else 0


def _size(dfa: SymbolicDFA) -> dict[str, int]:
    """The DFA's size: "bdd_nodes" (the transition functions, the
    acceptance and the reachable set), or "diagram_nodes" (the numbered
    diagram's nodes over the atoms) when the functions were not made
    (the summary does not make them)."""
    if dfa.delta_made or dfa.diagram is None:
        return {"bdd_nodes": dfa.num_nodes}
    return {"diagram_nodes": len(dfa.diagram.var)}


def _formulas(args: argparse.Namespace):
    """(source, line or None, text or None) for each formula of the batch:
    each -f FILE whole (its text read when compiled), or each formula line
    of each --lines FILE (a file that cannot be read: one entry, no text)."""
    if args.file:
        for path in args.file:
            yield str(path), None, None
        return
    for path in args.lines:
        try:
            text = formulas.read_formula_file(path, args.max_bytes)
        except InputError:
            yield str(path), None, None  # read again to report its error
            continue
        for number, line in enumerate(text.split("\n"), 1):
            if line.split("#", 1)[0].strip():  # (after number - 1 line ends: errors name the file's line)
                yield str(path), number, "\n" * (number - 1) + line
