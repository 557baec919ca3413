"""`symsynth synth`: LTLf synthesis from a formula and a partition file."""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.cli import formulas
from symsynth.cli.progress import bar as progress_bar
from symsynth.cli.stopping import killable
from symsynth.errors import InputError
from symsynth.files import write_atomic
from symsynth.logic import ast
from symsynth.synthesis import read_partition, solve_realizability
from symsynth.synthesis import symbolic_strategy as symbolic
from symsynth.synthesis.tlsf import read_tlsf
from symsynth.synthesis.machine import MAX_INPUTS, MAX_STATES, TooLarge, strategy_machine, write_json

DESCRIPTION = """\
Decide whether the agent, which sets the .outputs of SPEC.part, can force the
LTLf formula of SPEC.ltlf against an environment that sets the .inputs,
whatever the environment does (traces are finite and non-empty; the agent
wins once the trace read so far satisfies the formula).

A SPEC.tlsf is read as SYNTCOMP's finite-trace TLSF (SEMANTICS Mealy,Finite
or Moore,Finite; no --part: its INPUTS are the environment's, its OUTPUTS
the agent's; Mealy: the environment moves first, Moore: the agent), its
GLOBAL definitions evaluated as syfco does; --param N=3 sets a parameter.

The agent moves first in each step by default (--env-first: the environment).
Plain X is weak next by default, as in Lydia, SYNTCOMP's TLSF and the LTLf
synthesis datasets, and as `symsynth dfa` reads it (X[!] is strong next,
WX weak); --next strong reads X as strong.

Output as in SYNTCOMP: the first line is REALIZABLE or UNREALIZABLE, exit
status 10 or 20 (2 for bad input).  -o FILE writes a winning strategy: a
machine listing its states, as JSON (FILE.json) or Graphviz (FILE.dot), or,
for specs too large to list, its BDDs (symsynth.strategy-bdd/1, FILE.json);
--strategy chooses (default auto: the machine when it fits, else the BDDs).

A variable of the formula that the partition does not name is an error.
Both files must be regular files (not pipes or devices); an automaton built
for the formula past --max-states states is refused.  SIGTERM and Ctrl-C
end the command at once."""

REALIZABLE, UNREALIZABLE = 10, 20


def _position(text: str, name: str) -> str:
    """':line:column' of the first occurrence of the variable `name` in the
    formula's text outside comments ('' when it cannot be found)."""
    for number, line in enumerate(text.splitlines(), 1):
        found = re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", line.split("#", 1)[0])
        if found:
            return f":{number}:{found.start() + 1}"
    return ""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("synth", help=COMMANDS["synth"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("spec", type=Path, metavar="SPEC",
                        help="the LTLf formula (SPEC.ltlf, '#' starts a comment) or a TLSF specification (SPEC.tlsf)")
    parser.add_argument("--part", type=Path, metavar="SPEC.part",
                        help="the partition of SPEC.ltlf: '.inputs: ...' (environment) and '.outputs: ...' (agent)")
    parser.add_argument("--param", action="append", type=_parameter, default=[], metavar="NAME=N",
                        help="SPEC.tlsf: give the GLOBAL parameter NAME the value N (repeatable)")
    first = parser.add_mutually_exclusive_group()
    first.add_argument("--agent-first", dest="agent_first", action="store_true", default=None,
                       help="the agent moves first in each step (default for SPEC.ltlf; TLSF: Moore)")
    first.add_argument("--env-first", dest="agent_first", action="store_false",
                       help="the environment moves first in each step (TLSF: Mealy)")
    parser.add_argument("--next", choices=("strong", "weak"), default=None,
                        help="meaning of plain X in SPEC.ltlf (default: weak, as in the datasets and "
                             "`symsynth dfa`; X[!] is always strong; TLSF's finite semantics fixes X as weak)")
    parser.add_argument("-o", "--output", type=Path, metavar="FILE",
                        help="write a winning strategy to FILE (.json or .dot)")
    parser.add_argument("--strategy", choices=("auto", "machine", "bdd"), default="auto",
                        help="what -o writes: the listed machine, the BDDs, or (auto) the machine when it has at "
                             f"most {MAX_INPUTS} inputs and {MAX_STATES} states, the BDDs otherwise")
    parser.add_argument("--json", action="store_true", help="after the verdict line, a JSON summary")
    formulas.add_limits(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.output is not None and args.output.suffix not in (".json", ".dot"):
        raise InputError(f"-o {args.output}: expected a file name ending in .json or .dot")
    if args.output is not None and args.output.suffix == ".dot" and args.strategy == "bdd":
        raise InputError(f"-o {args.output} --strategy bdd: the BDDs are written as JSON; expected FILE.json")
    tlsf = args.spec.suffix == ".tlsf"
    _check_options(args, tlsf)
    given = None if tlsf else read_partition(args.part)
    text = formulas.read_formula_file(args.spec, args.max_bytes)
    with killable():  # (SIGTERM ends it at once: nothing is written before the strategy)
        if given is None:
            spec = read_tlsf(args.spec, text, dict(args.param))
            formula, partition = spec.formula, spec.partition
            if args.agent_first is None:
                args.agent_first = spec.agent_first
        else:
            formula, partition = formulas.parse(text, str(args.spec), args.next or "weak"), given
            _check_named(formula, partition, text, args)
        if args.agent_first is None:
            args.agent_first = True
        clock = time.perf_counter()
        dfa = formulas.compile_formula(formula, str(args.spec), args.max_states, args.construction)
        dfa.make_delta()  # (the game reads them: "dfa" seconds include them, as they always did)
        compiled = time.perf_counter() - clock
        with progress_bar(desc="game", unit=" rounds", delay=1.0) as bar:
            game = solve_realizability(dfa, partition, agent_first=args.agent_first,
                                       progress=lambda done: bar.update(done - bar.n))
        solved = time.perf_counter() - clock - compiled
        print("REALIZABLE" if game.realizable else "UNREALIZABLE", flush=True)
        if args.json:
            print(json.dumps({"realizable": game.realizable, "agent_first": game.agent_first,
                              "dfa_states": dfa.num_states, "rounds": len(game.rounds),
                              "seconds": {"dfa": round(compiled, 6), "game": round(solved, 6)}}), flush=True)
        strategy = _strategy_text(game, args) if args.output is not None and game.realizable else None
    if args.output is not None and not game.realizable:  # the verdict stands: exit 20, not 2
        print(f"symsynth synth: -o {args.output}: unrealizable, there is no winning strategy to write "
              "(nothing written)", file=sys.stderr)
    elif strategy is not None:
        write_atomic(args.output, strategy, "strategy")
    return REALIZABLE if game.realizable else UNREALIZABLE


def _parameter(text: str) -> tuple[str, int]:
    name, equal, value = text.partition("=")
    if not equal or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name.strip()) or \
            not re.fullmatch(r"-?[0-9]+", value.strip()):
        raise argparse.ArgumentTypeError(f"{text!r}: expected NAME=N, an integer value (e.g. N=3)")
    return name.strip(), int(value)


def _check_options(args: argparse.Namespace, tlsf: bool) -> None:
    """--part goes with SPEC.ltlf, --param with SPEC.tlsf."""
    if tlsf and args.part is not None:
        raise InputError(f"--part {args.part}: {args.spec} is TLSF, whose INPUTS and OUTPUTS are the partition; "
                         "leave --part out")
    if tlsf and args.next is not None:
        raise InputError(f"--next {args.next}: {args.spec} is TLSF, whose finite semantics reads X as weak next "
                         "and X[!] as strong; leave --next out")
    if not tlsf and args.part is None:
        raise InputError(f"{args.spec}: an LTLf formula needs its partition: --part SPEC.part (or give a "
                         "TLSF file, SPEC.tlsf)")
    if not tlsf and args.param:
        raise InputError(f"--param: parameters belong to TLSF specifications (SPEC.tlsf), not {args.spec}")


def _check_named(formula: ast.Formula, partition, text: str, args: argparse.Namespace) -> None:
    """Every variable of the formula is in the partition."""
    named = set(partition.inputs) | set(partition.outputs)
    unknown = [a.key for a in ast.atoms(formula) if a.key not in named]
    if unknown:
        raise InputError(f"{args.spec}{_position(text, unknown[0])}: {', '.join(unknown)} "
                         f"{'is' if len(unknown) == 1 else 'are'} in the formula but in neither list of "
                         f"{args.part}; name each variable as an input or an output")


def _strategy_text(game, args: argparse.Namespace) -> str:
    """The file -o writes (--strategy: module description)."""
    if args.strategy != "bdd":
        try:
            machine = strategy_machine(game)
        except TooLarge as error:
            if args.strategy == "machine" or args.output.suffix == ".dot":
                raise InputError(f"-o {args.output}: {error}; write its BDDs with --strategy bdd to FILE.json") \
                    from None
            print(f"{error}: writing its BDDs ({symbolic.FORMAT}) to {args.output}", file=sys.stderr)
        else:
            return machine.to_dot() if args.output.suffix == ".dot" else write_json(machine)
    return symbolic.write_json(symbolic.symbolic_strategy(game))
