#!/usr/bin/env python3
"""Benchmark: symsynth's LTLf -> DFA compiler on the families of the public
LTLf synthesis datasets, against raw MONA and ltlf2dfa, in one run.

    python bench/ltlf_families.py [--data DIR] [--timeout 60] [--out bench/results/ltlf-families.md]

Data: github.com/whitemech/finite-synthesis-datasets (MIT), read from a git
checkout or bare mirror (`--data`, default the mirror this project's tools
fetch to).  Families and the instances taken (a deterministic sample where
a family is large, so that the whole run takes about half an hour here):

  Patterns/Uright     uright01..20 (`p1 U (p2 U (...))`)
  Patterns/GFand      gfand01..20
  Single-Counter      all 20, System-first
  Double-Counter      all 20, System-first
  Nim                 nim_01..nim_05, instances 01..04 of each
  Random/Syft         syft_1..syft_5, instances 001..004 of each
  Random/Lydia        case_03..case_10, instances 01..02 of each

and, named in `--families`, the generated families of `bench/ltlf_generated.py`
(ours, not a published set: Rright, URright, Uconj, AG, Dwyer, TV), whose
formulas are given as text rather than read from the datasets.

For each instance, each tool gets `--timeout` seconds of CPU time (and three
times that of wall time: the machine may be shared; killed at either limit):

  symsynth  `compile_ltlf(text, next_semantics="weak")` in a worker process
            (the datasets' X is weak next, X[!] strong);
  MONA      `mona -q -u -w` on the program ltlf2dfa 2.0 writes for the
            formula ("raw MONA": the automaton built and printed);
  ltlf2dfa  its whole `to_dfa()` (parser, MONA program, MONA, DOT).

In a scaling family (Uright, GFand, the counters, Nim), a tool that timed out
is not run on the larger instances of its series ("TO*"): the family, or for
Nim one number of heaps (nim_03_01..04 grow in heap size; nim_04_01 starts
a new series with four heaps of size one, smaller than nim_03_03).

Equivalence: where symsynth and MONA both finish, symsynth's DFA and MONA's
automaton of the same program restricted to non-empty traces (`0 in $`) are
compared by a breadth-first search of their product over every letter when
the formula has at most `--exhaustive` atoms and 2^atoms x states is at most
EXHAUSTIVE_WORK (the languages are equal or a shortest distinguishing trace
is printed), else over `--traces` random traces (the table says which).
"""

from __future__ import annotations

import argparse
import csv
import io
import os
import platform
import math
import random
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections import deque
from itertools import product
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_automata import parse_mona  # noqa: E402
from ltlf_workers import MONA_FLAGS, WALL_FACTOR, Worker, read_mona  # noqa: E402
from ltlf_generated import generated  # noqa: E402
from provenance import commit  # noqa: E402

MIRROR = Path("/work/.mirror/whitemech+finite-synthesis-datasets/repo")
#: letters x symsynth's states up to which the product search tries every letter
EXHAUSTIVE_WORK = 200_000


def instances(data: Path) -> dict[str, list[str]]:
    """Family -> dataset paths, smallest first (module doc)."""
    def nums(prefix, n, width=2, suffix=".ltlf"):
        return [f"{prefix}{i:0{width}d}{suffix}" for i in range(1, n + 1)]

    listed = _list(data)
    counters = {name: sorted(p for p in listed if p.startswith(f"Two-player-Game/{name}/System-first/")
                             and p.endswith(".ltlf")) for name in ("Single-Counter", "Double-Counter")}
    return {
        "Uright": nums("Patterns/Uright/uright", 20),
        "GFand": nums("Patterns/GFand/gfand", 20),
        "Single-Counter": counters["Single-Counter"],
        "Double-Counter": counters["Double-Counter"],
        "Nim": [f"Two-player-Game/Nim/nim_{h:02d}/System-first/nim_{h:02d}_{i:02d}.ltlf"
                for h in range(1, 6) for i in range(1, 5)],
        "Syft": [f"Random/Syft/syft_{k}/{i:03d}.ltlf" for k in range(1, 6) for i in range(1, 5)],
        "Lydia": [f"Random/Lydia/case_{c:02d}_50/{i:02d}.ltlf" for c in range(3, 11) for i in range(1, 3)],
    }


SCALING = {"Uright", "GFand", "Single-Counter", "Double-Counter", "Nim", "Rright", "URright", "Uconj", "AG"}
GENERATED = {"Rright", "URright", "Uconj", "AG", "Dwyer", "TV"}  # bench/ltlf_generated.py: ours


def _list(data: Path) -> set[str]:
    if (data / ".git").exists() or not (data / "HEAD").exists():
        return {str(p.relative_to(data)) for p in data.rglob("*.ltlf")}
    out = subprocess.run(["git", "-C", str(data), "ls-tree", "-r", "--name-only", "HEAD"],
                         capture_output=True, text=True, check=True).stdout
    return set(out.split())


def read(data: Path, path: str) -> str:
    if (data / path).exists():
        return (data / path).read_text()
    return subprocess.run(["git", "-C", str(data), "show", f"HEAD:{path}"], capture_output=True, text=True,
                          check=True).stdout


def equivalent(sym, mona, atoms: list[str], exhaustive: int, traces: int, rng: random.Random):
    """(verdict, how): symsynth's DFA against MONA's automaton over non-empty
    traces; verdict True, or a distinguishing trace."""
    if len(atoms) <= exhaustive and (2 ** len(atoms)) * sym.num_states <= EXHAUSTIVE_WORK:
        letters = [frozenset(a for a, bit in zip(atoms, bits) if bit) for bits in product((0, 1), repeat=len(atoms))]
        start = (sym.initial, mona.start)
        seen, queue = {start: ()}, deque([start])
        while queue:
            q, m = queue.popleft()
            for letter in letters:
                pair = (sym.step(q, letter), _mona_step(mona, m, letter))
                word = seen[(q, m)] + (letter,)
                if sym.is_accepting(pair[0]) != (pair[1] in mona.accepting):
                    return word, "exhaustive"
                if pair not in seen:
                    seen[pair] = word
                    queue.append(pair)
        return True, "exhaustive"
    for _ in range(traces):
        word = tuple(frozenset(a for a in atoms if rng.random() < 0.5) for _ in range(rng.randint(1, 20)))
        if sym.accepts(word) != mona.run(word):
            return word, f"{traces} random traces"
    return True, f"{traces} random traces"


def _mona_step(auto, state, letter):
    for pred, target in auto.rows.get(state, ()):
        if pred(letter):
            return target
    raise ValueError(f"MONA's automaton has no transition from {state} on {sorted(letter)}")


def mona_program(text: str) -> str:
    from ltlf2dfa.base import MonaProgram
    from ltlf2dfa.parser.ltlf import LTLfParser
    return MonaProgram(LTLfParser()(text)).mona_program()


def peer_text(formula) -> str:
    """ltlf2dfa's syntax for `formula`, every operand in parentheses (ltlf2dfa
    reads `a U b R c` as `(a U b) R c`, symsynth as `a U (b R c)`), and
    `a W b` written `(a U b) | G a`, which ltlf2dfa lacks."""
    from symsynth.logic import ast

    unary = {ast.Not: "!", ast.Next: "X", ast.WeakNext: "WX", ast.Eventually: "F", ast.Always: "G"}
    binary = {ast.And: "&", ast.Or: "|", ast.Implies: "->", ast.Equiv: "<->", ast.Until: "U", ast.Release: "R"}
    done: dict[int, str] = {}
    stack: list = [(formula, False, None)]
    while stack:
        f, visited, alias = stack.pop()
        if isinstance(f, ast.WeakUntil):
            f, alias = ast.Or(ast.Until(f.left, f.right), ast.Always(f.left)), f
        children = [f.arg] if isinstance(f, ast.UNARY) else [f.left, f.right] if isinstance(f, ast.BINARY) else []
        if children and not visited:
            stack.append((f, True, alias))
            stack.extend((c, False, None) for c in children)
            continue
        if isinstance(f, ast.Atom):
            text = f.key
        elif isinstance(f, ast.Const):
            text = "true" if f.value else "false"
        elif isinstance(f, ast.Last):
            text = "last"
        elif isinstance(f, ast.UNARY):
            text = f"{unary[type(f)]}({done[id(f.arg)]})"
        else:
            text = f"({done[id(f.left)]}) {binary[type(f)]} ({done[id(f.right)]})"
        done[id(f)] = text
        if alias is not None:
            done[id(alias)] = text
    return done[id(formula)]


def timed_mona(path: Path, timeout: float, wall: float) -> dict:
    """MONA on the program at `path`: its time, or a timeout, or an error
    (MONA stops with a non-zero status when it runs out of its BDD tables:
    no automaton, however fast)."""
    clock, cpu = time.perf_counter(), _children_cpu()
    limit = max(1, math.ceil(timeout))

    def cap():  # in the child: SIGXCPU past `timeout` s of CPU time
        resource.setrlimit(resource.RLIMIT_CPU, (limit, limit + 1))

    try:
        done = subprocess.run(["mona", *MONA_FLAGS, str(path)], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True, timeout=wall,
                              preexec_fn=cap)
    except subprocess.TimeoutExpired:
        return {"seconds": None, "wall": None, "status": "timeout"}
    if done.returncode == -signal.SIGXCPU or _children_cpu() - cpu > timeout:
        return {"seconds": None, "wall": None, "status": "timeout"}
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or [f"exit status {done.returncode}"])[-1]
        return {"seconds": None, "wall": None, "status": f"error: {last[:80]}"}
    return {"seconds": _children_cpu() - cpu, "wall": time.perf_counter() - clock, "status": "ok"}


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=MIRROR)
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--wall", type=float, default=None,
                        help=f"wall-clock seconds per tool and instance (default {WALL_FACTOR} x --timeout)")
    parser.add_argument("--exhaustive", type=int, default=12, help="atoms up to which every letter is tried")
    parser.add_argument("--traces", type=int, default=2000)
    parser.add_argument("--families", default=",".join(["Uright", "GFand", "Single-Counter", "Double-Counter",
                                                        "Nim", "Syft", "Lydia"]))
    parser.add_argument("--out", type=Path, default=Path("bench/results/ltlf-families.md"))
    parser.add_argument("--from-csv", type=Path, nargs="+", metavar="CSV",
                        help="write the tables from the rows of earlier runs (in order) instead of running")
    args = parser.parse_args(argv)
    args.load = [os.getloadavg()[0]]
    if args.wall is None:
        args.wall = WALL_FACTOR * args.timeout
    if args.from_csv:
        rows = []
        for path in args.from_csv:
            with open(path, newline="") as given:
                rows += [_typed(r) for r in csv.DictReader(given)]
        args.load = sorted({float(r["load"]) for r in rows if r.get("load")}) or args.load
        write(rows, args)
        return 0
    from symsynth.automata import compile_ltlf
    from symsynth.logic import ast, parse_ltlf

    measured = commit()
    sym, l2d = Worker("sym-weak", args.timeout, args.wall), Worker("l2d", args.timeout, args.wall)
    work = Path(tempfile.mkdtemp(prefix="ltlf_families_"))
    rows = []
    chosen = args.families.split(",")
    ours = generated([f for f in chosen if f in GENERATED])
    ours_text = {family: dict(items) for family, items in ours.items()}
    families = {**(instances(args.data) if set(chosen) - GENERATED else {}),
                **{family: list(texts) for family, texts in ours_text.items()}}
    try:
        for family, paths in families.items():
            if family not in chosen:
                continue
            dead: dict[str, str] = {}
            series = None
            for path in paths:
                if family == "Nim" and Path(path).stem[:6] != series:  # nim_03, nim_04, ...
                    series, dead = Path(path).stem[:6], {}
                text = ours_text[family][path] if family in ours_text else read(args.data, path)
                name = Path(path).stem if family in SCALING | GENERATED else \
                    f"{Path(path).parent.name}/{Path(path).stem}"
                row = {"family": family, "instance": name, "atoms": None, "commit": measured}
                formula = parse_ltlf(text, next_semantics="weak")
                atoms = sorted({a.key for a in ast.atoms(formula)})
                row["atoms"] = len(atoms)
                peer = peer_text(formula)  # ltlf2dfa's syntax: X strong, WX weak, all parenthesized
                for tool, worker, given in (("symsynth", sym, text), ("ltlf2dfa", l2d, peer)):
                    if tool in dead:
                        row[tool], row[f"{tool}_status"] = None, "TO*"
                        continue
                    got = worker.run(given, 1, args.timeout)
                    status = "timeout" if got["timeout"] else ("error" if got.get("error") else "ok")
                    row[tool] = got["cpu"] if status == "ok" and got["times"] else None
                    row[f"{tool}_wall"] = got["times"][0] if status == "ok" and got["times"] else None
                    row[f"{tool}_status"] = status if status != "error" else f"error: {got['error'].splitlines()[0][:80]}"
                    if tool == "symsynth":
                        row["states"] = got.get("states")
                    if status == "timeout" and family in SCALING:
                        dead[tool] = row["instance"]
                program = work / "prog.mona"
                if "mona" in dead:
                    row["mona"], row["mona_status"] = None, "TO*"
                else:
                    try:
                        program.write_text(mona_program(peer))
                        got = timed_mona(program, args.timeout, args.wall)
                        row["mona"], row["mona_status"] = got["seconds"], got["status"]
                        row["mona_wall"] = got["wall"]
                    except Exception as error:  # ltlf2dfa cannot write a program for it
                        row["mona"], row["mona_status"] = None, f"error: {type(error).__name__}"
                    if row["mona_status"] == "timeout" and family in SCALING:
                        dead["mona"] = row["instance"]
                row["equivalence"] = ""
                if row["symsynth_status"] == "ok" and row["mona_status"] == "ok":
                    nonempty = work / "nonempty.mona"
                    nonempty.write_text(program.read_text() + "0 in $;\n")
                    output, complete = read_mona(nonempty, args.wall)
                    if output and complete:
                        verdict, how = equivalent(compile_ltlf(text, next_semantics="weak"), parse_mona(output),
                                                  atoms, args.exhaustive, args.traces,
                                                  random.Random(f"{family}/{path}"))
                        row["equivalence"] = f"equal ({how})" if verdict is True else \
                            "DIFFERENT on " + " ".join("{" + ",".join(sorted(x)) + "}" for x in verdict)
                    else:
                        row["equivalence"] = "not checked (MONA's automaton too large to read back)"
                row["load"] = round(os.getloadavg()[0], 2)
                args.load.append(row["load"])
                rows.append(row)
                write(rows, args)  # after every instance: an interrupted run keeps what it measured
                print(family, row["instance"], {k: row[k] for k in ("symsynth", "mona", "ltlf2dfa", "equivalence")},
                      flush=True)
    finally:
        sym.close()
        l2d.close()
    return 0


def write(rows: list[dict], args) -> None:
    from symsynth.files import write_atomic
    csv_path = args.out.with_suffix(".csv")
    columns = ["family", "instance", "atoms", "states", "symsynth", "symsynth_status", "mona", "mona_status",
               "ltlf2dfa", "ltlf2dfa_status", "equivalence", "load", "symsynth_wall", "mona_wall", "ltlf2dfa_wall",
               "commit"]
    table = io.StringIO()
    writer = csv.DictWriter(table, columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    write_atomic(csv_path, table.getvalue(), "the benchmark rows")
    mona_version = subprocess.run(["mona", "-v"], capture_output=True, text=True).stdout.strip().splitlines()[:1]
    families = sorted({row["family"] for row in rows})
    ours = [f for f in families if f in GENERATED]
    sources = "; ".join(([f"{', '.join(ours)}: generated by bench/ltlf_generated.py (ours, not a published set)"]
                         if ours else []) +
                        (["the others: github.com/whitemech/finite-synthesis-datasets (MIT)"]
                         if set(families) - GENERATED else []))
    title = "the public synthesis datasets" if not ours else "our generated families" if ours == families \
        else "the public synthesis datasets and our generated families"
    lines = [f"# LTLf to DFA on {title}: symsynth, raw MONA, ltlf2dfa", "",
             f"Command: `python bench/ltlf_families.py --families {','.join(families)} --timeout {args.timeout:g}`; "
             f"formulas: {sources}; machine: "
             f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
             f"MONA {' '.join(mona_version)}; ltlf2dfa 2.0.0. CPU seconds (user + system, MONA's "
             "own process; ltlf2dfa's with the MONA it runs) of one run each, wall-clock seconds in "
             "the CSV's `_wall` columns; "
             f"TO: over {args.timeout:g} CPU s (or {args.wall:g} s of wall time); TO*: not run after a smaller instance timed out. Rows: "
             f"[{csv_path.name}]({csv_path.name}). Load average (1 min) during the run: "
             f"{min(args.load):.1f} to {max(args.load):.1f} on {os.cpu_count()} cores (shared machine; "
             "the tools of one instance run one after the other, so load weighs on each).", ""]
    lines += runs(rows)
    tools = ("symsynth", "mona", "ltlf2dfa")
    lines += ["## Summary", "",
              "Median and worst over the instances where both symsynth and MONA finished (n); "
              "ltlf2dfa's over those it finished. Ratio: MONA's time over symsynth's (above 1: "
              "symsynth faster).", "",
              "| family | instances | finished (symsynth / MONA / ltlf2dfa) | n | median s (symsynth / MONA) "
              "| worst s (symsynth / MONA) | median ratio | ltlf2dfa median / worst s "
              "| largest within the limit (symsynth / MONA / ltlf2dfa) | equivalence |",
              "|---|---:|---|---:|---|---|---:|---|---|---|"]
    for family in dict.fromkeys(r["family"] for r in rows):
        mine = [r for r in rows if r["family"] == family]
        both = [r for r in mine if r["symsynth"] is not None and r["mona"] is not None]
        finished = " / ".join(str(sum(r[t] is not None for r in mine)) for t in tools)
        med = " / ".join(_fmt(statistics.median(r[t] for r in both)) if both else "-" for t in tools[:2])
        worst = " / ".join(_fmt(max(r[t] for r in both)) if both else "-" for t in tools[:2])
        ratio = (f"{statistics.median(r['mona'] / max(r['symsynth'], 1e-4) for r in both):.2f}"
                 if both else "-")
        l2d = [r["ltlf2dfa"] for r in mine if r["ltlf2dfa"] is not None]
        l2d_cell = f"{_fmt(statistics.median(l2d))} / {_fmt(max(l2d))}" if l2d else "-"
        largest = " / ".join(next((r["instance"] for r in reversed(mine) if r[t] is not None), "none")
                             for t in tools)
        checked = [r["equivalence"] for r in mine if r["equivalence"].startswith(("equal", "DIFFERENT"))]
        different = sum(c.startswith("DIFFERENT") for c in checked)
        lines.append(f"| {family} | {len(mine)} | {finished} | {len(both)} | {med} | {worst} | {ratio} | "
                     f"{l2d_cell} | {largest} | {len(checked) - different} equal, {different} different |")
    for family in dict.fromkeys(r["family"] for r in rows):
        lines += ["", f"## {family}", "", "| instance | atoms | states | symsynth s | MONA s | ltlf2dfa s | equivalence |",
                  "|---|---:|---:|---:|---:|---:|---|"]
        for r in (r for r in rows if r["family"] == family):
            lines.append(f"| {r['instance']} | {r['atoms']} | {r.get('states') or ''} | "
                         f"{_cell(r, 'symsynth')} | {_cell(r, 'mona')} | {_cell(r, 'ltlf2dfa')} | {r['equivalence']} |")
    notes = args.out.with_suffix(".notes.md")
    if notes.exists():  # the analysis written by hand next to the generated tables
        lines += ["", notes.read_text().rstrip()]
    write_atomic(args.out, "\n".join(lines) + "\n", "the benchmark table")
    print(f"wrote {args.out} and {csv_path}")


def runs(rows: list[dict]) -> list[str]:
    """A paragraph saying which symsynth commit each family's rows were
    measured at (rows merged from several runs with --from-csv)."""
    by_commit: dict[str, list[str]] = {}
    for r in rows:
        families = by_commit.setdefault(r.get("commit") or "unrecorded", [])
        if r["family"] not in families:
            families.append(r["family"])
    if len(by_commit) == 1:
        return [f"symsynth at commit {next(iter(by_commit))}; every family in this one run.", ""]
    parts = [f"{', '.join(families)} at {commit}" for commit, families in by_commit.items()]
    return ["Runs (one family per run at most, so each row's tools ran side by side): "
            + "; ".join(parts) + ".", ""]


def _typed(row: dict) -> dict:
    """A CSV row with its numbers back as numbers (empty cells None)."""
    out = dict(row)
    for key in ("symsynth", "mona", "ltlf2dfa"):
        out[key] = float(row[key]) if row.get(key) else None
    for key in ("atoms", "states"):
        out[key] = int(float(row[key])) if row.get(key) else None
    out["equivalence"] = row.get("equivalence") or ""
    return out


def _fmt(x: float) -> str:
    return f"{x:.3f}" if x < 10 else f"{x:.1f}"


def _cell(row: dict, tool: str) -> str:
    if row[tool] is not None:
        return _fmt(row[tool])
    status = row[f"{tool}_status"]
    return "TO" if status == "timeout" else ("TO*" if status == "TO*" else "err")


if __name__ == "__main__":
    sys.exit(main())
