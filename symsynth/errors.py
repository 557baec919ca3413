"""The project's own exceptions.

Everything a user can get wrong (a formula, a file, an option) raises a
`SymsynthError`; the command line turns it into one message on stderr and
exit code 2.  Anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import BinaryIO


class SymsynthError(Exception):
    """Base of all errors caused by the user's input."""

    exit_code = 2


class LTLfSyntaxError(SymsynthError):
    """A formula that does not parse.

    The message names the source, line and column, shows the offending line
    with a caret under the mistake, and says what was expected there.
    """

    def __init__(self, source: str, line: int, column: int, context: str, expected: str):
        self.source = source
        self.line = line
        self.column = column
        self.context = context
        self.expected = expected
        super().__init__(f"{source}:{line}:{column}: syntax error: {expected}\n{context}")


class SymsynthWarning(UserWarning):
    """Something the user should know that does not stop the command (the
    command line prints it as one line on stderr)."""


class InputError(SymsynthError):
    """Bad input that is not a formula: a file that cannot be read, a bad option."""


def read_text(path: Path, what: str, error: type[InputError] = InputError,
              limit: int | None = None, regular: bool = False) -> str:
    """The UTF-8 text of the file `path`, line ends read as Python reads text
    (`\\r\\n` and `\\r` are `\\n`); a file that cannot be read, is not UTF-8
    or holds more than `limit` bytes raises `error` naming `what` it is
    ("scene", "costmap", ...).  No more than `limit` + 1 bytes are read, so
    a device or pipe without end (`/dev/zero`) is refused too.  A named
    pipe is opened without waiting for a writer (`open` would wait for ever
    when none comes) and one that gives nothing is refused.  With
    `regular`, anything but a regular file (a pipe, a device, a directory)
    is refused before it is read."""
    try:
        with _open_now(path) as file:
            info = os.fstat(file.fileno())
            if regular and not stat.S_ISREG(info.st_mode):
                raise error(f"{what} {path} is not a regular file (a pipe, a device or a directory): "
                            f"symsynth reads {what}s from regular files only")
            size = info.st_size  # 0 for devices and pipes
            if limit is not None and size > limit:
                raise error(f"{what} {path} is {size:,} bytes: larger than the {limit:,} symsynth reads")
            data = file.read() if limit is None else file.read(limit + 1)
    except OSError as problem:
        raise error(f"cannot read {what} {path}: {problem.strerror}") from None
    if not data and stat.S_ISFIFO(info.st_mode):
        raise error(f"{what} {path} is a named pipe and nothing was written to it (no writer had it open): "
                    f"symsynth reads a {what} from a file, or from a pipe that is being written")
    if limit is not None and len(data) > limit:
        raise error(f"{what} {path} is more than {limit:,} bytes: larger than the {limit:,} symsynth reads")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise error(f"{what} {path} is not UTF-8 text") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _open_now(path: Path) -> BinaryIO:
    """`open(path, "rb")` that does not wait: a named pipe is opened
    non-blocking (then reads from a writer as usual, and as empty without
    one), every other file as `open` does."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    try:
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)  # reads wait for what a writer sends
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
