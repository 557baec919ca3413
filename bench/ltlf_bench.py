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
import os
import platform
import random
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # the modules beside this script, when it is imported as bench.ltlf_bench

from ltlf_automata import parse_l2d_dot, parse_mona  # noqa: E402
from ltlf_formulas import (atoms_of, conj_formula, l2d_text, make_traces, oracle, random_family,  # noqa: E402
                           seq_formula, sym_text, temporal_depth)
from ltlf_workers import MONA_FLAGS, Worker, mona_header, read_mona, time_mona  # noqa: E402

DEFAULT_OUT = HERE / "results" / "ltlf.md"
TARGET_SPEEDUP = 10.0

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
