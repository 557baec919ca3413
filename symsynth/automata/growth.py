"""How far a compilation's explicit automata grow: a state limit with a
clean refusal, and a progress callback.

The explicit constructions (progression, the one-step invariants, the
explicit products) add states one by one; each calls `grew(size)` with the
size of the automaton it is building.  Inside `watched(max_states,
progress)` that refuses an automaton past `max_states` states with
`StateLimitReached` (an `InputError`: the command line prints it, exit 2)
and calls `progress(states)` with the states built so far in all, at most
every PROGRESS_EVERY seconds.  Outside it `grew` costs a context-variable
lookup.  A formula such as `F(a & X X ... X b)` (n nexts) has a minimal DFA
of 2^n + 1 states, all of them made explicitly: n = 18 takes 40 s and a
gigabyte, n = 23 would not end.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass

from symsynth.errors import InputError

#: Seconds between two progress calls.
PROGRESS_EVERY = 0.25


class StateLimitReached(InputError):
    """An explicit automaton of the compilation passed the state limit."""


@dataclass
class _Watch:
    max_states: int | None
    progress: Callable[[int], None] | None
    built: int = 0
    reported: float = 0.0


_watch: ContextVar[_Watch | None] = ContextVar("symsynth_growth", default=None)


@contextmanager
def watched(max_states: int | None = None,
            progress: Callable[[int], None] | None = None) -> Iterator[None]:
    """Within the block, explicit automata past `max_states` states (None:
    no limit) are refused, and `progress` hears of the states built."""
    token = _watch.set(_Watch(max_states, progress, reported=time.monotonic()))
    try:
        yield
    finally:
        _watch.reset(token)


def grew(size: int, added: int = 1) -> None:
    """`added` states added to an explicit automaton now of `size` states."""
    watch = _watch.get()
    if watch is None:
        return
    watch.built += added
    if watch.max_states is not None and size > watch.max_states:
        raise StateLimitReached(f"an automaton built for the formula passed {watch.max_states:,} states "
                                f"(the state limit; its minimal DFA may be smaller, but the construction "
                                f"lists every state)")
    if watch.progress is not None and (added > 1 or watch.built % 64 == 0):
        now = time.monotonic()
        if now - watch.reported >= PROGRESS_EVERY:
            watch.reported = now
            watch.progress(watch.built)
