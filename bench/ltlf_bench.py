#!/usr/bin/env python3
"""Benchmark: symsynth's LTLf -> DFA compiler against ltlf2dfa 2.0 and raw MONA.

    python bench/ltlf_bench.py [--quick] [--out FILE.md]

Families
  conj    G(a1 -> F b1) & ... & G(an -> F bn)          n = 1..10
  seq     F(a1 & X F(a2 & X F(... & X F(an))))          n = 1..10
  random  seeded random formulas over a, b, c, d (size-bounded; both tools'
          common operators: ! & | -> <-> X WX F G U R true false last)

For every formula:
  sym      in-process `compile_ltlf(text)`, median of REPS calls, in a worker
           process that has already compiled a warm-up formula (imports and
           grammar loading are excluded);
  l2d      in-process `LTLfParser()(text).to_dfa()`, median of REPS calls
           (ltlf2dfa's full pipeline: parser construction, MONA program, a
           MONA subprocess, sympy simplification of the guards, DOT text);
  MONA     wall time of `mona -q -u -w prog.mona` (the flags ltlf2dfa uses)
           on the exact program ltlf2dfa generates, output discarded, median
           of REPS runs; also without -w ("MONA no -w": the automaton is
           built but not printed; -w prints every BDD path of every state,
           which dominates for large conjunctions);
  states   symsynth's `num_states`; ltlf2dfa's DFA as drawn (its DOT:
           MONA's automaton without MONA's extra initial state 0); and
           "adj", the size of the minimal complete DFA of ltlf2dfa's
           language restricted to non-empty traces, computed exactly from its
           DFA (see README.md), which must equal symsynth's count;
  traces   random non-empty traces run through symsynth's DFA, ltlf2dfa's
           DOT (parsed and simulated; guards are sympy text over the atoms)
           and an independent position-indexed LTLf evaluator (the oracle).

Each call runs with a time limit (default 60 s): a blow-up is recorded as a
timeout ("TO"), and in the two scaling families the larger instances of a
tool that timed out are not run ("TO*", counted as timeouts).

Only the standard library is needed here; symsynth, ltlf2dfa (which needs
sympy and lark) and the `mona` binary must be installed.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing as mp
import os
import resource
import platform
import random
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE / "results" / "ltlf.md"
MONA_FLAGS = ["-q", "-u", "-w"]  # as in ltlf2dfa.ltlf2dfa.invoke_mona
TARGET_SPEEDUP = 10.0
EXPLICIT_MAX = 256             # symsynth's to_explicit() is checked up to this many states
MONA_READ_LIMIT = 128 * 2**20  # bytes of MONA's -w output read back for simulation (Random/Syft
#                               syft_3/001: 39 MB; counters_05: 14 MB)

# ---------------------------------------------------------------------------
# Formulas: a small tuple AST, printed for both tools, and an oracle
# ---------------------------------------------------------------------------
# ("ap", name) ("true",) ("false",) ("last",)
# (op, f) for op in ! X WX F G
# (op, f, g) for op in & | -> <-> U R

UNARY = ("!", "X", "WX", "F", "G")
BINARY = ("&", "|", "->", "<->", "U", "R")


def ap(name):
    return ("ap", name)


def text_of(node, top=True):
    """Text read identically by symsynth and ltlf2dfa.

    Unary operators bind tightest in both grammars; every binary
    subformula is parenthesized, so precedence and associativity (which
    differ: ltlf2dfa chains U/R to the left, symsynth to the right) never
    matter.  `X` is strong next in both (symsynth's default convention).
    """
    op = node[0]
    if op == "ap":
        return node[1]
    if op in ("true", "false", "last"):
        return op
    if op in UNARY:
        arg = text_of(node[1], top=False)
        if node[1][0] in BINARY and not arg.startswith("("):
            arg = f"({arg})"
        return f"!{arg}" if op == "!" else f"{op} {arg}"
    # & and | are associative in both grammars: print chains flat
    left = text_of(node[1], top=op in ("&", "|") and node[1][0] == op)
    right = text_of(node[2], top=False)
    s = f"{left} {op} {right}"
    return s if top else f"({s})"


sym_text = text_of   # symsynth grammar (grammars/ltlf.lark)
l2d_text = text_of   # ltlf2dfa grammar (ltlf2dfa/parser/ltlf.lark): lower-case atoms only


def atoms_of(node, out=None):
    out = {} if out is None else out
    if node[0] == "ap":
        out.setdefault(node[1], None)
    for child in node[1:]:
        if isinstance(child, tuple):
            atoms_of(child, out)
    return list(out)


def temporal_depth(node):
    kids = [temporal_depth(c) for c in node[1:] if isinstance(c, tuple)]
    here = 1 if node[0] in ("X", "WX", "F", "G", "U", "R") else 0
    return here + max(kids, default=0)


def oracle(node, trace):
    """Truth of `node` at position 0 of the non-empty `trace` (LTLf semantics,
    De Giacomo & Vardi 2013), by one backward pass per subformula."""
    return _values(node, trace)[0]


def _values(node, trace):
    n, op = len(trace), node[0]
    if op == "ap":
        return [node[1] in letter for letter in trace]
    if op == "true":
        return [True] * n
    if op == "false":
        return [False] * n
    if op == "last":
        return [i == n - 1 for i in range(n)]
    f = _values(node[1], trace)
    if op == "!":
        return [not v for v in f]
    if op == "X":
        return [i + 1 < n and f[i + 1] for i in range(n)]
    if op == "WX":
        return [i + 1 >= n or f[i + 1] for i in range(n)]
    if op in ("F", "G"):
        out, acc = [False] * n, op == "G"
        for i in range(n - 1, -1, -1):
            acc = (f[i] or acc) if op == "F" else (f[i] and acc)
            out[i] = acc
        return out
    g = _values(node[2], trace)
    if op == "&":
        return [x and y for x, y in zip(f, g)]
    if op == "|":
        return [x or y for x, y in zip(f, g)]
    if op == "->":
        return [(not x) or y for x, y in zip(f, g)]
    if op == "<->":
        return [x == y for x, y in zip(f, g)]
    out, acc = [False] * n, op == "R"
    for i in range(n - 1, -1, -1):
        if op == "U":
            acc = g[i] or (f[i] and acc)
        else:  # f R g: g holds up to and including the first f, or forever
            acc = g[i] and (f[i] or acc)
        out[i] = acc
    return out


def conj_formula(n):
    node = None
    for i in range(1, n + 1):
        part = ("G", ("->", ap(f"a{i}"), ("F", ap(f"b{i}"))))
        node = part if node is None else ("&", node, part)
    return node


def seq_formula(n):
    node = ap(f"a{n}")
    for i in range(n - 1, 0, -1):
        node = ("&", ap(f"a{i}"), ("X", ("F", node)))
    return ("F", node)


_UNARY_W = [("!", 2), ("X", 2), ("WX", 1), ("F", 3), ("G", 3)]
_BINARY_W = [("&", 3), ("|", 3), ("->", 2), ("<->", 1), ("U", 3), ("R", 2)]


def _pick(rng, weighted):
    total = sum(w for _, w in weighted)
    r = rng.uniform(0, total)
    for item, w in weighted:
        r -= w
        if r <= 0:
            return item
    return weighted[-1][0]


def random_formula(rng, size, atoms):
    """A formula with exactly `size` nodes."""
    if size <= 1:
        r = rng.random()
        if r < 0.05:
            return ("true",)
        if r < 0.09:
            return ("false",)
        if r < 0.15:
            return ("last",)
        return ap(rng.choice(atoms))
    if size == 2 or rng.random() < 0.4:
        return (_pick(rng, _UNARY_W), random_formula(rng, size - 1, atoms))
    left = rng.randint(1, size - 2)
    return (_pick(rng, _BINARY_W), random_formula(rng, left, atoms),
            random_formula(rng, size - 1 - left, atoms))


def random_family(count, seed, max_size=13):
    rng = random.Random(seed)
    atoms = ["a", "b", "c", "d"]
    seen, out = set(), []
    while len(out) < count:
        node = random_formula(rng, rng.randint(2, max_size), atoms)
        key = text_of(node)
        if key not in seen:
            seen.add(key)
            out.append(node)
    return out


def make_traces(rng, atoms, depth, count):
    """Random non-empty traces; every single-letter trace first when few."""
    traces = []
    if 2 ** len(atoms) <= 16:
        for bits in range(2 ** len(atoms)):
            traces.append([frozenset(a for k, a in enumerate(atoms) if bits >> k & 1)])
    lmax = min(24, max(6, 2 * depth + 3))
    while len(traces) < count:
        length = rng.randint(1, lmax)
        p = rng.choice((0.15, 0.5, 0.85))
        traces.append([frozenset(a for a in atoms if rng.random() < p) for _ in range(length)])
    return traces[:count]


# ---------------------------------------------------------------------------
# ltlf2dfa's and MONA's automata: parsing, simulation, state counts
# ---------------------------------------------------------------------------

@dataclass
class Auto:
    """A complete DFA read off ltlf2dfa's DOT or MONA's output."""
    start: int
    accepting: set
    rows: dict            # state -> list of (predicate(letter) -> bool, target)
    signature: dict       # state -> hashable; equal iff equal transition functions
    source: str           # "dot" or "mona"

    def run(self, trace):
        state = self.start
        for letter in trace:
            for pred, target in self.rows.get(state, ()):
                if pred(letter):
                    state = target
                    break
            else:
                raise ValueError(f"no transition from {state} on {sorted(letter)}")
        return state in self.accepting

    def reachable(self, roots):
        seen, stack = set(roots), list(roots)
        while stack:
            for _, t in self.rows.get(stack.pop(), ()):
                if t not in seen:
                    seen.add(t)
                    stack.append(t)
        return seen

    def counts(self):
        """(states as drawn, minimal complete DFA size over non-empty traces).

        The automaton is MONA's minimal DFA of L' (ltlf2dfa's language, where
        the empty trace counts), started after MONA's state 0.  Over non-empty
        traces the language is L = L' minus the empty trace.  The residuals of
        L after non-empty words are those of L' (the states S reachable by a
        non-empty word, pairwise distinct by minimality); the residual of L at
        the empty word is L itself.  So |min DFA(L)| = |S| + [L not a residual
        of S].  If the start state rejects, L = L' and the answer is the drawn
        size.  Otherwise a state q in S has residual L iff q rejects and q has
        exactly the start state's transitions (same successor on each letter,
        by minimality), which is a comparison of MONA's canonical BDD paths.
        """
        drawn = self.reachable([self.start])
        if self.start not in self.accepting:
            return len(drawn), len(drawn)
        after = self.reachable({t for _, t in self.rows.get(self.start, ())})
        sig = self.signature[self.start]
        twin = any(q not in self.accepting and self.signature.get(q) == sig for q in after)
        return len(drawn), len(after) + (0 if twin else 1)


_TOKEN = re.compile(r"\s*(?:([A-Za-z_][A-Za-z0-9_]*)|(.))")


def compile_guard(text):
    """A sympy guard as ltlf2dfa prints it (`~a & b | c`, `true`, lower-cased)
    -> predicate over a letter (set of true atoms)."""
    tokens = [m.group(1) or m.group(2) for m in _TOKEN.finditer(text) if (m.group(1) or m.group(2))]
    pos = 0

    def peek():
        return tokens[pos] if pos < len(tokens) else None

    def take(expected=None):
        nonlocal pos
        tok = peek()
        if expected is not None and tok != expected:
            raise ValueError(f"guard {text!r}: expected {expected!r}, got {tok!r}")
        pos += 1
        return tok

    def disj():
        parts = [conj()]
        while peek() == "|":
            take()
            parts.append(conj())
        return parts[0] if len(parts) == 1 else (lambda s, p=parts: any(q(s) for q in p))

    def conj():
        parts = [unary()]
        while peek() == "&":
            take()
            parts.append(unary())
        return parts[0] if len(parts) == 1 else (lambda s, p=parts: all(q(s) for q in p))

    def unary():
        if peek() == "~":
            take()
            inner = unary()
            return lambda s: not inner(s)
        return primary()

    def primary():
        tok = take()
        if tok == "(":
            inner = disj()
            take(")")
            return inner
        if tok == "true":
            return lambda s: True
        if tok == "false":
            return lambda s: False
        if tok is None or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", tok):
            raise ValueError(f"guard {text!r}: unexpected {tok!r}")
        if peek() == "(":  # sympy function form: xor, equivalent, implies, ite, not, and, or
            take("(")
            args = [disj()]
            while peek() == ",":
                take()
                args.append(disj())
            take(")")
            fn = {
                "xor": lambda v: sum(v) % 2 == 1,
                "equivalent": lambda v: all(v) or not any(v),
                "implies": lambda v: (not v[0]) or v[1],
                "ite": lambda v: v[1] if v[0] else v[2],
                "not": lambda v: not v[0],
                "and": all, "or": any,
            }.get(tok)
            if fn is None:
                raise ValueError(f"guard {text!r}: unknown function {tok!r}")
            return lambda s, a=args, f=fn: f([q(s) for q in a])
        return lambda s, name=tok: name in s

    result = disj()
    if pos != len(tokens):
        raise ValueError(f"guard {text!r}: trailing {tokens[pos:]!r}")
    return result


def parse_l2d_dot(dot):
    start, accepting, rows, sig = None, set(), {}, {}
    for line in dot.splitlines():
        s = line.strip()
        if s.startswith("node [shape = doublecircle]"):
            accepting = {int(x) for x in re.findall(r"\d+", s.split("]", 1)[1])}
            continue
        m = re.fullmatch(r"init -> (\d+);", s)
        if m:
            start = int(m.group(1))
            continue
        m = re.fullmatch(r'(\d+) -> (\d+) \[label="(.*)"\];', s)
        if m:
            src, dst, guard = int(m.group(1)), int(m.group(2)), m.group(3)
            rows.setdefault(src, []).append((compile_guard(guard), dst))
            sig.setdefault(src, set()).add((guard, dst))
    if start is None:
        raise ValueError("no initial state in ltlf2dfa's DOT")
    return Auto(start, accepting, rows, {k: frozenset(v) for k, v in sig.items()}, "dot")


def _pattern_pred(variables, pattern):
    need = [(v, c == "1") for v, c in zip(variables, pattern) if c in "01"]
    return lambda s: all((v in s) == want for v, want in need)


def parse_mona(output):
    """MONA's `-w` automaton; the trace starts after state 0's dummy letter."""
    m = re.search(r"DFA for formula with free variables:[ \t]*(.*)", output)
    if not m:
        raise ValueError("no automaton in MONA's output")
    variables = [v.lower() for v in m.group(1).split()]
    m = re.search(r"Accepting states:[ \t]*(.*)", output)
    accepting = {int(x) for x in m.group(1).split()} if m else set()
    rows, sig = {}, {}
    for sm in re.finditer(r"^State (\d+): ([01X]*) -> state (\d+)", output, re.M):
        src, pattern, dst = int(sm.group(1)), sm.group(2), int(sm.group(3))
        rows.setdefault(src, []).append((_pattern_pred(variables, pattern), dst))
        sig.setdefault(src, []).append((pattern, dst))
    initial = int(re.search(r"Initial state:[ \t]*(\d+)", output).group(1))
    targets = {t for _, t in rows.get(initial, ())}
    if len(targets) != 1:
        raise ValueError(f"MONA's initial state branches on the dummy letter: {targets}")
    return Auto(targets.pop(), accepting, rows, {k: tuple(v) for k, v in sig.items()}, "mona")


# ---------------------------------------------------------------------------
# Workers: one process per tool, killed and restarted on a timeout
# ---------------------------------------------------------------------------

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
                return compile_ltlf(text, next_semantics=semantics)
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


# ---------------------------------------------------------------------------
# The benchmark
# ---------------------------------------------------------------------------

@dataclass
class Row:
    family: str
    label: str
    node: tuple
    text: str
    sym: dict = field(default_factory=dict)
    l2d: dict = field(default_factory=dict)
    mona: dict = field(default_factory=dict)
    mona_now: dict = field(default_factory=dict)   # MONA without -w
    mona_nonempty: int | None = None
    sym_states: int | None = None
    sym_explicit: int | None = None
    l2d_drawn: int | None = None
    l2d_adj: int | None = None
    l2d_source: str = ""
    n_traces: int = 0
    agree: int | None = None           # traces where symsynth and ltlf2dfa agree
    sym_wrong: int | None = None       # traces where symsynth differs from the oracle
    l2d_wrong: int | None = None
    example: str = ""
    notes: list = field(default_factory=list)

    def med(self, tool):
        data = getattr(self, tool)
        return statistics.median(data["times"]) if data.get("times") and not data.get("timeout") else None


class Bench:
    def __init__(self, args):
        self.args = args
        self.sym = Worker("sym", args.timeout)
        self.l2d = Worker("l2d", args.timeout)
        from ltlf2dfa.base import MonaProgram
        from ltlf2dfa.parser.ltlf import LTLfParser
        self.MonaProgram, self.LTLfParser = MonaProgram, LTLfParser
        self.parser = LTLfParser()
        self.workdir = tempfile.mkdtemp(prefix="ltlf_bench_")

    def close(self):
        self.sym.close()
        self.l2d.close()
        shutil.rmtree(self.workdir, ignore_errors=True)

    def measure(self, row, rng, skip_l2d=None, skip_sym=None):
        a = self.args
        atoms = atoms_of(row.node)
        traces = make_traces(rng, atoms, temporal_depth(row.node), a.traces)
        row.n_traces = len(traces)
        truth = [oracle(row.node, t) for t in traces]

        # symsynth
        if skip_sym:
            row.sym = {"times": [], "timeout": True, "skipped": skip_sym}
        else:
            row.sym = self.sym.run(sym_text(row.node), a.reps, a.budget, traces)
        sym_acc = row.sym.get("accepts")
        row.sym_states = row.sym.get("states")
        row.sym_explicit = row.sym.get("explicit")
        if row.sym.get("error"):
            row.notes.append(f"symsynth: {row.sym['error']}")

        # ltlf2dfa full pipeline
        if skip_l2d:
            row.l2d = {"times": [], "timeout": True, "skipped": skip_l2d}
        else:
            row.l2d = self.l2d.run(l2d_text(row.node), a.reps, a.budget)
        if row.l2d.get("error"):
            row.notes.append(f"ltlf2dfa: {row.l2d['error']}")

        # raw MONA on ltlf2dfa's program: as ltlf2dfa runs it (-w prints the
        # whole automaton), and without -w (the automaton is only built)
        program = self.MonaProgram(self.parser(l2d_text(row.node))).mona_program()
        path = Path(self.workdir) / "prog.mona"
        path.write_text(program, encoding="utf-8")
        row.mona = time_mona(path, MONA_FLAGS, a.reps, a.timeout, a.budget)
        row.mona_now = time_mona(path, [f for f in MONA_FLAGS if f != "-w"], a.reps,
                                 a.timeout, a.budget)
        # The same program restricted to non-empty traces: MONA's own minimal
        # DFA of symsynth's language (plus MONA's state 0), a cross-check of "adj".
        nonempty = Path(self.workdir) / "prog_nonempty.mona"
        nonempty.write_text(program + "0 in $;\n", encoding="utf-8")
        text, _ = read_mona(nonempty, a.timeout, header_only=True)
        n_ne = mona_header(text)
        row.mona_nonempty = None if n_ne is None else max(1, n_ne - 1)

        # ltlf2dfa's automaton: its DOT when it finished, else MONA's own output
        auto = None
        try:
            if row.l2d.get("dot"):
                auto = parse_l2d_dot(row.l2d["dot"])
            else:
                text, complete = read_mona(path, a.timeout)
                if text and complete:
                    auto = parse_mona(text)
                elif text and mona_header(text):
                    row.l2d_source = "h"
                    row.l2d_drawn = mona_header(text) - 1
                    row.l2d_adj = row.mona_nonempty
                    row.notes.append("MONA's automaton too large to read back: counts from "
                                     "its header, no trace check against ltlf2dfa")
                else:
                    row.notes.append("MONA timed out printing the automaton")
        except ValueError as error:
            row.notes.append(f"cannot read ltlf2dfa's automaton: {error}")
        if auto is not None:
            row.l2d_source = auto.source
            row.l2d_drawn, row.l2d_adj = auto.counts()
            if row.mona_nonempty is not None and row.mona_nonempty != row.l2d_adj:
                row.notes.append(f"adj {row.l2d_adj} but MONA on the non-empty program has "
                                 f"{row.mona_nonempty} states after its state 0")
            try:
                l2d_acc = [auto.run(t) for t in traces]
            except ValueError as error:
                row.notes.append(f"ltlf2dfa automaton incomplete: {error}")
                l2d_acc = None
        else:
            l2d_acc = None

        if l2d_acc is not None:
            row.l2d_wrong = sum(x != y for x, y in zip(l2d_acc, truth))
        if sym_acc is not None:
            row.sym_wrong = sum(x != y for x, y in zip(sym_acc, truth))
        if sym_acc is not None and l2d_acc is not None:
            row.agree = sum(x == y for x, y in zip(sym_acc, l2d_acc))
        for i, t in enumerate(traces):
            s = sym_acc[i] if sym_acc is not None else truth[i]
            l = l2d_acc[i] if l2d_acc is not None else truth[i]
            if s != truth[i] or l != truth[i]:
                word = " ".join("{" + ",".join(sorted(x)) + "}" for x in t)
                row.example = f"trace `{word}`: symsynth {s}, ltlf2dfa {l}, oracle {truth[i]}"
                break
        if row.sym_states is not None and row.sym_explicit is not None \
                and row.sym_states != row.sym_explicit:
            row.notes.append(f"symsynth num_states {row.sym_states} != to_explicit() {row.sym_explicit}")

    def scaling_family(self, name, build, ns):
        rows, to = [], {"sym": None, "l2d": None}
        for n in ns:
            node = build(n)
            row = Row(name, str(n), node, sym_text(node))
            rng = random.Random(f"{self.args.seed}/{name}/{n}")
            skip = {k: (f"n={v} timed out" if v is not None and not self.args.no_skip else None)
                    for k, v in to.items()}
            t0 = time.perf_counter()
            self.measure(row, rng, skip_l2d=skip["l2d"], skip_sym=skip["sym"])
            for k in to:
                if to[k] is None and getattr(row, k).get("timeout"):
                    to[k] = n
            rows.append(row)
            log(f"  {name} n={n:<2} {fmt_row_short(row)}  [{time.perf_counter() - t0:.1f} s]")
        return rows

    def random_family(self, count):
        rows = []
        for i, node in enumerate(random_family(count, self.args.seed)):
            row = Row("random", str(i + 1), node, sym_text(node))
            self.measure(row, random.Random(f"{self.args.seed}/random/{i}"))
            rows.append(row)
            if (i + 1) % 20 == 0 or i + 1 == count:
                log(f"  random {i + 1}/{count} {fmt_row_short(row)}")
        return rows

    def cold(self, text):
        """Cold command-line runs, once: symsynth's CLI, ltlf2dfa's CLI."""
        timeout = self.args.timeout
        exe = Path(sys.executable).parent
        sym_cmd = ([str(exe / "symsynth")] if (exe / "symsynth").exists()
                   else [sys.executable, "-m", "symsynth.cli"]) + ["dfa", text]
        path = Path(self.workdir) / "formula.ltlf"
        path.write_text(text, encoding="utf-8")
        l2d_cmd = ([str(exe / "ltlf2dfa")] if (exe / "ltlf2dfa").exists()
                   else [sys.executable, "-m", "ltlf2dfa"]) + ["-l", "ltlf", "-f", str(path)]
        out = {}
        for key, cmd in (("sym", sym_cmd), ("l2d", l2d_cmd)):
            t0 = time.perf_counter()
            try:
                proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout,
                                      cwd=self.workdir, start_new_session=True)
                out[key] = time.perf_counter() - t0 if proc.returncode == 0 else f"exit {proc.returncode}"
            except subprocess.TimeoutExpired:
                out[key] = None
        return out


def log(msg):
    print(msg, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def fmt_ms(seconds):
    if seconds is None:
        return "-"
    ms = seconds * 1000
    if ms >= 100:
        return f"{ms:.0f}"
    if ms >= 10:
        return f"{ms:.1f}"
    return f"{ms:.2f}"


REPS = 5  # set from the arguments in main()


def fmt_time(data):
    if data.get("skipped"):
        return "TO*"
    if data.get("timeout"):
        return "TO"
    if not data.get("times"):
        return "err" if data.get("error") else "-"
    s = fmt_ms(statistics.median(data["times"]))
    return s if len(data["times"]) >= REPS else f"{s} ({len(data['times'])}x)"


def ratio(row, other, timeout):
    """(value, is_lower_bound) of other/sym, or None."""
    sym = row.med("sym")
    if sym is None or sym <= 0:
        return None
    data = getattr(row, other)
    if data.get("timeout"):
        return timeout / sym, True
    val = row.med(other)
    return (val / sym, False) if val is not None else None


def fmt_ratio(r):
    if r is None:
        return "-"
    value, lower = r
    s = f"{value:.0f}x" if value >= 100 else f"{value:.1f}x" if value >= 1 else f"{value:.2f}x"
    return (">" + s) if lower else s


def fmt_states(row):
    sym = "-" if row.sym_states is None else str(row.sym_states)
    if row.l2d_drawn is None:
        return sym, "-", "-"
    mark = {"dot": "", "mona": " (m)", "h": " (h)"}.get(row.l2d_source, "")
    adj = str(row.l2d_adj)
    if row.sym_states is not None and row.sym_states != row.l2d_adj:
        adj = f"**{adj}** ≠"
    return sym, f"{row.l2d_drawn}{mark}", adj


def fmt_traces(row):
    if row.sym_wrong is None and row.l2d_wrong is None:
        return "-"
    bad = []
    if row.sym_wrong:
        bad.append(f"sym wrong {row.sym_wrong}")
    if row.l2d_wrong:
        bad.append(f"l2d wrong {row.l2d_wrong}")
    if row.agree is not None:
        head = f"{row.agree}/{row.n_traces}"
    else:
        head = f"{row.n_traces - (row.sym_wrong or 0)}/{row.n_traces} vs oracle"
    return f"**{head}** ({', '.join(bad)})" if bad else head


def fmt_row_short(row):
    return (f"sym {fmt_time(row.sym)} ms, l2d {fmt_time(row.l2d)} ms, "
            f"mona {fmt_time(row.mona)} ms, states {row.sym_states}/{row.l2d_adj}"
            + (" DISAGREE" if (row.sym_wrong or row.l2d_wrong) else ""))


HEADER = ("| {k} | formula | symsynth ms | ltlf2dfa ms | MONA ms | MONA no -w ms | ltlf2dfa/sym "
          "| MONA/sym | states sym | l2d drawn | l2d adj | traces agree |")
RULE = "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"


def table(rows, key, timeout, shorten=None):
    out = [HEADER.format(k=key), RULE]
    for r in rows:
        text = r.text if shorten is None or len(r.text) <= shorten else r.text[:shorten - 1] + "…"
        s, d, a = fmt_states(r)
        text = text.replace("|", "\\|")  # a table cell, even in a code span
        out.append(f"| {r.label} | `{text}` | {fmt_time(r.sym)} | {fmt_time(r.l2d)} "
                   f"| {fmt_time(r.mona)} | {fmt_time(r.mona_now)} "
                   f"| {fmt_ratio(ratio(r, 'l2d', timeout))} "
                   f"| {fmt_ratio(ratio(r, 'mona', timeout))} | {s} | {d} | {a} | {fmt_traces(r)} |")
    return out


def speedup_verdict(rows, timeout):
    """PASS iff every row's ltlf2dfa/symsynth >= 10 (a timeout is a lower bound)."""
    failing = []
    for r in rows:
        rt = ratio(r, "l2d", timeout)
        if r.l2d.get("error") and not r.l2d.get("times") and not r.l2d.get("timeout"):
            continue  # ltlf2dfa crashed: nothing to compare
        if rt is None or rt[0] < TARGET_SPEEDUP:
            failing.append(r)
    return failing


def summary_stats(values):
    if not values:
        return "-"
    gm = math.exp(statistics.fmean(math.log(v) for v in values))
    return (f"median {statistics.median(values):.1f}x, geo-mean {gm:.1f}x, "
            f"min {min(values):.2f}x, max {max(values):.0f}x")


def report(results, meta, args):
    timeout = args.timeout
    lines, verdicts = [], []
    lines += ["# LTLf -> DFA: symsynth vs ltlf2dfa 2.0 vs raw MONA", ""]
    lines += [f"- {k}: {v}" for k, v in meta.items()]
    lines += ["",
              "Times are medians in milliseconds (`(kx)`: only k calls fit the per-formula budget). "
              "`TO`: a call exceeded the per-call limit; `TO*`: not run because a smaller instance "
              "of the same family timed out (counted as a timeout). A ratio `>Nx` is a lower bound "
              "from a timeout. `l2d drawn`: states of ltlf2dfa's DFA (MONA's automaton without its "
              "initial state 0, sink included); `(m)`: read from MONA's output because ltlf2dfa "
              "itself timed out; `(h)`: only MONA's header could be read (its full output is too "
              "large), and `adj` is then MONA's count for the program with `0 in $` added. `l2d adj`: the minimal complete DFA of ltlf2dfa's language "
              "restricted to non-empty traces, which must equal `states sym` (bold when it does not). "
              "`traces agree`: random non-empty traces on which both DFAs agree; any trace where "
              "a tool differs from the independent oracle is counted as `wrong`.", ""]

    for fam, rows in results.items():
        if fam == "cold":
            continue
        title = {"conj": "Conjunctions `G(a1 -> F b1) & ... & G(an -> F bn)`",
                 "seq": "Nested sequences `F(a1 & X F(a2 & X F(... & X F(an))))`",
                 "random": f"Random formulas ({len(rows)}, seed {args.seed})"}[fam]
        lines += [f"## {title}", ""]
        lines += table(rows, "n" if fam != "random" else "#", timeout,
                       shorten=70 if fam != "random" else None)
        lines.append("")
        cold = results.get("cold", {}).get(fam)
        if cold:
            label, c = cold

            def cfmt(v):
                return "timeout" if v is None else v if isinstance(v, str) else f"{v * 1000:.0f} ms"
            lines += [f"Cold command line, once, on {label}: `symsynth dfa` {cfmt(c['sym'])}; "
                      f"`ltlf2dfa -l ltlf -f` (prints MONA's DFA, no sympy step) {cfmt(c['l2d'])}.", ""]

        l2d_r = [ratio(r, "l2d", timeout) for r in rows]
        mona_r = [ratio(r, "mona", timeout) for r in rows]
        if fam == "random":
            lines += ["Summary:", ""]
            lines.append(f"- ltlf2dfa/symsynth (finished rows): "
                         f"{summary_stats([x[0] for x in l2d_r if x and not x[1]])}")
            lines.append(f"- MONA/symsynth: {summary_stats([x[0] for x in mona_r if x and not x[1]])}")
        n_to = {t: sum(1 for r in rows if getattr(r, t).get("timeout")) for t in ("sym", "l2d", "mona")}
        n_skip = {t: sum(1 for r in rows if getattr(r, t).get("skipped")) for t in ("sym", "l2d")}
        n_err = {t: sum(1 for r in rows if getattr(r, t).get("error")) for t in ("sym", "l2d")}
        dis = [r for r in rows if r.sym_wrong or r.l2d_wrong or (r.agree is not None and r.agree != r.n_traces)]
        smis = [r for r in rows if r.sym_states is not None and r.l2d_adj is not None
                and r.sym_states != r.l2d_adj]
        unchecked = [r for r in rows if r.sym_wrong is None]
        no_l2d = [r for r in rows if r.l2d_wrong is None]
        lines.append(f"- timeouts: symsynth {n_to['sym']}" + (f" ({n_skip['sym']} not run)" if n_skip['sym'] else "")
                     + f", ltlf2dfa {n_to['l2d']}" + (f" ({n_skip['l2d']} not run)" if n_skip['l2d'] else "")
                     + f", MONA -w {n_to['mona']}; "
                     f"errors: symsynth {n_err['sym']}, ltlf2dfa {n_err['l2d']}")
        lines.append(f"- rows with trace disagreements: {len(dis)}; state-count mismatches "
                     f"(sym vs l2d adj): {len(smis)}; rows where symsynth was not checked on traces: "
                     f"{len(unchecked)}; where ltlf2dfa's DFA was not: {len(no_l2d)}")
        slow = sorted((r for r in rows if r.med("sym") is not None), key=lambda r: -r.med("sym"))[:5]
        if fam == "random" and slow:
            lines.append("- slowest for symsynth: " + "; ".join(
                f"#{r.label} `{r.text}` {fmt_ms(r.med('sym'))} ms" for r in slow))
        failing = speedup_verdict(rows, timeout)
        if failing:
            lines.append(f"- below {TARGET_SPEEDUP:.0f}x vs ltlf2dfa: " + "; ".join(
                f"{'n=' if fam != 'random' else '#'}{r.label} `{r.text[:60]}` "
                f"{fmt_ratio(ratio(r, 'l2d', timeout))}" for r in failing[:15])
                + (" …" if len(failing) > 15 else ""))
        for r in (dis + smis)[:20]:
            lines.append(f"- {'n=' if fam != 'random' else '#'}{r.label} `{r.text[:90]}`: "
                         f"states sym {r.sym_states}, l2d adj {r.l2d_adj}; {r.example or 'no trace differs'}")
        for r in rows:
            for note in r.notes:
                lines.append(f"- {'n=' if fam != 'random' else '#'}{r.label}: {note}")
        if fam == "conj":
            last = [r for r in rows if r.label == "10"]
            if last:
                r = last[0]
                s, m = r.med("sym"), r.med("mona")
                ok = s is not None and m is not None and s <= m
                if r.mona.get("timeout"):
                    ok = s is not None
                verdicts.append((ok, f"[conj n=10] symsynth no slower than raw MONA as ltlf2dfa runs it "
                                     f"(-q -u -w) (symsynth {fmt_time(r.sym)} ms, MONA "
                                     + (f"timed out > {timeout:g} s)" if r.mona.get("timeout")
                                        else f"{fmt_time(r.mona)} ms)")))
                m2 = r.med("mona_now")
                lines.append(f"- conj n=10 against MONA without -w (automaton built, not printed): "
                             f"symsynth {fmt_time(r.sym)} ms, MONA {fmt_time(r.mona_now)} ms"
                             + (f" (MONA/symsynth {m2 / s:.2f}x)" if s and m2 else ""))
        lines.append("")

        verdicts.append((not failing,
                         f"[{fam}] symsynth >= {TARGET_SPEEDUP:.0f}x faster than ltlf2dfa's full pipeline "
                         f"on every formula ({len(rows) - len(failing)}/{len(rows)} rows; min "
                         f"{fmt_ratio(min((x for x in l2d_r if x), default=None, key=lambda x: x[0]))})"))
        verdicts.append((not dis and not smis and not unchecked,
                         f"[{fam}] check: DFAs agree on all traces and state counts match "
                         f"({len(dis)} disagreeing rows, {len(smis)} count mismatches, "
                         f"{len(unchecked)} unchecked; {len(no_l2d)} rows with ltlf2dfa's DFA "
                         f"too large to simulate, symsynth checked against the oracle only)"))

    lines += ["## Targets and checks", "", "```"]
    lines += [f"{'PASS' if ok else 'FAIL'} {msg}" for ok, msg in verdicts]
    lines += ["```", ""]
    return "\n".join(lines), verdicts


def environment(args, bench):
    meta = {}
    meta["date"] = time.strftime("%Y-%m-%d %H:%M:%S %Z")
    meta["machine"] = f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.platform()}"
    meta["python"] = platform.python_version()
    try:
        meta["load average at start"] = " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        pass
    try:
        from importlib.metadata import version
        meta["ltlf2dfa"] = version("ltlf2dfa")
        meta["symsynth"] = version("symsynth")
        meta["dd"] = version("dd")
        meta["sympy"] = version("sympy")
    except Exception:
        pass
    try:
        banner = subprocess.run([shutil.which("mona") or "mona"], capture_output=True, text=True,
                                timeout=10).stdout.splitlines()
        meta["MONA"] = f"{banner[0].strip()} ({shutil.which('mona')}, flags {' '.join(MONA_FLAGS)})"
    except Exception:
        meta["MONA"] = "?"
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        bench.LTLfParser()
        times.append(time.perf_counter() - t0)
    meta["ltlf2dfa parser construction (part of its pipeline)"] = \
        f"{statistics.median(times) * 1000:.1f} ms median"
    meta["settings"] = (f"reps {args.reps}, per-call limit {args.timeout:g} s, per-formula budget "
                        f"{args.budget:g} s, {args.traces} traces per formula, seed {args.seed}"
                        + (", --quick" if args.quick else ""))
    return meta


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true",
                   help="3 reps, 20 s limit, 40 random formulas, 100 traces")
    p.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"markdown file (default {DEFAULT_OUT})")
    p.add_argument("--families", default="conj,seq,random")
    p.add_argument("--max-n", type=int, default=10)
    p.add_argument("--random", type=int, default=None, help="number of random formulas (default 200)")
    p.add_argument("--reps", type=int, default=None, help="timed calls per formula (default 5)")
    p.add_argument("--timeout", type=float, default=None, help="per-call limit in s (default 60)")
    p.add_argument("--budget", type=float, default=None,
                   help="stop repeating a formula once its calls took this long (default 120 s)")
    p.add_argument("--traces", type=int, default=None, help="random traces per formula (default 300)")
    p.add_argument("--seed", type=int, default=2024)
    p.add_argument("--no-skip", action="store_true",
                   help="run larger instances even after a smaller one timed out")
    args = p.parse_args(argv)
    q = args.quick
    args.reps = args.reps or (3 if q else 5)
    global REPS
    REPS = args.reps
    args.timeout = args.timeout or (20.0 if q else 60.0)
    args.budget = args.budget or (30.0 if q else 120.0)
    args.traces = args.traces or (100 if q else 300)
    args.random = args.random if args.random is not None else (40 if q else 200)
    families = [f.strip() for f in args.families.split(",") if f.strip()]

    bench = Bench(args)
    results = {"cold": {}}
    try:
        meta = environment(args, bench)
        ns = range(1, args.max_n + 1)
        for fam in families:
            t0 = time.perf_counter()
            log(f"family {fam} ...")
            if fam == "conj":
                rows = bench.scaling_family("conj", conj_formula, ns)
            elif fam == "seq":
                rows = bench.scaling_family("seq", seq_formula, ns)
            elif fam == "random":
                rows = bench.random_family(args.random)
            else:
                p.error(f"unknown family {fam}")
            results[fam] = rows
            if rows:
                pick = rows[-1] if fam != "random" else max(rows, key=lambda r: len(r.text))
                label = f"n={pick.label}" if fam != "random" else f"#{pick.label} (longest)"
                results["cold"][fam] = (label, bench.cold(pick.text))
            log(f"family {fam} done in {time.perf_counter() - t0:.0f} s")
    finally:
        bench.close()

    text, verdicts = report(results, meta, args)
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text + "\n", encoding="utf-8")
    log(f"wrote {args.out}")
    return 0 if all(ok for ok, _ in verdicts) else 1


if __name__ == "__main__":
    sys.exit(main())
