"""What contacts cost the solvers: the game family (bench/gamefamily.py) with
and without one displacement contact (`push`), side by side in one run.

    python bench/contacts_bench.py [--sizes 3x5,4x6] [--k 2] [--timeout 300]
                                   [--solvers symbolic,explicit,forward] [-o bench/results/contacts.md]

With the contact, every object can also be slid between any two locations
(semantics §4b): the costmap gets motions in mode `empty` to every `x/push`
from every anchor and from every `x/push` to every `x/top`, costed like the
family's motions (distance on the layout, detours over places in between),
and a slide rule for every ordered pair of locations, costed as a carry
plus 2 (a slide over places in between has the family's two rules: around,
or straight when they are free).  The task and everything else is the
family's, so the comparison isolates the contact: more end-effector values
(objects x (grasps + contacts)), one more robot relation, and moves that
reach a goal without grab and drop (the forward solver's lower bound is 0
with contacts).

A benchmark family of this project's own design (not a public one); the
point is the ratio with and without the contact, each solver run in a
child process of its own, one at a time, with the same timeout.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))
from gamefamily import layout, motion_rules, pattern_data  # noqa: E402

SLIDE_EXTRA = 2


def with_contact(data: dict) -> dict:
    """The family's scene with the contact `push` (module doc)."""
    data = json.loads(json.dumps(data))
    locations, samples = data["locations"], data["else_samples"]
    places = locations + samples
    points = layout(locations, samples)
    grasps = data["grasps"]
    anchors = [("home", "home")] + [(f"{x}/{a}", x) for x in places for a in grasps + ["push"]]
    motions = data["costmap"]["motions"]
    for x in places:
        for s, ps in anchors:
            if s != f"{x}/push":
                motions.append({"mode": "empty", "from": s, "to": f"{x}/push",
                                "rules": motion_rules(points, ps, x, places)})
        for g in grasps:
            for y in places:
                motions.append({"mode": "empty", "from": f"{y}/push", "to": f"{x}/{g}",
                                "rules": motion_rules(points, y, x, places)})
    slides = []
    for l in locations:
        for m in locations:
            if l != m:
                rules = [dict(r, cost=r["cost"] + SLIDE_EXTRA) for r in motion_rules(points, l, m, places)]
                slides.append({"contact": "push", "from": l, "to": m, "rules": rules})
    data["contacts"] = ["push"]
    data["costmap"]["slides"] = slides
    return data


def run(path: Path, solver: str, timeout: float) -> dict:
    clock = time.perf_counter()
    try:
        done = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(path), "--solver", solver,
                               "--json"], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "seconds": timeout}
    seconds = time.perf_counter() - clock
    if done.returncode != 0:
        return {"status": "error", "seconds": seconds, "message": done.stderr.strip().splitlines()[-1:]}
    out = json.loads(done.stdout)
    return {"status": "ok", "seconds": seconds, "cost_bound": out["cost_bound"], "states": out.get("states")}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", default="3x5,4x6")
    parser.add_argument("--k", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=300)
    parser.add_argument("--solvers", default="symbolic,explicit,forward")
    parser.add_argument("-o", "--output", default="bench/results/contacts.md")
    args = parser.parse_args(argv)
    sizes = [tuple(map(int, s.split("x"))) for s in args.sizes.split(",")]
    solvers = args.solvers.split(",")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n, m in sizes:
            base = pattern_data(n, m, k=args.k)
            for label, data in (("without", base), ("with push", with_contact(base))):
                path = Path(tmp) / f"family-{n}x{m}-{label.replace(' ', '-')}.yaml"
                path.write_text(yaml.safe_dump(data))
                for solver in solvers:
                    result = run(path, solver, args.timeout)
                    rows.append((n, m, label, solver, result))
                    print(n, m, label, solver, result, flush=True)
    lines = ["# Contacts on the game family: time with and without one displacement contact",
             "",
             f"Command: `python bench/contacts_bench.py --sizes {args.sizes} --k {args.k} "
             f"--timeout {args.timeout:g} --solvers {args.solvers}`",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
             "wall seconds of `symsynth solve` in a child process (start-up included), one run each.",
             "A family of this project's design (bench/gamefamily.py), not a public benchmark.",
             "",
             "| n x m | solver | E_p without | s without | E_p with push | s with push | ratio |",
             "|---|---|---:|---:|---:|---:|---:|"]
    for n, m in sizes:
        for solver in solvers:
            cell = {label: r for (a, b, label, s, r) in rows if (a, b, s) == (n, m, solver)}
            plain, push = cell["without"], cell["with push"]

            def show(r):
                return (f"{r['seconds']:.2f}" if r["status"] == "ok" else r["status"],
                        "inf" if r.get("cost_bound") is None and r["status"] == "ok" else str(r.get("cost_bound", "-")))
            (s0, v0), (s1, v1) = show(plain), show(push)
            ratio = f"{push['seconds'] / plain['seconds']:.1f}x" if plain["status"] == push["status"] == "ok" else "-"
            lines.append(f"| {n} x {m} | {solver} | {v0} | {s0} | {v1} | {s1} | {ratio} |")
    Path(args.output).write_text("\n".join(lines) + "\n")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
