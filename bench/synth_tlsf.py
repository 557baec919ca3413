#!/usr/bin/env python3
"""Benchmark: `symsynth synth chomp.tlsf --param N=.. --param M=..` as a
process (SYNTCOMP's tlsf-fin chomp family, tests/data/tlsf-fin/), with each
DFA construction, against the verdict known for chomp (the first player, the
system here, wins every board but 1 x 1).

    python bench/synth_tlsf.py [--sizes 2x2,2x6,3x4,4x3] [--construction progression,compositional]
                               [--timeout 300] [--out bench/results/synth-tlsf.md]

Per size and construction: the wall time of the process (start-up and the
TLSF reading included), the DFA and game seconds the command prints
(`--json`), the DFA's states, the verdict, and the peak memory of the
process (its max RSS, when the platform reports it).  Run it under `nice -n 10`; the load average is
written beside the rows.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from provenance import commit  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CHOMP = ROOT / "tests" / "data" / "tlsf-fin" / "chomp.tlsf"


def run(n: int, m: int, construction: str, timeout: float) -> dict:
    command = [sys.executable, "-m", "symsynth.cli", "synth", str(CHOMP), "--param", f"N={n}", "--param", f"M={m}",
               "--json", "--construction", construction]
    start = time.perf_counter()
    try:  # (GNU time prints the process's max RSS in KB as the last line of stderr)
        done = subprocess.run(["/usr/bin/time", "-f", "%M", *command], capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"size": f"{n}x{m}", "construction": construction, "status": f"> {timeout:g} s"}
    wall = time.perf_counter() - start
    code, out, err = done.returncode, done.stdout, done.stderr
    peak = int(err.split()[-1]) / 1024
    lines = out.split()
    if code not in (10, 20):
        return {"size": f"{n}x{m}", "construction": construction, "status": f"exit {code}",
                "error": err.strip()[-200:]}
    summary = json.loads(out.splitlines()[1])
    expected = (n, m) != (1, 1)
    return {"size": f"{n}x{m}", "construction": construction, "status": "ok", "wall": wall,
            "dfa": summary["seconds"]["dfa"], "game": summary["seconds"]["game"],
            "states": summary["dfa_states"], "verdict": lines[0],
            "agrees": summary["realizable"] == expected, "peak_mb": peak}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="1x1,2x2,2x3,3x3,2x4,2x5,2x6,3x4,4x3")
    parser.add_argument("--construction", default="progression,compositional")
    parser.add_argument("--timeout", type=float, default=300.0)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    rows = []
    for construction in args.construction.split(","):
        for size in args.sizes.split(","):
            n, m = (int(x) for x in size.split("x"))
            load = os.getloadavg()[0]
            row = run(n, m, construction, args.timeout)
            row["load"] = load
            rows.append(row)
            print(json.dumps(row), flush=True)
    if args.out:
        lines = [f"# chomp (tlsf-fin) as `symsynth synth` processes, commit {commit()}", "",
                 "| size | construction | wall s | DFA s | game s | DFA states | verdict | as known | "
                 "peak MB | load |", "|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            if r["status"] != "ok":
                lines.append(f"| {r['size']} | {r['construction']} | {r['status']} | | | | | | | {r['load']:.1f} |")
                continue
            lines.append(f"| {r['size']} | {r['construction']} | {r['wall']:.2f} | {r['dfa']:.2f} | {r['game']:.3f} | "
                         f"{r['states']} | {r['verdict']} | {'yes' if r['agrees'] else 'NO'} | "
                         f"{r['peak_mb']:.0f} | {r['load']:.1f} |")
        args.out.write_text("\n".join(lines) + "\n")
    return 0 if all(r.get("agrees", True) for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
