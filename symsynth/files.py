"""Output files written whole or not at all.

`write_atomic` writes to a temporary file in the target's folder, flushes
it to disk and renames it over the target: a reader sees the old file or the
new one, never half of one, and a write that fails (a full disk, a file size
limit, an interrupt) leaves the old file as it was and no temporary behind.
`atomic_output` does the same for writers that want a file name (images).

A target that is not a regular file (a terminal, `/dev/null`, `/dev/full`, a
pipe) is written directly: renaming over it would replace the device or the
pipe with a plain file.  Every `OSError` becomes an `InputError` naming the
file and what went wrong.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from symsynth.errors import InputError


def _special(path: Path) -> bool:
    """Whether `path` exists and is not a regular file (a device, a pipe)."""
    try:
        return not stat.S_ISREG(os.stat(path).st_mode)
    except OSError:
        return False


def write_atomic(path: str | Path, data: str | bytes, what: str) -> None:
    """Write `data` (text as UTF-8) to `path` whole or not at all."""
    content = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_output(path, what) as temporary:
        with open(temporary, "wb") as out:
            out.write(content)


@contextmanager
def atomic_output(path: str | Path, what: str) -> Iterator[Path]:
    """A file name to write to; on success it becomes `path` (module docstring)."""
    path = Path(path)
    if _special(path):
        try:
            yield path
        except OSError as error:
            raise InputError(f"cannot write {what} {path}: {error.strerror or error}") from None
        return
    try:
        handle, name = tempfile.mkstemp(dir=path.parent or Path("."), prefix=f".{path.name}.", suffix=".tmp")
        os.close(handle)
    except OSError as error:
        raise InputError(f"cannot write {what} {path}: {error.strerror or error}") from None
    temporary = Path(name)
    try:
        yield temporary
        with open(temporary, "rb") as done:
            os.fsync(done.fileno())
        os.chmod(temporary, 0o644 & ~_umask())
        os.replace(temporary, path)
    except OSError as error:
        raise InputError(f"cannot write {what} {path}: {error.strerror or error}") from None
    finally:
        if temporary.exists():
            temporary.unlink()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# -- input files ---------------------------------------------------------------------

def check_regular(path: str | Path, what: str, error: type[InputError] = InputError,
                  limit: int | None = None) -> None:
    """Refuse, before it is opened, an input that is no regular file: a
    named pipe with no writer blocks `open` for ever, a device (`/dev/zero`)
    never ends; and, with `limit`, a file of more than `limit` bytes.  A
    missing file is left to the reader, which names it."""
    try:
        info = os.stat(path)
    except OSError:
        return
    if not stat.S_ISREG(info.st_mode):
        kind = ("a folder" if stat.S_ISDIR(info.st_mode) else "a named pipe" if stat.S_ISFIFO(info.st_mode)
                else "a socket" if stat.S_ISSOCK(info.st_mode) else "a device")
        raise error(f"{what} {path} is {kind}, not a regular file: symsynth reads a {what} from a file only "
                    "(save it to one first)")
    if limit is not None and info.st_size > limit:
        raise error(f"{what} {path} is {info.st_size:,} bytes: larger than the {limit:,} symsynth reads")


def cache_dir() -> Path:
    """Where symsynth keeps what it computed for later runs (costmaps, the
    TLSF parser's tables): `$SYMSYNTH_CACHE`, else `$XDG_CACHE_HOME/symsynth`,
    else `~/.cache/symsynth`."""
    if os.environ.get("SYMSYNTH_CACHE"):
        return Path(os.environ["SYMSYNTH_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "symsynth"
