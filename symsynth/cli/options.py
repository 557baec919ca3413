"""Argument types and checks shared by the subcommands: each turns bad input
into one message (argparse's usage error, or an `InputError`)."""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

from symsynth.errors import InputError


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


def positive(text: str) -> float:
    value = number(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be > 0, found {text}")
    return value


def check_writable(path: Path, what: str) -> None:
    """Fail now, not after minutes of work, if `path` cannot be written."""
    folder = path.parent
    if path.is_dir() or not folder.is_dir() or not os.access(folder, os.W_OK):
        raise InputError(f"cannot write {what} {path}: "
                         + ("it is a directory" if path.is_dir() else f"{folder} is not a writable directory"))


def size(text: str) -> tuple[int, int]:
    """`WIDTHxHEIGHT` in pixels, each side 16..8192."""
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT such as 800x600, found {text!r}") from None
    if not (16 <= width <= 8192 and 16 <= height <= 8192):
        raise argparse.ArgumentTypeError(f"each side must be 16..8192 pixels, found {text}")
    return width, height
