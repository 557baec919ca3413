"""Whether the compiled solver's layered solve ends within a time limit,
predicted from the layers explored so far (`Deadline`), so that
`solvers.compiled` hands a game it would not finish to the AND-OR search
(`solvers.andor`) while most of the limit is left.

Exploring (`packed.explore`) passes over each layer twice, from h = k down
to 0: once for the robot's moves (closing the layer), once for the
human's (seeding layer h - 1); layer 0 has the robot's pass only.  The
work is counted in nodes passed over, which on the pattern family cost
about the same each (6 x 8: 1.6-2.8 us per node and pass), and after each
batch the sizes of the closed layers are known and the growing one is at
least what it holds.  The prediction:

- layer sizes: the growing layer has at least `ratio` times the nodes of
  the one before, and each later layer grows over the one before it by
  half the excess over 1 of the step before (ratios r, 1 + (r - 1) / 2,
  1 + (r - 1) / 4, ...); `ratio` is the growth between
  the last two closed layers, or `FIRST_RATIO` while fewer than two are
  closed, raised to what the growing layer already shows.  Measured
  ratios: pattern 5 x 7 2.07, 1.10, 1.01; 6 x 8 2.36, 1.19, 1.02; sorting
  8 x 12 1.28, 1.04, 1.00.  So `FIRST_RATIO` assumes little (the human
  pass over layer k shows the real growth soon after), and the halving is
  slower than the fall measured;
- seconds: the seconds per node passed so far, times the passes left;
  solving then takes `SOLVE_SHARE` of exploring (measured 0.13-0.27 at
  pattern 5 x 7, 0.32-0.54 at 6 x 8, 0.20-0.26 for sorting 8 x 12; the
  reserve below covers the rest).

The layered solve goes on while it is predicted to end before the limit
less `RESERVE` of it, and stops when that time has passed: a prediction
that is too low costs the search the time spent, never its reserve.

Memory is predicted the same way: what the process has grown by since the
start, plus
the bytes per node the exploring has added so far times the nodes still
to come, with `SOLVE_BYTES` per node for the solve's own arrays.  When
that passes `MEMORY_SHARE` of the memory the machine had available at the
start (`available_memory`), the layered solve hands over too (once
`MEMORY_AFTER` nodes are explored, so that the growth per node is not the
arrays' first allocation): pattern
7 x 10 x k = 3 needs 12.9 GB for its layers, where the search that answers
in its place used about 2 GB.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence

import numpy as np

#: Growth of layer k - 1 over layer k assumed before it is seen (measured 1.28-2.36)
FIRST_RATIO = 1.3
#: Seconds of the bottom-up solve per second of exploring (measured 0.13-0.54; an uninterruptible
#: kernel call, so a solve above it eats into the reserve, never past the limit up to 0.56)
SOLVE_SHARE = 0.45
#: Share of the limit always left to the AND-OR search
RESERVE = 0.1
#: Share of the memory available at the start the layered solve may be predicted to use
MEMORY_SHARE = 0.8
#: Bytes per node of the bottom-up solve's own arrays (its values and choices, 8 + 4)
SOLVE_BYTES = 12
#: Nodes explored before memory is predicted: below, the arrays' first allocations
#: dominate what the process has grown by (and such a game needs little memory)
MEMORY_AFTER = 1_000_000


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation now: Linux's
    MemAvailable (free memory and the caches it may reclaim), else the free
    physical pages; None where the system says neither."""
    try:
        with open("/proc/meminfo") as meminfo:
            for line in meminfo:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def resident_memory() -> int:
    """Bytes of this process resident in memory now (0 where the system does not say)."""
    try:
        with open("/proc/self/statm") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


class HandOver(Exception):
    """The layered solve stops: it would not end in time (the message says why)."""


def layer_sizes(h: int, nodes: int, lo: np.ndarray, done: int) -> tuple[list[int], int]:
    """The nodes of layers k, k - 1, ... found so far (the last one growing)
    and the nodes passed over, from `explore`'s progress: `lo[j]` the first
    node of layer j (set for j >= h, and for h - 1 once layer h is closed
    and its human moves seed h - 1), `done` the end of the last batch."""
    k = len(lo) - 1
    sizes = [int(lo[j - 1] - lo[j]) for j in range(k, h, -1)]
    passed = 2 * sum(sizes) + done - int(lo[h])
    if h > 0 and lo[h - 1] > lo[h]:  # layer h closed: its human moves are seeding h - 1
        size = int(lo[h - 1] - lo[h])
        return sizes + [size, nodes - int(lo[h - 1])], passed + size
    return sizes + [nodes - int(lo[h])], passed


def predicted_sizes(sizes: Sequence[int], k: int) -> list[float]:
    """The nodes of all k + 1 layers, predicted from `layer_sizes` (module doc)."""
    closed, growing = list(sizes[:-1]), sizes[-1]
    ratio = closed[-1] / closed[-2] if len(closed) >= 2 and closed[-2] else FIRST_RATIO
    size = float(growing)
    if closed and closed[-1]:
        ratio = max(ratio, growing / closed[-1])
        size = max(size, ratio * closed[-1])
    out = [float(s) for s in closed] + [size]
    excess = max(ratio - 1.0, 0.0)
    while len(out) < k + 1:
        excess /= 2
        out.append(out[-1] * (1 + excess))
    return out


def passes(sizes: Sequence[float]) -> float:
    """The nodes passed over to explore layers of these sizes (k, ..., 0):
    two passes each, one for layer 0."""
    return 2 * sum(sizes) - sizes[-1]


class Deadline:
    """The layered solve's time: `check` after each batch, `check_solve`
    before the bottom-up solve; both raise `HandOver` when it would not end
    before `end` (the limit less its reserve)."""

    def __init__(self, limit: float, clock: Callable[[], float] | None = None, memory: int | None = None,
                 resident: Callable[[], int] | None = None):
        self.clock = time.perf_counter if clock is None else clock  # read now: tests patch it
        self.start = self.clock()
        self.limit = limit
        self.end = self.start + limit * (1 - RESERVE)
        self.explore_start = self.start  # `exploring` sets it when the exploring starts
        self.resident = resident_memory if resident is None else resident
        self.memory = available_memory() if memory is None else memory  # bytes; None: not known
        self.resident_start = self.resident_init = self.resident()

    def exploring(self) -> None:
        """The exploring starts now: its seconds and bytes per node are counted from here."""
        self.explore_start = self.clock()
        self.resident_start = self.resident()

    def left(self) -> float:
        """Seconds of the whole limit left (the reserve included)."""
        return self.start + self.limit - self.clock()

    def check(self, h: int, nodes: int, lo: np.ndarray, done: int) -> None:
        now = self.clock()
        if now > self.end:
            raise HandOver(f"was not done after {now - self.start:.1f} s ({nodes:,} nodes explored)")
        k = len(lo) - 1
        sizes, passed = layer_sizes(h, nodes, lo, done)
        predicted = predicted_sizes(sizes, k)
        seconds = (now - self.explore_start) * passes(predicted) / max(passed, 1) * (1 + SOLVE_SHARE)
        if self.explore_start + seconds > self.end:
            raise HandOver(f"was predicted to take about {seconds:.0f} s for {sum(predicted):,.0f} nodes "
                           f"(from {nodes:,} in {now - self.explore_start:.1f} s, layer h = {h} of {k})")
        self._check_memory(nodes, sum(predicted))

    def _check_memory(self, nodes: int, predicted: float) -> None:
        """`HandOver` when the layers are predicted to need more than their
        share of the memory available at the start (module doc)."""
        if self.memory is None or nodes < MEMORY_AFTER:
            return
        now = self.resident()
        per_node = max(now - self.resident_start, 0) / nodes
        # (what the process held at the start is outside the memory then available)
        need = max(now - self.resident_init, 0) + per_node * max(predicted - nodes, 0.0) + SOLVE_BYTES * predicted
        if need > MEMORY_SHARE * self.memory:
            raise HandOver(f"was predicted to need about {need / 1e9:.1f} GB for {predicted:,.0f} nodes, more "
                           f"than {MEMORY_SHARE:.0%} of the {self.memory / 1e9:.1f} GB available (from "
                           f"{nodes:,} nodes in {max(now - self.resident_start, 0) / 1e6:,.0f} MB)")

    def check_solve(self, explore_seconds: float, nodes: int) -> None:
        now = self.clock()
        if now + SOLVE_SHARE * explore_seconds > self.end:
            raise HandOver(f"explored its {nodes:,} nodes in {explore_seconds:.1f} s, too late to solve "
                           "them within the limit")
