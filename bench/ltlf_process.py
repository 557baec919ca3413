#!/usr/bin/env python3
"""Benchmark: `symsynth dfa` against raw MONA *as commands*, the way a user's
script or an LTLf paper's harness times them (issue 31): the wall time of
the whole process, start-up included, next to symsynth's in-process time.

    python bench/ltlf_process.py [--families Rright,AG,...] [--timeout 30] [--reps 3]
                                 [--out bench/results/ltlf-process.md]

Families: the generated ones of `bench/ltlf_generated.py` (ours) and a
sample of the public datasets (`bench/ltlf_families.py`'s, read from the
same mirror): Uright, GFand, Single-Counter, Double-Counter, Nim (up to
six heaps), Syft, Lydia.  Per formula:

  symsynth   `symsynth dfa -f FILE` (plain X weak, the default), wall time
             of the process, median of --reps runs (one when the first
             takes over a second); "in-process" is the compile time the
             command prints;
  MONA       `mona -q -u -w PROG` on the program ltlf2dfa 2.0 writes for
             the formula (`W` rewritten as `U | G`, which ltlf2dfa lacks),
             wall time, median likewise;
  check      MONA's automaton of the same program restricted to non-empty
             traces (`0 in $`) against symsynth's DFA: language equality by
             `ltlf_families.equivalent` (every letter, or random traces past
             its size bound) and the state counts (MONA's minimal automaton
             without its dummy initial state).

Before the runs symsynth is set up as an installed copy is after its first
run: its modules compiled to bytecode (`compileall`, as `pip install` does;
an environment with PYTHONDONTWRITEBYTECODE=1 would otherwise compile every
module from source in every process, 40 ms) and the LTLf parser's tables in
the cache directory (one `symsynth dfa` run; the first run of an install
builds them, 35 ms).  `--cold` leaves both out.

Target (issue 31): every formula within max(0.3 s, 2 x MONA) as processes.
"""

from __future__ import annotations

import argparse
import compileall
import csv
import io
import os
import platform
import random
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_automata import parse_mona  # noqa: E402
from ltlf_workers import MONA_FLAGS, read_mona  # noqa: E402
from ltlf_families import MIRROR, equivalent, instances, mona_program, peer_text, read  # noqa: E402
from ltlf_generated import generated  # noqa: E402
from provenance import commit  # noqa: E402

SYMSYNTH = [sys.executable, "-m", "symsynth.cli"]
DATASETS = ("Uright", "GFand", "Single-Counter", "Double-Counter", "Nim", "Syft", "Lydia")
#: Dataset instances taken per family (the smallest ones of the sample, and Nim up to six heaps).
SAMPLE = {"Uright": 20, "GFand": 16, "Single-Counter": 10, "Double-Counter": 7, "Syft": 12, "Lydia": 10}


def dataset_formulas(data: Path, family: str) -> list[tuple[str, str]]:
    if family == "Nim":
        paths = [f"Two-player-Game/Nim/nim_{h:02d}/System-first/nim_{h:02d}_{i:02d}.ltlf"
                 for h, i in ((1, 1), (2, 1), (2, 2), (3, 1), (3, 2), (4, 1), (5, 1), (6, 1))]
    else:
        paths = instances(data)[family][:SAMPLE[family]]
    return [(Path(p).stem if family not in ("Syft", "Lydia") else f"{Path(p).parent.name}/{Path(p).stem}",
             read(data, p)) for p in paths]


def timed(command: list[str], timeout: float, reps: int) -> tuple[float | None, float | None, str]:
    """(median wall seconds, median CPU seconds (user + system of the
    process), both None on a timeout or failure; the first run's stdout)."""
    times, cpus, first = [], [], ""
    for rep in range(reps):
        clock, cpu = time.perf_counter(), _children_cpu()
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, None, "timeout"
        times.append(time.perf_counter() - clock)
        cpus.append(_children_cpu() - cpu)
        if done.returncode != 0:
            return None, None, "error: " + (done.stderr.strip().splitlines() or ["?"])[-1][:100]
        if rep == 0:
            first = done.stdout
            if times[0] > 1.0:
                break
    return statistics.median(times), statistics.median(cpus), first


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def measure(family: str, name: str, text: str, work: Path, args) -> dict:
    from symsynth.automata import compile_ltlf
    from symsynth.logic import ast, parse_ltlf

    row = {"family": family, "instance": name, "commit": args.commit}
    formula = parse_ltlf(text, next_semantics="weak")
    atoms = sorted({a.key for a in ast.atoms(formula)})
    row["atoms"] = len(atoms)
    spec = work / "f.ltlf"
    spec.write_text(text)
    wall, row["symsynth_cpu"], out = timed([*SYMSYNTH, "dfa", "-f", str(spec), "--max-states", "0"],
                                           args.timeout, args.reps)
    row["symsynth_s"] = wall
    row["symsynth_status"] = "ok" if wall is not None else out
    if wall is not None:
        fields = dict(line.split(None, 1) for line in out.splitlines() if line.strip())
        row["states"] = int(fields["states"].split()[0])
        row["in_process_s"] = float(fields["seconds"])
    program = work / "f.mona"
    try:
        program.write_text(mona_program(peer_text(formula)))
    except Exception as error:  # ltlf2dfa cannot write a program for it
        row["mona_status"] = f"error: {type(error).__name__}"
        row["mona_s"] = None
        return row
    row["mona_s"], row["mona_cpu"], status = timed(["mona", *MONA_FLAGS, str(program)], args.timeout, args.reps)
    row["mona_status"] = "ok" if row["mona_s"] is not None else status
    if row["mona_s"] is not None and wall is not None and not args.no_check:
        nonempty = work / "nonempty.mona"
        nonempty.write_text(program.read_text() + "0 in $;\n")
        output, complete = read_mona(nonempty, 3 * args.timeout)
        if output and complete:
            mona = parse_mona(output)
            row["mona_states"] = len(mona.reachable([mona.start]))
            verdict, how = equivalent(compile_ltlf(text, next_semantics="weak"), mona, atoms, 12, 1000,
                                      random.Random(f"{family}/{name}"))
            row["check"] = (f"equal ({how})" if verdict is True else "DIFFERENT") + \
                ("" if row["mona_states"] == row["states"] else f"; states {row['states']} vs {row['mona_states']}")
        else:
            row["check"] = "not checked (MONA's automaton too large to read back)"
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=MIRROR)
    parser.add_argument("--families", default=",".join([*generated().keys(), *DATASETS]))
    parser.add_argument("--timeout", type=float, default=30.0, help="wall seconds per command run")
    parser.add_argument("--reps", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("bench/results/ltlf-process.md"))
    parser.add_argument("--only", default="", help="instances to run (names, comma-separated; default all)")
    parser.add_argument("--no-check", action="store_true",
                        help="skip the comparison with MONA's automaton (it runs MONA and symsynth once more)")
    parser.add_argument("--cold", action="store_true",
                        help="no bytecode compiled and no parser tables cached before the runs (module docstring)")
    args = parser.parse_args(argv)
    args.commit = commit()
    if not args.cold:
        warm_up()
    chosen = args.families.split(",")
    ours = generated([f for f in chosen if f not in DATASETS])
    rows: list[dict] = []
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory(prefix="ltlf_process_") as tmp:
        for family in chosen:
            items = ours[family] if family in ours else dataset_formulas(args.data, family)
            dead = False
            for name, text in items:
                if args.only and name not in args.only.split(","):
                    continue
                if dead:  # a scaling family: past a timeout, the larger ones are skipped
                    rows.append({"family": family, "instance": name, "symsynth_status": "TO*",
                                 "mona_status": "TO*", "commit": args.commit, "ours": family in ours})
                    continue
                row = measure(family, name, text, Path(tmp), args)
                row["ours"] = family in ours
                row["load"] = round(os.getloadavg()[0], 1)
                loads.append(row["load"])
                rows.append(row)
                dead = family in ("Rright", "URright", "Uconj", "AG", "Uright", "GFand") and \
                    row["symsynth_status"] == "timeout" and row["mona_status"] == "timeout"
                print(family, name, {k: row.get(k) for k in ("symsynth_s", "in_process_s", "mona_s", "check")},
                      flush=True)
                write(rows, args, loads)
    return 0


def warm_up() -> None:
    """symsynth as an installed copy is after its first run (module docstring)."""
    import symsynth
    compileall.compile_dir(str(Path(symsynth.__file__).parent), quiet=1)
    subprocess.run([*SYMSYNTH, "dfa", "a U b"], capture_output=True, check=True)


def target(row: dict) -> str:
    """The issue's target, on CPU seconds of the processes: the machine is
    shared, and wall time counts the other jobs' turns."""
    sym, mona = row.get("symsynth_cpu"), row.get("mona_cpu")
    if sym is None:
        return "no answer" if mona is not None else "neither"
    if mona is None:
        return "met (MONA none)"
    return "met" if sym <= max(0.3, 2 * mona) else "MISSED"


def write(rows: list[dict], args, loads: list[float]) -> None:
    from symsynth.files import write_atomic
    columns = ["family", "instance", "ours", "atoms", "states", "mona_states", "symsynth_s", "symsynth_cpu",
               "in_process_s", "symsynth_status", "mona_s", "mona_cpu", "mona_status", "check", "commit", "load"]
    table = io.StringIO()
    writer = csv.DictWriter(table, columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    csv_path = args.out.with_suffix(".csv")
    write_atomic(csv_path, table.getvalue(), "the benchmark rows")
    lines = ["# `symsynth dfa` against raw MONA as processes", "",
             f"Command: `python bench/ltlf_process.py --families {args.families} --timeout {args.timeout:g} "
             f"--reps {args.reps}" + (f" --only {args.only}" if args.only else "") +
             (" --no-check" if args.no_check else "") + (" --cold" if args.cold else "") +
             f"`; symsynth at {args.commit}; machine: {platform.machine()}, "
             f"{os.cpu_count()} cores, Python {platform.python_version()}, shared with other jobs (load "
             f"average {min(loads):.1f} to {max(loads):.1f} during the run). Wall seconds of the whole "
             "command and its CPU seconds (user + system), medians of the runs (one run past 1 s); "
             "in-process: the compile time symsynth prints. MONA: `mona -q -u -w` on ltlf2dfa 2.0's "
             "program. Target: symsynth within max(0.3 s, 2 x MONA), judged on CPU seconds (on a loaded "
             "machine the wall clock counts the other jobs' turns). " +
             ("Cold: no bytecode compiled and no parser tables cached beforehand (PYTHONDONTWRITEBYTECODE="
              f"{os.environ.get('PYTHONDONTWRITEBYTECODE', 'unset')}). " if args.cold else
              "symsynth's bytecode compiled and its parser tables cached before the runs, as after an "
              "installed copy's first run. ") + "Rows: [" + csv_path.name + "](" + csv_path.name + ").", "",
             "| family | instance | atoms | states | symsynth wall / CPU s | in-process s | MONA wall / CPU s "
             "| target (CPU) | check |",
             "|---|---|---:|---:|---:|---:|---:|---|---|"]
    for r in rows:
        fam = f"{r['family']} (ours)" if r.get("ours") else r["family"]
        lines.append(f"| {fam} | {r['instance']} | {r.get('atoms', '')} | {r.get('states', '')} | "
                     f"{_cell(r, 'symsynth_s', 'symsynth_status')} / {_num(r.get('symsynth_cpu'))} | "
                     f"{_num(r.get('in_process_s'))} | {_cell(r, 'mona_s', 'mona_status')} / "
                     f"{_num(r.get('mona_cpu'))} | {target(r)} | {r.get('check', '')} |")
    write_atomic(args.out, "\n".join(lines) + "\n", "the benchmark table")


def _num(x) -> str:
    return "" if x is None else (f"{x:.3f}" if x < 10 else f"{x:.1f}")


def _cell(row, key, status) -> str:
    if row.get(key) is not None:
        return _num(row[key])
    s = row.get(status, "")
    return "TO" if s == "timeout" else ("TO*" if s == "TO*" else "err")


if __name__ == "__main__":
    sys.exit(main())
