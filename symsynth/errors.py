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
    a device or pipe without end (`/dev/zero`) is refused too.  With
    `regular`, anything but a regular file (a named pipe, which would block
    in `open` until a writer comes, a device, a directory) is refused
    before it is read: it is opened without blocking and checked."""
    try:
        with _opened(path, regular) as file:
            if regular and not stat.S_ISREG(os.fstat(file.fileno()).st_mode):
                raise error(f"{what} {path} is not a regular file (a pipe, a device or a directory): "
                            f"symsynth reads {what}s from regular files only")
            size = os.fstat(file.fileno()).st_size  # 0 for devices and pipes
            if limit is not None and size > limit:
                raise error(f"{what} {path} is {size:,} bytes: larger than the {limit:,} symsynth reads")
            data = file.read() if limit is None else file.read(limit + 1)
    except OSError as problem:
        raise error(f"cannot read {what} {path}: {problem.strerror}") from None
    if limit is not None and len(data) > limit:
        raise error(f"{what} {path} is more than {limit:,} bytes: larger than the {limit:,} symsynth reads")
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise error(f"{what} {path} is not UTF-8 text") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")


def _opened(path: Path, nonblocking: bool) -> BinaryIO:
    """`path` opened for reading in binary; with `nonblocking`, without
    waiting for a writer when it is a named pipe (O_NONBLOCK, cleared again
    once open: a regular file ignores it)."""
    if not nonblocking:
        return open(path, "rb")
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    os.set_blocking(descriptor, True)
    return os.fdopen(descriptor, "rb")
