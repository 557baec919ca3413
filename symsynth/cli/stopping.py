"""SIGTERM and Ctrl-C end `symsynth dfa` and `symsynth synth` at once, even
inside a long BDD operation.

The command line's handler (`symsynth.cli._signals`) is Python code: it
raises `Stopped` where the program is, so clean-ups run, but Python runs
it only between two bytecodes, and one CUDD call (a product, a
bisimulation step, a preimage) can last minutes: `timeout 60 symsynth
synth` on Double-Counter 08 was still running at 162 s.  A signal handler
cannot run inside CUDD, and no other thread can run while a CUDD call holds
the interpreter.  So while these commands compute (parse, compile, solve),
SIGTERM and SIGINT get their default action: the kernel ends the process
on the spot (exit status 128 + the signal's number in a shell).  That is
safe there: the computation holds no file open for writing, starts no
process and leaves nothing behind.  Around writing a file (`-o`, `--dot`)
the Python handler is back, so an interrupted write removes its temporary
file (`symsynth.files.write_atomic`).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

SIGNALS = (signal.SIGTERM, signal.SIGINT)


@contextmanager
def killable() -> Iterator[None]:
    """Inside the block SIGTERM and SIGINT end the process at once (their
    default action); the handlers before it are restored after.  A signal
    the process was started with ignored stays ignored (a shell starts a
    background job with SIGINT ignored, so that Ctrl-C at the terminal does
    not end it).  Only in the main thread (the others cannot set handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {signum: signal.signal(signum, signal.SIG_DFL) for signum in SIGNALS
           if signal.getsignal(signum) is not signal.SIG_IGN}
    try:
        yield
    finally:
        for signum, handler in old.items():
            signal.signal(signum, handler)
