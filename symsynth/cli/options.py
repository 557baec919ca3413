"""Argument types and checks shared by the subcommands: each turns bad input
into one message (argparse's usage error, or an `InputError`)."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Sequence
from pathlib import Path

from symsynth.errors import InputError
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the costmap options' modules are imported only by the commands that declare them
    from decimal import Decimal
    from symsynth.problem import CostmapRequest


def count(text: str) -> int:
    """A whole number >= 0 (human moves, seeds)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 0, found {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, found {value}")
    return value


def number(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, found {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, found {text!r}")
    return value


def amount(text: str) -> float:
    """A finite number >= 0."""
    value = number(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, found {text}")
    return value


def exact_amount(text: str) -> Decimal:
    """A finite number >= 0 as the decimal it is written as, exactly (a budget:
    49.99999999999999999999 is below 50, which the float it rounds to is not).
    (decimal is imported here: `dfa` and `synth` read no amount.)"""
    from decimal import Decimal, InvalidOperation
    try:
        value = Decimal(text.strip())
    except InvalidOperation:
        raise argparse.ArgumentTypeError(f"expected a number, found {text!r}") from None
    if not value.is_finite():
        raise argparse.ArgumentTypeError(f"expected a finite number, found {text!r}")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, found {text}")
    return value


def positive(text: str) -> float:
    value = number(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, found {text}")
    return value


def output_file(text: str) -> Path:
    """An output file's name (-o): not empty (Path('') is '.', the folder)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a file name, found an empty one")
    return Path(text)


def check_writable(path: Path, what: str, inputs: Sequence[Path | None] = ()) -> None:
    """Fail now, not after minutes of work, if `path` cannot be written: a
    folder, a file in no writable folder, a read-only file (the atomic write
    would replace it all the same: a rename needs only the folder), or one
    of this command's `inputs` (`-o scene.yaml` would put the output in
    place of the scene)."""
    folder = path.parent
    if path.is_dir() or not folder.is_dir() or not os.access(folder, os.W_OK):
        raise InputError(f"cannot write {what} {path}: "
                         + ("it is a directory" if path.is_dir() else f"{folder} is not a writable directory"))
    if path.exists() and (not os.access(path, os.W_OK) or not path.stat().st_mode & 0o222):  # (root may write)
        raise InputError(f"cannot write {what} {path}: the file is read-only (make it writable, or choose "
                         "another name)")
    for given in inputs:
        if given is not None and path.exists() and given.exists() and path.samefile(given):
            raise InputError(f"cannot write {what} {path}: it is this command's input {given}, which the "
                             f"{what} would replace; choose another name")


def size(text: str) -> tuple[int, int]:
    """`WIDTHxHEIGHT` in pixels, each side 16..8192."""
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT such as 800x600, found {text!r}") from None
    if not (16 <= width <= 8192 and 16 <= height <= 8192):
        raise argparse.ArgumentTypeError(f"each side must be 16..8192 pixels, found {text}")
    return width, height


def add_executor(parser: argparse.ArgumentParser, jobs_help: str, default_jobs: int | None = None) -> None:
    """--executor, --address and --jobs: where independent jobs run (`symsynth.parallel`)."""
    from symsynth.parallel import EXECUTORS

    parser.add_argument("--executor", choices=tuple(EXECUTORS), default="local",
                        help="local processes (default) or a Ray cluster (pip install 'symsynth[ray]')")
    parser.add_argument("--address", metavar="ADDR",
                        help="with --executor ray: the cluster to join ('auto' or HOST:PORT); "
                             "none starts a local Ray instance")
    parser.add_argument("--jobs", type=at_least_one, default=default_jobs, metavar="N", help=jobs_help)


def at_least_one(text: str) -> int:
    """A count of at least one (runs, trials, jobs)."""
    value = count(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, found {value}")
    return value


def fraction(what: str):
    """The argument type of a number in [0, 1], named `what` in its message."""
    def parse(text: str) -> float:
        value = number(text)
        if not 0 <= value <= 1:
            raise argparse.ArgumentTypeError(f"{what} in [0, 1], found {text}")
        return value
    return parse


def randomization(text: str):
    """A physical world's randomization, `friction=R,mass=R,pose=M`."""
    from symsynth.execution.physics import Randomization  # pybullet: only for the commands that ask

    try:
        return Randomization.parse(text)
    except InputError as error:
        raise argparse.ArgumentTypeError(str(error).removeprefix("--randomize: ")) from None


def executor(args: argparse.Namespace):
    """The executor the options name."""
    from symsynth.parallel import EXECUTORS

    if args.address is not None and args.executor != "ray":
        raise InputError("--address names a Ray cluster: give --executor ray with it")
    return EXECUTORS[args.executor](args.jobs, args.address)


PLANNER_HELP = "planner plugin (default: the scene's planner.name)"


def add_costmap_options(parser: argparse.ArgumentParser, *, planner_help: str = PLANNER_HELP,
                        seed_alias: bool = True) -> None:
    """--method, --planner, --costmap-seed and --no-cache: how a physical
    scene's costmap is obtained when it has none (`costmap_request`), the
    same options for every command.  `seed_alias`: also read --seed, the
    older spelling, where --seed means nothing else (solve, costmap)."""
    from symsynth.planning.methods import METHODS  # not for dfa and synth, which share count, etc.

    group = parser.add_argument_group("costmap options (physical scenes)",
                                      "how the costmap is obtained: from the cache, else by motion planning")
    group.add_argument("--method", choices=tuple(METHODS), default="recursive",
                       help="sg (start-goal, the paper's Alg. 2) or recursive (Alg. 3; default)")
    group.add_argument("--planner", metavar="NAME", help=planner_help)
    group.add_argument("--costmap-seed", type=count, metavar="S",
                       help="roadmap seed (default: the scene's planner.seed); same seed, same costmap")
    if seed_alias:
        group.add_argument("--seed", type=count, dest="costmap_seed", help=argparse.SUPPRESS)
    group.add_argument("--no-cache", action="store_true",
                       help="compute the costmap even if a cached one exists (it is then not cached)")


def costmap_request(args: argparse.Namespace, progress: bool = True) -> CostmapRequest:
    """The `problem.CostmapRequest` of `add_costmap_options`' options."""
    from symsynth.problem import CostmapRequest

    return CostmapRequest(args.method, args.planner, args.costmap_seed, not args.no_cache, progress)
