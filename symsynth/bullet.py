"""PyBullet, without its chatter on standard output.

PyBullet's C code prints "pybullet build time: ..." when imported and
"argv[0]=" when a client connects, straight to file descriptors 2 and 1
(where `--json` output goes).  `client()` opens a private DIRECT-mode client with
that descriptor pointed at /dev/null for the moment it takes.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections.abc import Iterator


_libc = ctypes.CDLL(None)


@contextlib.contextmanager
def _silenced_stdout() -> Iterator[None]:
    """File descriptors 1 and 2 to /dev/null for a moment."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    try:
        with open(os.devnull, "wb") as devnull:
            os.dup2(devnull.fileno(), 1)
            os.dup2(devnull.fileno(), 2)
        yield
    finally:
        _libc.fflush(None)  # C stdio buffers what it printed: drop it while 1 and 2 are /dev/null
        for fd, copy in zip((1, 2), saved):
            os.dup2(copy, fd)
            os.close(copy)


with _silenced_stdout():
    import pybullet  # noqa: E402  (the import prints its build time)
    from pybullet_utils import bullet_client  # noqa: E402


def client(gui: bool = False) -> bullet_client.BulletClient:
    """A new PyBullet client of its own: headless, or with a window
    (`gui=True`, which needs a display)."""
    if gui:
        if not os.environ.get("DISPLAY") and sys.platform.startswith("linux"):
            from symsynth.errors import SymsynthError

            raise SymsynthError("a window needs a display, and DISPLAY is not set; "
                                "leave --gui out (the simulation runs headless)")
        return bullet_client.BulletClient(connection_mode=pybullet.GUI)
    with _silenced_stdout():
        return bullet_client.BulletClient(connection_mode=pybullet.DIRECT)
