#!/usr/bin/env python3
"""Benchmark: `symsynth synth` on every family of the public LTLf synthesis
datasets, each verdict checked against the published one.

    python bench/synth_families.py [--data DIR] [--timeout 60] [--jobs 1] [--resume]
                                   [--families Uright,GFand,...] [--out bench/results/synth-families.md]

Data: github.com/whitemech/finite-synthesis-datasets (MIT), every `.ltlf`
with its `.part` (the System-first versions of the games), read from a git
checkout or bare mirror (`--data`, default the mirror this project's tools
fetch to):

  Uright, GFand              Patterns/, 20 each
  Single-Counter, Double-Counter   Two-player-Game/*/System-first, 20 each
  Nim                        nim_01 .. nim_20 (heaps), 20 instances each
  Syft                       Random/Syft/syft_1 .. syft_5, 200 each
  Lydia                      Random/Lydia/case_03_50 .. case_10_50, 50 each

Each instance runs `symsynth synth SPEC.ltlf --part SPEC.part --json` (the
command line's own `main`, agent first, X weak) in a child process forked
for it, with `--timeout` seconds of CPU time (RLIMIT_CPU, then killed:
"timeout"), `--wall` seconds of wall time (default 3 x the timeout: also
"timeout") and `--memory` GB of address space (beyond: "memory").  CPU time,
not wall time, because this machine is shared: under a load of 9 on 2
cores a niced child gets a fraction of a core, and a wall limit would
measure the neighbours.  `--jobs N` children run at once.  Within a scaling
set (the patterns, the counters, each nim_HH) instances run one at a time,
smallest first, and after a timeout or a memory-out the larger ones are not
run ("skipped").

Expected verdicts: `tests/data/synth-verdicts/verdicts.csv`, from the
integration tests of Nike (and LydiaSyft, which inherited them); its
`nike_ci` column marks the instances Nike's tests run, the ones their
authors call tractable for Nike.  The scaling families run first (they
stop at their first timeout), then Nike's CI instances of the random
families, then the other random instances set by set interleaved (instance
1 of every set, then 2, ...), so that an interrupted run (`--stop-after`;
`--resume` carries on from the CSV) has the comparison with Nike.

Output: `--out` (markdown: per family and per set: instances, run, solved
within the limit, verdicts, agreement with the published verdicts, Nike's
CI instances solved) and the rows in the CSV beside it; the machine, the
load average at start and end and the commit are recorded.  The exit
status is 1 when a verdict disagrees with a published one.
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import json
import math
import multiprocessing as mp
import multiprocessing.connection
import os
import platform
import resource
import signal
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_families import MIRROR, _list, read  # noqa: E402
from provenance import commit  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
VERDICTS = ROOT / "tests" / "data" / "synth-verdicts" / "verdicts.csv"
FAMILIES = ("Uright", "GFand", "Single-Counter", "Double-Counter", "Nim", "Syft", "Lydia")
#: families whose instances grow along a set: after a timeout, the rest of the set is skipped
SCALING = {"Uright", "GFand", "Single-Counter", "Double-Counter", "Nim"}
COLUMNS = ["family", "set", "instance", "path", "expected", "nike_ci", "status", "agrees", "cpu_seconds", "seconds",
           "dfa_seconds", "game_seconds", "dfa_states", "exit"]


def instances(data: Path) -> list[dict]:
    """Every instance of the datasets with its family and set, in the
    datasets' order (smallest first within a scaling set)."""
    listed = sorted(p for p in _list(data) if p.endswith(".ltlf"))
    rows = []
    for path in listed:
        parts = path.split("/")
        if parts[0] == "Patterns":
            family, subset = parts[1], parts[1]
        elif parts[0] == "Two-player-Game":
            if "System-first" not in parts:
                continue
            family = parts[1]
            subset = parts[2] if family == "Nim" else family
        elif parts[0] == "Random":
            family, subset = parts[1], parts[2]
        else:
            continue
        rows.append({"family": family, "set": subset, "instance": Path(path).stem, "path": path})
    return rows


#: statuses after which the larger instances of a scaling set are skipped
OUT = ("timeout", "wall", "memory")


def _harder(row: dict, out: dict) -> bool:
    """Whether `row` is at least as large as `out`, an instance that ran out:
    a later instance of the same scaling set, or for Nim (nim_HH_TT: HH heaps
    of TT tokens) at least as many heaps and tokens."""
    if row["family"] != out["family"] or row["family"] not in SCALING:
        return False
    if row["family"] == "Nim":
        mine, theirs = row["instance"].split("_")[1:], out["instance"].split("_")[1:]
        return all(int(a) >= int(b) for a, b in zip(mine, theirs))
    return row["set"] == out["set"] and row["instance"] > out["instance"]


def published(path: Path) -> dict[str, tuple[str, str]]:
    with open(path, newline="") as file:
        return {r["instance"]: (r["expected"], r["nike_ci"]) for r in csv.DictReader(file)}


def schedule(rows: list[dict]) -> list[dict]:
    """The scaling families, then Nike's CI instances, then the rest
    interleaved across sets (module doc)."""
    first = [r for r in rows if r["family"] in SCALING]
    first += [r for r in rows if r["family"] not in SCALING and r["nike_ci"] == "yes"]
    by_set: dict[str, list[dict]] = defaultdict(list)
    for r in rows:
        if r["family"] not in SCALING and r["nike_ci"] != "yes":
            by_set[r["set"]].append(r)
    rest = []
    for i in range(max((len(v) for v in by_set.values()), default=0)):
        rest += [v[i] for v in by_set.values() if i < len(v)]
    return first + rest


def _child(conn, spec: str, part: str, memory: float, cpu: float) -> None:
    """Runs in the forked child: the command line's `main`, its stdout captured."""
    limit = int(memory * 2**30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    seconds = math.ceil(cpu)
    resource.setrlimit(resource.RLIMIT_CPU, (seconds, seconds + 1))  # SIGXCPU, then SIGKILL
    from symsynth.cli import main
    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["synth", spec, "--part", part, "--json"])
    except MemoryError:
        conn.send({"status": "memory", "err": "MemoryError", "cpu": time.process_time()})
        return
    except BaseException as error:  # a bug: reported in the table, not fatal to the run
        conn.send({"status": "error", "err": f"{type(error).__name__}: {error}", "cpu": time.process_time()})
        return
    conn.send({"exit": code, "out": out.getvalue(), "err": err.getvalue(), "cpu": time.process_time()})


class Run:
    """One instance in a forked child (module doc)."""

    def __init__(self, data: Path, row: dict, args, work: Path, number: int):
        self.row, self.args = row, args
        spec, part = work / f"{number}.ltlf", work / f"{number}.part"
        spec.write_text(read(data, row["path"]))
        part.write_text(read(data, row["path"][:-len(".ltlf")] + ".part"))
        ctx = mp.get_context("fork")
        self.conn, child = ctx.Pipe(duplex=False)
        self.clock = time.perf_counter()
        self.proc = ctx.Process(target=_child, args=(child, str(spec), str(part), args.memory, args.timeout),
                                daemon=True)
        self.proc.start()
        child.close()

    def done(self) -> bool:
        return (self.conn.poll() or not self.proc.is_alive()
                or time.perf_counter() - self.clock > self.args.wall)

    def result(self) -> dict:
        try:
            got = self.conn.recv() if self.conn.poll() else None
        except EOFError:  # the child died without a word (RLIMIT_CPU, the kernel)
            got = None
        seconds = time.perf_counter() - self.clock
        self.proc.kill()  # CUDD does not look at signals
        self.proc.join()
        self.conn.close()
        result = {"seconds": round(seconds, 3), "exit": "", "cpu_seconds": "", "dfa_seconds": "",
                  "game_seconds": "", "dfa_states": ""}
        if got is None:  # killed: by RLIMIT_CPU (SIGXCPU/SIGKILL), at the wall limit, or by the kernel (memory)
            signal_number = -(self.proc.exitcode or 0)
            if signal_number == signal.SIGXCPU:
                return result | {"status": "timeout", "cpu_seconds": self.args.timeout}
            if seconds > self.args.wall:
                return result | {"status": "wall"}
            return result | {"status": "crashed", "error": f"exit {self.proc.exitcode}"}
        result["cpu_seconds"] = round(got["cpu"], 3)
        if got.get("status"):
            return result | {"status": got["status"], "error": got["err"][:200]}
        lines = got["out"].splitlines()
        result["exit"] = got["exit"]
        if got["exit"] not in (10, 20) or not lines:
            memory_out = "MemoryError" in got["err"] or "memory" in got["err"].lower()
            return result | {"status": "memory" if memory_out else "error", "error": got["err"].strip()[:200]}
        summary = json.loads(lines[1])
        return result | {"status": lines[0].lower(), "dfa_seconds": summary["seconds"]["dfa"],
                         "game_seconds": summary["seconds"]["game"], "dfa_states": summary["dfa_states"]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=MIRROR)
    parser.add_argument("--timeout", type=float, default=60.0, help="CPU seconds per instance")
    parser.add_argument("--wall", type=float, default=None, help="wall seconds per instance (default 3 x timeout)")
    parser.add_argument("--jobs", type=int, default=1, help="instances run at once")
    parser.add_argument("--memory", type=float, default=8.0, help="GB of address space per instance")
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--verdicts", type=Path, default=VERDICTS)
    parser.add_argument("--resume", action="store_true", help="keep the rows of the CSV and run the others")
    parser.add_argument("--retry-wall", action="store_true",
                        help="with --resume: run again the instances killed at the wall limit (and those skipped)")
    parser.add_argument("--stop-after", type=float, default=None, metavar="MINUTES",
                        help="start no instance after this many minutes (the report says what was not run)")
    parser.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "synth-families.md")
    args = parser.parse_args(argv)
    args.wall = args.wall or 3 * args.timeout
    import symsynth.cli  # noqa: F401  (imported once here, inherited by every forked child)

    wanted = set(args.families.split(","))
    verdicts = published(args.verdicts)
    rows = [r for r in instances(args.data) if r["family"] in wanted]
    for r in rows:
        r["expected"], r["nike_ci"] = verdicts.get(r["path"], ("", "no"))
    csv_path = args.out.with_suffix(".csv")
    done: dict[str, dict] = {}
    if args.resume and csv_path.exists():
        with open(csv_path, newline="") as file:
            again = ("", "not run") + (("wall", "skipped") if args.retry_wall else ())
            done = {r["path"]: r for r in csv.DictReader(file) if r["status"] not in again}
    meta = {"load_start": os.getloadavg(), "started": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "commit": commit(), "args": args}
    work = Path(tempfile.mkdtemp(prefix="synth_families_"))
    dead = [r for r in done.values() if r["family"] in SCALING and r["status"] in OUT]  # ran out
    clock = time.perf_counter()
    pending = [r for r in schedule(rows)]
    running: list[Run] = []
    number = 0

    def finish(row: dict) -> None:
        row["agrees"] = _agrees(row)
        done[row["path"]] = row
        write(rows, done, meta, csv_path, args.out)

    while pending or running:
        busy = {r.row["set"] for r in running if r.row["family"] in SCALING}
        while len(running) < args.jobs:
            row = next((r for r in pending if r["path"] in done or r["family"] not in SCALING
                        or r["set"] not in busy), None)
            if row is None:
                break
            pending.remove(row)
            if row["path"] in done:  # resumed: its run kept, the verdicts as the file now has them
                row.update(done[row["path"]] | {k: row[k] for k in ("expected", "nike_ci")})
                row["agrees"] = _agrees(row)
                done[row["path"]] = row
            elif args.stop_after is not None and time.perf_counter() - clock > 60 * args.stop_after:
                row["status"] = "not run"
                finish(row)
            elif any(_harder(row, out) for out in dead):
                row["status"] = "skipped"
                finish(row)
            else:
                number += 1
                running.append(Run(args.data, row, args, work, number))
                busy = {r.row["set"] for r in running if r.row["family"] in SCALING}
        if not running:
            continue
        mp.connection.wait([r.conn for r in running] + [r.proc.sentinel for r in running], timeout=1.0)
        for run in [r for r in running if r.done()]:
            running.remove(run)
            row = run.row
            row.update(run.result())
            if row["family"] in SCALING and row["status"] in OUT:
                dead.append(row)
            print(row["path"], row["status"], row["seconds"], row["cpu_seconds"], row.get("error", ""), flush=True)
            finish(row)
    meta["load_end"] = os.getloadavg()
    write(rows, done, meta, csv_path, args.out)
    return 1 if any(r.get("agrees") == "no" for r in done.values()) else 0


def _agrees(row: dict) -> str:
    if row["status"] not in ("realizable", "unrealizable") or not row["expected"]:
        return ""
    return "yes" if row["status"] == row["expected"] else "no"


def write(rows: list[dict], done: dict[str, dict], meta: dict, csv_path: Path, out: Path) -> None:
    """The CSV (every row run so far) and the markdown report."""
    ran = [done[r["path"]] for r in rows if r["path"] in done]
    with open(csv_path, "w", newline="") as file:
        writer = csv.DictWriter(file, COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(ran)
    args = meta["args"]
    load_end = meta.get("load_end")
    lines = ["# `symsynth synth` on the LTLf synthesis datasets", "",
             f"Command: `nice -n 10 python bench/synth_families.py --timeout {args.timeout:g} --wall {args.wall:g} "
             f"--memory {args.memory:g} --jobs {args.jobs}"
             + (f" --stop-after {args.stop_after:g}" if args.stop_after is not None else "")
             + f"`{' (resumed)' if args.resume else ''}; symsynth commit {meta['commit']}; "
             f"started {meta['started']}; data: github.com/whitemech/finite-synthesis-datasets (MIT), "
             "System-first, agent first, X weak; machine: "
             f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; load average "
             f"(1/5/15 min) at start {_load(meta['load_start'])}"
             + (f", at end {_load(load_end)}" if load_end else ", run in progress or interrupted") + ". "
             f"Each instance in a forked child: {args.timeout:g} s of CPU time, {args.wall:g} s of wall time, "
             f"{args.memory:g} GB; times are CPU seconds of the child (the `seconds` column of the CSV: wall). "
             "*timeout*: the CPU limit reached; *wall*: killed at the wall limit before it (the machine's load, "
             "undecided); *skipped*: not run, a smaller instance of its scaling set ran out. "
             "Expected verdicts: [tests/data/synth-verdicts](../../tests/data/synth-verdicts/README.md) "
             "(Nike's and LydiaSyft's integration tests); *Nike CI*: the instances Nike's tests run, "
             f"which its authors call tractable for Nike. Rows: [{csv_path.name}]({csv_path.name}).", ""]
    header = ("| {0} | instances | run | solved ≤ {1:g} CPU s | realizable / unrealizable | timeout / wall / memory / "
              "skipped | published verdicts: agree / disagree | Nike CI: instances / solved by symsynth | "
              "median / max CPU s (solved) |")
    rule = "|---|---:|---:|---:|---|---|---|---|---|"
    lines += ["## Per family", "", header.format("family", args.timeout), rule]
    families = list(dict.fromkeys(r["family"] for r in rows))
    for family in families:
        lines.append(_line(family, [r for r in rows if r["family"] == family], done))
    lines.append(_line("**all**", rows, done))
    disagreements = [r for r in ran if r.get("agrees") == "no"]
    lines += ["", "## Disagreements with the published verdicts", ""]
    lines += [f"- {r['path']}: symsynth {r['status']}, published {r['expected']}" for r in disagreements] or ["none"]
    lines += ["", "## Per set", "", header.format("set", args.timeout), rule]
    for subset in dict.fromkeys(r["set"] for r in rows):
        lines.append(_line(subset, [r for r in rows if r["set"] == subset], done))
    errors = [r for r in ran if r["status"] in ("error", "crashed")]
    if errors:
        lines += ["", "## Errors", ""] + [f"- {r['path']}: {r.get('error', r['status'])}" for r in errors]
    out.write_text("\n".join(lines) + "\n")


def _line(name: str, rows: list[dict], done: dict[str, dict]) -> str:
    decided = [done[r["path"]] for r in rows if r["path"] in done and done[r["path"]]["status"] != "not run"]
    status = [r["status"] for r in decided]
    ran = [r for r in decided if r["status"] != "skipped"]
    solved = [r for r in ran if r["status"] in ("realizable", "unrealizable")]
    ci = [r for r in rows if r["nike_ci"] == "yes"]
    ci_solved = sum(1 for r in ci if r["path"] in done and done[r["path"]]["status"] in ("realizable", "unrealizable"))
    times = sorted(float(r["cpu_seconds"]) for r in solved)
    median = f"{times[len(times) // 2]:.2f} / {times[-1]:.2f}" if times else "-"
    agree = sum(r.get("agrees") == "yes" for r in ran)
    disagree = sum(r.get("agrees") == "no" for r in ran)
    return (f"| {name} | {len(rows)} | {len(ran)} | {len(solved)} | {status.count('realizable')} / "
            f"{status.count('unrealizable')} | {status.count('timeout')} / {status.count('wall')} / "
            f"{status.count('memory')} / "
            f"{status.count('skipped')} | {agree} / {disagree} | {len(ci)} / {ci_solved} | {median} |")


def _load(load) -> str:
    return "/".join(f"{x:.1f}" for x in load)


if __name__ == "__main__":
    sys.exit(main())
