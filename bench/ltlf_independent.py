#!/usr/bin/env python3
"""Benchmark: compiling n independent one-step invariants (issue 17).

    python bench/ltlf_independent.py --before DIR [--sizes 10,20,...] [--timeout 120]
                                     [--out bench/results/ltlf-independent.md]

The formula is `G(a1 -> X b1) & ... & G(an -> X bn)` (distinct atoms per
conjunct); its minimal DFA has 2^n + 2 states (tests/test_symbolic_minimize.py
works it out), each conjunct a 4-state component of the symbolic product.
`compile_ltlf` is timed for the code in `--before` (a checkout of an earlier
commit, e.g. `git worktree add /tmp/before <commit>`) and for this checkout,
side by side in one run: each call in a fresh process (imports and the
grammar excluded by a warm-up compilation), one after the other for each n,
with a time limit; after a timeout the larger sizes of that side are not run.
The state count of both sides is checked against 2^n + 2.  The load average
(1 min) is recorded per row: both sides of a row ran under about the same load.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))

from symsynth.files import write_atomic  # noqa: E402

SIZES = (10, 20, 40, 80, 160, 300)

WORKER = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
from symsynth.automata import compile_ltlf
n = int(sys.argv[2])
compile_ltlf("G(a -> X b) & G(c -> X d)")  # warm-up: imports, grammar
text = " & ".join(f"G(a{i} -> X b{i})" for i in range(n))
clock = time.perf_counter()
dfa = compile_ltlf(text)
seconds = time.perf_counter() - clock
print(json.dumps({"seconds": seconds, "minimal": dfa.num_states == float(2 ** n + 2),
                  "bits": len(dfa.bits)}))
"""


def run(code: Path, n: int, timeout: float) -> dict:
    try:
        out = subprocess.run([sys.executable, "-c", WORKER, str(code), str(n)], capture_output=True,
                             text=True, timeout=timeout, check=True)
    except subprocess.TimeoutExpired:
        return {"seconds": None}
    return json.loads(out.stdout.strip().splitlines()[-1])


def cell(result: dict | None, timeout: float) -> str:
    if result is None:
        return f"TO* (> {timeout:g} s)"
    if result["seconds"] is None:
        return f"TO (> {timeout:g} s)"
    return f"{result['seconds']:.3f}" + ("" if result["minimal"] else " (NOT 2^n+2 states)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, required=True, help="checkout of the earlier code")
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)))
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--out", type=Path, default=HERE / "results" / "ltlf-independent.md")
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",")]
    before_rev = subprocess.run(["git", "-C", str(args.before), "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True).stdout.strip()
    after_rev = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                               capture_output=True, text=True).stdout.strip()
    rows = []
    stopped = {"before": False, "after": False}
    for n in sizes:
        row: dict = {"n": n, "load": round(os.getloadavg()[0], 2)}
        for side, code in (("before", args.before), ("after", ROOT)):
            row[side] = None if stopped[side] else run(code, n, args.timeout)
            if row[side] is not None and row[side]["seconds"] is None:
                stopped[side] = True
        rows.append(row)
        print(json.dumps(row), flush=True)
    lines = [
        "# n independent one-step invariants: compile_ltlf before and after (issue 17)",
        "",
        f"Command: `nice -n 10 python bench/ltlf_independent.py --before <checkout of {before_rev}> "
        f"--sizes {args.sizes} --timeout {args.timeout:g}`; before: {before_rev}, after: {after_rev}; "
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}. "
        "Formula `G(a1 -> X b1) & ... & G(an -> X bn)`, minimal DFA 2^n + 2 states (checked on both "
        "sides). Seconds of one `compile_ltlf` call in a fresh process after a warm-up; TO: over the "
        "limit; TO*: not run after a smaller n timed out. Load: 1-minute load average at the start of "
        "the row (2 cores, shared machine).",
        "",
        "| n | state bits | before s | after s | load |",
        "|---:|---:|---:|---:|---:|",
    ]
    for row in rows:
        bits = next((r["bits"] for r in (row["after"], row["before"]) if r and r.get("bits")), "")
        lines.append(f"| {row['n']} | {bits} | {cell(row['before'], args.timeout)} | "
                     f"{cell(row['after'], args.timeout)} | {row['load']} |")
    write_atomic(args.out, "\n".join(lines) + "\n", "the benchmark table")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
