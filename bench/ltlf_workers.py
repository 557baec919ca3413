"""The LTLf benchmarks' processes: one worker process per tool (symsynth,
ltlf2dfa), killed and restarted on a timeout, its CPU time read from /proc;
MONA run and read back."""

from __future__ import annotations

import os
import re
import resource
import shutil
import signal
import subprocess
import threading
import time
import traceback
import multiprocessing as mp

MONA_FLAGS = ["-q", "-u", "-w"]  # as in ltlf2dfa.ltlf2dfa.invoke_mona
EXPLICIT_MAX = 256             # symsynth's to_explicit() is checked up to this many states
MONA_READ_LIMIT = 128 * 2**20  # bytes of MONA's -w output read back for simulation (Random/Syft
#                               syft_3/001: 39 MB; counters_05: 14 MB)


WARMUP = {
    "sym": "G(wa -> F wb) & X(wc U wd) & F last",
    "l2d": "G(wa -> F wb) & X(wc U wd) & F last",
}


def _worker(conn, tool):  # pragma: no cover - runs in the child
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)  # ltlf2dfa prints diagnostics on stdout
    try:
        if tool in ("sym", "sym-weak"):  # sym-weak: X is weak next (the synthesis datasets)
            from symsynth.automata import compile_ltlf
            semantics = "weak" if tool == "sym-weak" else "strong"

            def run(text):
                dfa = compile_ltlf(text, next_semantics=semantics)
                dfa.make_delta()  # (a backward DFA's transition bits: timed, as before they were made on use)
                return dfa
        else:
            from ltlf2dfa.parser.ltlf import LTLfParser

            def run(text):
                return LTLfParser()(text).to_dfa()
        result = run(WARMUP["sym" if tool == "sym-weak" else tool])
        if tool != "l2d":
            result.num_states
    except BaseException:
        conn.send(("fatal", traceback.format_exc()))
        return
    conn.send(("ready",))
    while True:
        req = conn.recv()
        if req is None:
            return
        text, reps, budget, traces = req
        times, result = [], None
        try:
            for _ in range(reps):
                c0, t0 = cpu_seconds(), time.perf_counter()
                fresh = run(text)
                dt = time.perf_counter() - t0
                conn.send(("cpu", cpu_seconds() - c0))
                result = fresh  # the previous result is freed here, outside the timing
                times.append(dt)
                conn.send(("tick", dt))
                if sum(times) + dt > budget:
                    break
            if tool != "l2d":
                conn.send(("states", result.num_states))
                conn.send(("accepts", [bool(result.accepts(t)) for t in traces]))
                conn.send(("explicit", result.to_explicit().num_states
                           if result.num_states <= EXPLICIT_MAX else None))
            else:
                conn.send(("dot", result))
        except Exception as error:
            conn.send(("error", f"{type(error).__name__}: {error}"))
        conn.send(("end",))


#: A run is stopped after `timeout` seconds of CPU time (the machine is
#: shared: the wall clock counts the other jobs' turns too), or after
#: WALL_FACTOR times that of wall time; the worker is checked every POLL s.
WALL_FACTOR = 3
POLL = 0.25  # (each check lists /proc for the worker's children: a few ms)
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds() -> float:
    """User and system CPU time of this process and of its waited-for
    children (MONA, run by ltlf2dfa): on a shared machine, the time a
    tool's work took, where the wall clock also counts the others' turns."""
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def _descendants(pid):
    children = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as fh:
                ppid = int(fh.read().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(ppid, []).append(int(entry))
    out, stack = [], [pid]
    while stack:
        for c in children.get(stack.pop(), ()):
            out.append(c)
            stack.append(c)
    return out


class Worker:
    def __init__(self, tool, timeout, wall=None):
        self.tool, self.timeout = tool, timeout
        self.wall = wall if wall is not None else WALL_FACTOR * timeout
        self.proc = self.conn = None

    def _start(self):
        ctx = mp.get_context("spawn")
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_worker, args=(child, self.tool), daemon=True)
        self.proc.start()
        child.close()
        if not self.conn.poll(max(120, self.timeout)):
            self.kill()
            raise RuntimeError(f"{self.tool} worker did not start")
        msg = self.conn.recv()
        if msg[0] != "ready":
            self.kill()
            raise RuntimeError(f"{self.tool} worker failed to start:\n{msg[1]}")

    def cpu(self) -> float:
        """CPU seconds of the worker and every process under it (MONA, when
        ltlf2dfa runs it), those it waited for included."""
        if self.proc is None:
            return 0.0
        total = 0.0
        for pid in [self.proc.pid, *_descendants(self.proc.pid)]:
            try:
                with open(f"/proc/{pid}/stat") as fh:
                    fields = fh.read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            total += sum(int(x) for x in fields[11:15]) / CLOCK_TICKS  # utime stime cutime cstime
        return total

    def kill(self):
        if self.proc is None:
            return
        for pid in _descendants(self.proc.pid):  # MONA runs in its own session
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self.proc.kill()
        self.proc.join(5)
        self.conn.close()
        self.proc = self.conn = None

    def close(self):
        if self.proc is not None:
            try:
                self.conn.send(None)
                self.proc.join(5)
            except OSError:
                pass
            self.kill()

    def run(self, text, reps, budget, traces=()):
        """-> dict(times=[...], timeout=bool, error=str|None, ...)."""
        if self.proc is None:
            self._start()
        out = {"times": [], "timeout": False, "error": None}
        self.conn.send((text, reps, budget, list(traces)))
        start = self.cpu()
        wall = time.monotonic() + self.wall
        while True:
            while not self.conn.poll(POLL) and (self.cpu() - start <= self.timeout and time.monotonic() <= wall):
                pass
            if not self.conn.poll():
                self.kill()
                if "states" in out:
                    out["error"] = f"post-processing (accepts/to_explicit) > {self.timeout:g} s"
                else:
                    out["timeout"] = True
                return out
            try:
                msg = self.conn.recv()
            except EOFError:
                self.kill()
                out["error"] = "worker died"
                return out
            kind = msg[0]
            if kind == "tick":
                out["times"].append(msg[1])
            elif kind == "end":
                return out
            elif kind == "error":
                out["error"] = msg[1]
            else:
                out[kind] = msg[1]


def _mona():
    return shutil.which("mona") or "/usr/bin/mona"


def time_mona(path, flags, reps, timeout, budget):
    """Median-able wall times of `mona FLAGS path`, output discarded."""
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        try:
            subprocess.run([_mona(), *flags, str(path)], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL, timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"times": times, "timeout": True}
        times.append(time.perf_counter() - t0)
        if sum(times) + times[-1] > budget:
            break
    return {"times": times, "timeout": False}


def read_mona(path, timeout, limit=MONA_READ_LIMIT, header_only=False):
    """MONA's `-w` output; only its header when `header_only` or when the
    whole automaton is longer than `limit` bytes (it lists every BDD path of
    every state).  -> (text or None on a timeout, complete)."""
    proc = subprocess.Popen([_mona(), *MONA_FLAGS, str(path)], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    fired = []
    timer = threading.Timer(timeout, lambda: (fired.append(1), proc.kill()))
    timer.start()
    lines, size, complete = [], 0, True
    try:
        for line in proc.stdout:
            lines.append(line)
            size += len(line)
            if (header_only and line.startswith("Transitions:")) or size > limit:
                complete = False
                break
    finally:
        timer.cancel()
        if proc.poll() is None:
            proc.kill()
        proc.stdout.close()
        proc.wait()
    if fired:
        return None, False
    return "".join(lines), complete


def mona_header(text):
    """The number of states in MONA's header (its state 0 included)."""
    m = re.search(r"Automaton has (\d+) states?", text or "")
    return int(m.group(1)) if m else None
