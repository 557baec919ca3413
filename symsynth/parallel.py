"""Independent jobs on several processes: a local pool, or a Ray cluster.

An `Executor` maps a module-level function over items and yields
`(index, result)` as each job ends; `setup(*setup_args)` runs in a worker
before its jobs (a planner built once per worker, say).  Results do not
depend on where a job ran: callers put them back in item order.

- `LocalPool(workers)`: forked processes on this machine, killed with their
  parent (even by SIGKILL) and at once when the caller leaves the block;
- `RayCluster(workers, address)`: tasks of a Ray cluster (the optional
  extra `symsynth[ray]`); `address` joins a running cluster ("auto", or
  "HOST:PORT"), none starts a local one with `workers` CPUs, shut down at
  the end.  Every node needs symsynth installed at the same version.

`EXECUTORS` names them for the command line.
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
import signal
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, Protocol

from symsynth.errors import InputError

Setup = Callable[..., None] | None


class Executor(Protocol):
    workers: int

    def imap(self, fn: Callable[[Any], Any], items: Sequence[Any], setup: Setup = None,
             setup_args: tuple = ()) -> Iterator[tuple[int, Any]]: ...

    def __enter__(self) -> Executor: ...

    def __exit__(self, *exc) -> None: ...


def die_with_parent() -> None:
    """Ask Linux to send this process SIGKILL when its parent dies
    (prctl PR_SET_PDEATHSIG); elsewhere nothing happens."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        return
    if os.getppid() == 1:  # the parent died before the call
        os._exit(1)


def _start_local(setup: Setup, setup_args: tuple) -> None:
    """A local worker: killed with its parent, deaf to the terminal's Ctrl-C
    (the parent handles it and terminates the pool), ended by SIGTERM
    without a word, then the caller's setup."""
    die_with_parent()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the parent's handler, which it inherits
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _HELD)  # held by the parent while it forked
    if setup is not None:
        setup(*setup_args)


def _indexed(job: tuple[Callable, int, Any]) -> tuple[int, Any]:
    fn, i, item = job
    return i, fn(item)


class LocalPool:
    """Forked worker processes on this machine (one job in this process when
    `workers` is 1)."""

    def __init__(self, workers: int | None = None):
        self.workers = max(1, workers or os.cpu_count() or 1)

    def __enter__(self) -> LocalPool:
        return self

    def __exit__(self, *exc) -> None:
        return None

    def imap(self, fn, items, setup=None, setup_args=()):
        if self.workers == 1 or len(items) <= 1:
            if setup is not None:
                setup(*setup_args)
            for i, item in enumerate(items):
                yield i, fn(item)
            return
        context = multiprocessing.get_context("fork")
        # Leaving the block terminates the workers at once, also on an
        # interrupt (an executor's shutdown would wait for running jobs).
        with _held():
            pool = context.Pool(min(self.workers, len(items)), initializer=_start_local,
                                initargs=(setup, setup_args))
        with pool:
            yield from pool.imap_unordered(_indexed, [(fn, i, item) for i, item in enumerate(items)])


#: Signals held back while the pool forks its workers.
_HELD = {signal.SIGINT, signal.SIGTERM}


@contextmanager
def _held() -> Iterator[None]:
    """SIGINT and SIGTERM held back inside the block, delivered when it ends.
    Around a fork: the stop they raise would otherwise land in the fork's
    own hooks (logging's lock release, right after the child exists), where
    Python prints "Exception ignored" and goes on, and the command ran to
    its end instead of stopping (seen once in the signal tests, load 12)."""
    old = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _ray_job(fn, setup, setup_args, item):
    if setup is not None:
        setup(*setup_args)
    return fn(item)


class RayCluster:
    """Jobs as Ray tasks of one CPU each."""

    def __init__(self, workers: int | None = None, address: str | None = None):
        try:
            import ray
        except ImportError:
            raise InputError("the ray executor needs Ray: pip install 'symsynth[ray]'") from None
        self.ray = ray
        self.address = address
        self.workers = max(1, workers or os.cpu_count() or 1)
        self.started = False

    def __enter__(self) -> RayCluster:
        ray = self.ray
        if not ray.is_initialized():
            options: dict[str, Any] = {"include_dashboard": False, "log_to_driver": False,
                                       "configure_logging": False}
            if self.address is None:
                options["num_cpus"] = self.workers
            try:
                ray.init(address=self.address, **options)
            except (ConnectionError, ValueError, RuntimeError) as error:
                where = f"the Ray cluster at {self.address}" if self.address else "a local Ray instance"
                raise InputError(f"cannot start or join {where}: {error}") from None
            self.started = True
        return self

    def __exit__(self, *exc) -> None:
        if self.started:
            self.ray.shutdown()
            self.started = False

    def imap(self, fn, items, setup=None, setup_args=()):
        ray = self.ray
        remote = ray.remote(num_cpus=1, max_retries=0)(_ray_job)
        shared = ray.put(setup_args)
        pending = {remote.remote(fn, setup, shared, item): i for i, item in enumerate(items)}
        try:
            while pending:
                done, _ = ray.wait(list(pending), num_returns=1)
                for ref in done:
                    yield pending.pop(ref), ray.get(ref)
        finally:
            for ref in pending:
                ray.cancel(ref, force=True)


EXECUTORS: dict[str, Callable[[int | None, str | None], Executor]] = {
    "local": lambda workers, address: LocalPool(workers),
    "ray": lambda workers, address: RayCluster(workers, address),
}
