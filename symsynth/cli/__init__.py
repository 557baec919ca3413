"""The `symsynth` command: `main(argv) -> int`.

Each subcommand lives in its own module with `register(subparsers)` that
adds its parser and sets `run`.  Only the module of the subcommand chosen
is imported (`COMMANDS` names them): `symsynth dfa` loads the LTLf
compiler, not the solvers, the scene or numba, so it starts in a tenth of
a second.  `symsynth --help` (or a command line without a known
subcommand) imports none of them: it lists each by its line in `COMMANDS`.  Only
`SymsynthError` is caught here: it becomes one message on stderr and exit
code 2.  Anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import NoReturn

from symsynth import __version__
from symsynth.errors import SymsynthError, SymsynthWarning

#: The subcommands in the order `--help` lists them, with the line it shows
#: for each: the command NAME is the module `symsynth.cli.NAME`, imported
#: only when it is chosen.
COMMANDS = {
    "dfa": "compile an LTLf formula to its minimal symbolic DFA",
    "solve": "solve a scene's game: the cost the robot can guarantee against the human",
    "costmap": "compute a physical scene's conditional costmap by motion planning, or verify one",
    "show": "render a physical scene to a PNG with its places and objects labelled",
    "simulate": "run a strategy in a PyBullet world against a simulated human",
    "synth": "LTLf synthesis: is a formula realizable by an agent against an environment?",
    "bench": "run a comparison experiment: a matrix of scenes, methods and solvers, with tables and plots",
}


class Parser(argparse.ArgumentParser):
    """argparse's parser, whose usage errors add a hint when the command
    line has an argument that starts with '-' but is no option: a formula
    such as '-a' (or '->'...) is read as an option and goes missing."""

    argv: Sequence[str] = ()

    def error(self, message: str) -> NoReturn:
        options = {o for action in self._actions for o in action.option_strings}
        dashed = [a for a in self.argv if a.startswith("-") and a.split("=")[0] not in options
                  and a != "--" and not _is_number(a)]
        if dashed:
            message += (f"\n(the argument {dashed[0]!r} starts with '-' and is read as an option: give an "
                        f"option's value as --OPTION={dashed[0]!r}, and a formula after --)")
        super().error(message)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def chosen(argv: Sequence[str]) -> str | None:
    """The subcommand a command line names: its first argument that is not
    an option, when that is a subcommand (None otherwise: `--help`, a
    typo, nothing)."""
    for arg in argv:
        if not arg.startswith("-"):
            return arg if arg in COMMANDS else None
    return None


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser with every subcommand registered, or, given `command`,
    only that one in full (the others by name: their modules stay
    unimported, and argparse only reads the chosen one's options)."""
    parser = Parser(
        prog="symsynth",
        description="Symbolic reactive synthesis for robot manipulation: LTLf tasks, "
                    "minimal symbolic DFAs, cost-bounded games.",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="Run 'symsynth COMMAND --help' for the options of a command.",
    )
    parser.add_argument("--version", action="version", version=f"symsynth {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMANDS:
        if name == command:
            importlib.import_module(f"symsynth.cli.{name}").register(subparsers)
        else:
            subparsers.add_parser(name, help=COMMANDS[name] if command is None else None)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    Parser.argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser(chosen(Parser.argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:  # --help, --version, or a usage error (already printed)
        return int(exit_.code or 0)
    try:
        with warnings.catch_warnings(), _signals():
            warnings.simplefilter("always", SymsynthWarning)
            warnings.showwarning = lambda message, *_, **__: print(
                f"symsynth {args.command}: warning: {message}", file=sys.stderr)
            return args.run(args)
    except SymsynthError as error:
        print(f"symsynth {args.command}: {error}", file=sys.stderr)
        return error.exit_code
    except MemoryError:  # the work outgrew the process's limit (ulimit, prlimit) or the machine
        print(f"symsynth {args.command}: out of memory: this problem needs more memory than the process "
              "may take (its address-space limit or the machine's memory); nothing more was written",
              file=sys.stderr)
        if argv is None:  # the program itself: it ends here, its finalizers not run (a CUDD operation
            # stopped by the lack of memory can leave references behind, which dd reports as an
            # error, with a traceback, when the manager is freed)
            for stream in (sys.stdout, sys.stderr):
                try:
                    stream.flush()
                except (BrokenPipeError, ValueError):  # (its reader is gone: nothing to keep)
                    pass
            os._exit(1)
        return 1
    except BrokenPipeError:  # e.g. `symsynth dfa --json ... | head`
        sys.stdout = None
        return 0
    except KeyboardInterrupt as stop:
        signum = getattr(stop, "signum", signal.SIGINT)
        print(f"symsynth {args.command}: stopped by {signal.Signals(signum).name}; finished work "
              "(cached costmaps, written files) is kept", file=sys.stderr)
        return 128 + signum


class Stopped(KeyboardInterrupt):
    """SIGTERM, raised where the program is, as Ctrl-C is (so the same
    clean-ups run: worker pools terminated, temporary files removed)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


@contextmanager
def _signals() -> Iterator[None]:
    """While a command runs: SIGTERM stops it like Ctrl-C, and a file size
    limit (SIGXFSZ, which kills by default) makes the write fail with an
    error the command reports.  Only in the main thread, where Python
    delivers signals; the previous handlers come back afterwards."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum, frame):
        raise Stopped(signum)
    old = {signal.SIGTERM: signal.signal(signal.SIGTERM, stop),
           signal.SIGXFSZ: signal.signal(signal.SIGXFSZ, signal.SIG_IGN)}
    try:
        yield
    finally:
        for signum, handler in old.items():
            signal.signal(signum, handler)
