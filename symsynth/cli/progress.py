"""Progress bars for the LTLf subcommands, without importing tqdm unless one
can be shown: tqdm and what it loads (importlib.metadata, logging) cost
about 40 ms, a fifth of a `symsynth dfa` run, and its bars appear only on a
terminal anyway."""

from __future__ import annotations

import sys
from typing import Any


class Quiet:
    """What `bar` returns when stderr is no terminal: updates are counted
    and nothing is printed."""

    def __init__(self, total: float | None = None):
        self.n: float = 0
        self.total = total

    def update(self, done: float = 1) -> None:
        self.n += done

    def __enter__(self) -> Quiet:
        return self

    def __exit__(self, *_: object) -> None:
        return None


def bar(**options: Any) -> Any:
    """tqdm's bar on stderr (shown after `delay` seconds, removed when done)
    when stderr is a terminal, otherwise a `Quiet` one."""
    if not sys.stderr.isatty():
        return Quiet(options.get("total"))
    from tqdm import tqdm
    return tqdm(leave=False, **options)
