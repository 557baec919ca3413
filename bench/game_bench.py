#!/usr/bin/env python3
"""Benchmark: the game solvers (explicit, symbolic, forward) on a growing pattern family.

    python bench/game_bench.py [--quick] [--sizes 1x2,2x3,...] [--solvers explicit,symbolic,forward]
                               [--limit SOLVER=NxM ...] [--timeout S] [--k K] [--seed S]
                               [--mem-limit GB] [--out FILE.md]

Family (bench/gamefamily.py): n blocks, m >= n + 1 locations, 2 Else samples,
grasp `top`, a human with k moves (default 3), the task one pattern
F(at(c1, l_p1) & ... & at(cn, l_pn)), a conditional costmap from a grid
layout.  Sizes (n, m) along 1x2 2x3 2x4 3x4 3x5 4x6 5x7 6x8 7x10 8x12.

Every (size, solver) runs alone in a fresh child process (this script with
`--worker`), one after the other, never two at once:
  time     the solver call itself, measured in the child (imports and the
           scene's construction excluded; the child's start-up is not timed);
  memory   the child's peak resident set (ru_maxrss from wait4 on that child:
           CUDD's C heap included), and its resident set just before the
           solver was called (Python, symsynth, the scene);
  value    E_p (cost_bound); all solvers that finish a size must agree, else
           a MISMATCH line is printed and the exit status is 2;
  states   the solver's `states`; `stats` (the symbolic solver's iterations,
           peak BDD nodes, time splits...) and `seconds` are listed as given.

A child is killed (SIGKILL, its whole process group) when it runs longer than
the time limit (default 600 s) or its resident set grows past the memory
limit (default 8 GB); the cell says TO or OOM, and the larger sizes are not
run for that solver (TO*, OOM*).

`--limit SOLVER=NxM` runs SOLVER only up to that size (one of --sizes); its
larger cells say "—" (not run), e.g. `--limit explicit=5x7`.

Targets (PASS/FAIL), for each solver other than explicit (the issue states
them for the symbolic one): (a) at least 10x faster than the explicit one at
the largest size the explicit one finishes (same run, side by side); (b)
8 objects x 12 locations x k = 3 solved in under 60 s.  Exit status 0 when
all pass, 1 when a target fails, 2 on a mismatch.
"""

from __future__ import annotations

import argparse
import functools
import inspect
import json
import os
import platform
import shlex
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from tqdm import tqdm

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from provenance import commit  # noqa: E402

ROOT = HERE.parent
DEFAULT_OUT = HERE / "results" / "game.md"
SIZES = [(1, 2), (2, 3), (2, 4), (3, 4), (3, 5), (4, 6), (5, 7), (6, 8), (7, 10), (8, 12)]
QUICK_SIZES = [(1, 2), (2, 3), (2, 4), (3, 4)]
#: NAME:variant -> the solver's options: `plain` without the reduction by
#: interchangeable objects, `reachable` (symbolic only) the attractor on the
#: positions a play from the start reaches
VARIANTS = {"plain": {"symmetric": False}, "reachable": {"reachable_only": True}}
TARGET_SPEEDUP = 10.0
TARGET_SIZE = (8, 12, 3)
TARGET_SECONDS = 60.0
POLL = 0.1  # s between checks of a running child


def log(msg):
    tqdm.write(msg, file=sys.stderr)


# ---------------------------------------------------------------------------
# The child: one solver on one scene
# ---------------------------------------------------------------------------

def worker(solver: str, n: int, m: int, k: int, seed: int, out: str, colours: int = 0,
           time_limit: float = 0.0) -> int:
    import resource

    result: dict = {"solver": solver}
    try:
        from gamefamily import pattern_scene
        from symsynth.solvers import SOLVERS, prepare

        clock = time.perf_counter()
        scene = pattern_scene(n, m, k=k, seed=seed, colours=colours or None)
        result["build_s"] = time.perf_counter() - clock
        name, _, variant = solver.partition(":")
        result["prepare_s"] = prepare(name)  # compiling kernels: not the solver's time
        solve = SOLVERS[name]
        if variant:
            solve = functools.partial(solve, **VARIANTS[variant])
        if time_limit and "time_limit" in inspect.signature(SOLVERS[name]).parameters:
            solve = functools.partial(solve, time_limit=time_limit)  # (the others answer exactly)
        result["base_kb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        clock = time.perf_counter()
        solution = solve(scene)
        result["solve_s"] = time.perf_counter() - clock
        result["cost_bound"] = solution.cost_bound
        result["lower"] = None if solution.exact else _plain(solution.lower_bound)
        result["states"] = solution.states
        result["seconds"] = {str(a): _plain(b) for a, b in dict(solution.seconds).items()}
        result["stats"] = {str(a): _plain(b) for a, b in solution.stats.items()}
        result["status"] = "ok"
    except BaseException as error:  # noqa: BLE001 - reported to the parent
        import traceback
        result["status"] = "ERR"
        result["error"] = f"{type(error).__name__}: {error}"
        result["traceback"] = traceback.format_exc()
    Path(out).write_text(json.dumps(result), encoding="utf-8")
    return 0


def _plain(x):
    if isinstance(x, (bool, int, float, str)) or x is None:
        return x
    try:
        return float(x)
    except (TypeError, ValueError):
        return str(x)


# ---------------------------------------------------------------------------
# The parent: run children with limits
# ---------------------------------------------------------------------------

@dataclass
class Cell:
    solver: str
    n: int
    m: int
    k: int
    status: str = "ok"            # ok, TO, OOM, ERR, TO*, OOM*, ERR*, n/a
    solve_s: float | None = None  # solver call, in the child
    prepare_s: float = 0.0        # the solver's once-per-process set-up, before the clock
    wall_s: float | None = None   # the child process, start to exit
    peak_mb: float | None = None
    base_mb: float | None = None
    cost_bound: float | None = None
    lower: float | None = None    # with --time-limit, an answer not proven exact: lower <= E_p <= cost_bound
    states: int | None = None
    seconds: dict = field(default_factory=dict)
    stats: dict = field(default_factory=dict)
    error: str | None = None

    @property
    def ok(self):
        return self.status == "ok"


def run_cell(solver, n, m, k, seed, timeout, mem_limit_mb, colours=0, time_limit=0.0) -> Cell:
    cell = Cell(solver, n, m, k)
    with tempfile.TemporaryDirectory(prefix="game_bench_") as tmp:
        out = Path(tmp) / "result.json"
        errfile = Path(tmp) / "stderr.txt"
        cmd = [sys.executable, str(Path(__file__).resolve()), "--worker", solver,
               str(n), str(m), str(k), str(seed), str(out), str(colours), str(time_limit)]
        with open(errfile, "wb") as err:
            start = time.perf_counter()
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                    stderr=err, start_new_session=True, cwd=ROOT)
            killed = None
            while True:
                pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
                if pid:
                    break
                elapsed = time.perf_counter() - start
                if killed is None:
                    if elapsed > timeout:
                        killed = "TO"
                    elif mem_limit_mb and _rss_mb(proc.pid) > mem_limit_mb:
                        killed = "OOM"
                    if killed:
                        try:
                            os.killpg(proc.pid, signal.SIGKILL)
                        except ProcessLookupError:
                            pass
                time.sleep(POLL)
            proc.returncode = os.waitstatus_to_exitcode(status)  # reaped by wait4
        cell.wall_s = time.perf_counter() - start
        cell.peak_mb = usage.ru_maxrss / 1024  # KiB on Linux
        if killed:
            cell.status = killed
            cell.solve_s = cell.wall_s
            return cell
        if not out.exists():
            cell.status = "ERR"
            tail = errfile.read_text(errors="replace").strip().splitlines()[-3:]
            cell.error = f"child exited with {proc.returncode}: " + " | ".join(tail)
            return cell
        result = json.loads(out.read_text(encoding="utf-8"))
    cell.status = result["status"]
    cell.error = result.get("error")
    if cell.status == "ERR":
        log(result.get("traceback", ""))
    cell.solve_s = result.get("solve_s")
    cell.prepare_s = result.get("prepare_s", 0.0)
    cell.base_mb = result["base_kb"] / 1024 if "base_kb" in result else None
    cell.cost_bound = result.get("cost_bound")
    cell.lower = result.get("lower")
    cell.states = result.get("states")
    cell.seconds = result.get("seconds", {})
    cell.stats = result.get("stats", {})
    return cell


def _rss_mb(pid: int) -> float:
    """Resident set of `pid`, in MB (Linux /proc; 0 once it is gone)."""
    total = 0
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1])
    except OSError:
        pass
    return total / 1024


# ---------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------

def fmt_s(cell: Cell | None) -> str:
    if cell is None:
        return ""
    if cell.status in ("TO", "OOM"):
        return f"{cell.status} ({cell.wall_s:.0f} s)"
    if cell.status == "n/a":
        return "—"
    if not cell.ok:
        return cell.status
    t = cell.solve_s
    return f"{t:.3f}" if t < 10 else f"{t:.1f}"


def fmt_mb(cell: Cell | None) -> str:
    if cell is None or cell.peak_mb is None:
        return ""
    s = f"{cell.peak_mb:.0f}"
    if cell.status in ("TO", "OOM"):
        return "≥" + s
    if cell.base_mb is not None:
        s += f" ({cell.base_mb:.0f})"
    return s


def fmt_num(x) -> str:
    if isinstance(x, bool) or x is None:
        return str(x)
    if isinstance(x, int):
        return f"{x:,}"
    if isinstance(x, float):
        if x.is_integer() and abs(x) < 1e15:
            return f"{int(x):,}"
        return f"{x:.3g}"
    return str(x)


def fmt_value(x) -> str:
    return "∞" if x is None else fmt_num(float(x))


def report(sizes, solvers, cells, meta, args):
    lines = ["# Game solvers on the pattern family", ""]
    lines += [f"- {key}: {value}" for key, value in meta.items()]
    lines += ["", "Time: the solver call in a fresh child process, s. Memory: the child's peak "
              "resident set, MB (in parentheses: before the solver was called). `TO`/`OOM`: killed "
              "at the limit; `*`: not run, a smaller size failed. A solver's once-per-process set-up "
              "(the compiled solver's kernels, compiled or loaded from numba's cache) runs before the "
              "clock starts: `prepare` in the splits.", ""]

    head = ["n", "m", "k"]
    for s in solvers:
        head += [f"{s} s", f"{s} MB", f"{s} states"]
    head += ["E_p"]
    compared = [s for s in solvers if s != "explicit"] if "explicit" in solvers else []
    head += [f"explicit/{s}" for s in compared]
    if args.time_limit:
        head += ["intervals [lower, upper] upper/lower"]
    lines.append("| " + " | ".join(head) + " |")
    lines.append("|" + "|".join("---:" for _ in head) + "|")
    mismatches = []
    for (n, m) in sizes:
        row = [str(n), str(m), str(args.k)]
        values = {}
        for s in solvers:
            c = cells.get((s, n, m))
            row += [fmt_s(c), fmt_mb(c), fmt_num(c.states) if c is not None and c.ok else ""]
            if c is not None and c.ok and c.lower is None:
                values[s] = c.cost_bound
        distinct = {v for v in values.values()}
        bounds = {s: (c.lower, c.cost_bound) for s in solvers
                  if (c := cells.get((s, n, m))) is not None and c.ok and c.lower is not None}
        if len(distinct) == 1 and any(not _holds(lo, up, next(iter(distinct))) for lo, up in bounds.values()):
            mismatches.append((n, m, {s: c.cost_bound for s in solvers
                                      if (c := cells.get((s, n, m))) is not None and c.ok}))
            row.append("**MISMATCH** " + ", ".join(f"{s} [{fmt_value(lo)}, {fmt_value(up)}]"
                                                    for s, (lo, up) in bounds.items())
                       + f" against {fmt_value(next(iter(distinct)))}")
        elif len(distinct) > 1:
            mismatches.append((n, m, values))
            row.append("**MISMATCH** " + ", ".join(f"{s} {fmt_value(v)}" for s, v in values.items()))
        else:
            row.append(fmt_value(next(iter(distinct))) if distinct else "")
        for s in compared:
            row.append(_ratio(cells.get(("explicit", n, m)), cells.get((s, n, m))))
        if args.time_limit:
            row.append("; ".join(f"{s} [{fmt_value(lo)}, {fmt_value(up)}]"
                                 + (f" {up / lo:.3f}" if up is not None and lo else "")
                                 for s, (lo, up) in bounds.items()))
        lines.append("| " + " | ".join(row) + " |")
    lines.append("")

    detail = [c for c in cells.values() if c.ok and (c.stats or c.seconds)]
    if detail:
        lines += ["### Solver splits and stats", "",
                  "| n | m | solver | seconds | stats |", "|---:|---:|---|---|---|"]
        for (n, m) in sizes:
            for s in solvers:
                c = cells.get((s, n, m))
                if c is None or not c.ok or not (c.seconds or c.stats):
                    continue
                secs = " ".join(f"{a}={fmt_num(b)}" for a, b in c.seconds.items())
                if c.prepare_s:
                    secs = f"(prepare={fmt_num(c.prepare_s)}) " + secs
                stats = " ".join(f"{a}={fmt_num(b)}" for a, b in c.stats.items())
                lines.append(f"| {n} | {m} | {s} | {secs} | {stats} |")
        lines.append("")
    errors = [c for c in cells.values() if c.status == "ERR"]
    if errors:
        lines += ["### Errors", ""]
        lines += [f"- {c.solver} {c.n}x{c.m}: {c.error}" for c in errors]
        lines.append("")

    verdicts = []  # (status, message); status PASS, FAIL or SKIP
    for s in [x for x in solvers if x != "explicit"] or ["symbolic"]:
        verdicts.append(_target_speedup(sizes, cells, solvers, s))
        verdicts.append(_target_size(sizes, cells, solvers, args, s))
    for n, m, values in mismatches:
        verdicts.append(("MISMATCH", f"{n}x{m}: E_p differs: "
                         + ", ".join(f"{s} {fmt_value(v)}" for s, v in values.items())))
    lines += ["## Targets", "", "```"]
    lines += [f"{status} {msg}" for status, msg in verdicts]
    lines += ["```", "", "This file is rewritten by every run; notes on a run and one-off experiments "
              "go in `game-notes.md` next to it.", ""]
    return "\n".join(lines), verdicts


def _holds(lower, upper, exact) -> bool:
    """Whether the interval [lower, upper] (upper None: no strategy proven) holds the exact value."""
    if exact is None:
        return upper is None
    return lower <= exact and (upper is None or exact <= upper)


def _ratio(e: Cell | None, y: Cell | None) -> str:
    if e is None or y is None or not y.ok or not y.solve_s:
        return ""
    if e.ok:
        return f"{e.solve_s / y.solve_s:.1f}x"
    if e.status in ("TO", "OOM"):
        return f">{e.wall_s / y.solve_s:.0f}x"
    return ""


def _target_speedup(sizes, cells, solvers, solver):
    what = (f"(a) {solver} >= {TARGET_SPEEDUP:.0f}x faster than explicit at the largest size "
            "explicit finishes")
    if "explicit" not in solvers or solver not in solvers:
        return "SKIP", f"{what}: needs --solvers explicit,{solver}"
    done = [(n, m) for (n, m) in sizes if (c := cells.get(("explicit", n, m))) is not None and c.ok]
    if not done:
        return "FAIL", f"{what}: explicit finished no size"
    n, m = done[-1]
    e, y = cells[("explicit", n, m)], cells.get((solver, n, m))
    if y is not None and y.status == "n/a":
        return "SKIP", f"{what}: {solver} not run at {n}x{m} (--limit)"
    if y is None or not y.ok:
        return "FAIL", f"{what}: at {n}x{m} explicit {e.solve_s:.2f} s, {solver} {y.status if y else 'not run'}"
    ratio = e.solve_s / y.solve_s if y.solve_s else float("inf")
    return ("PASS" if ratio >= TARGET_SPEEDUP else "FAIL",
            f"{what}: at {n}x{m}, explicit {e.solve_s:.2f} s / {solver} {y.solve_s:.3f} s = {ratio:.1f}x")


def _target_size(sizes, cells, solvers, args, solver):
    n, m, k = TARGET_SIZE
    what = f"(b) {n} objects x {m} locations x k={k} solved by {solver} in < {TARGET_SECONDS:.0f} s"
    if solver not in solvers or (n, m) not in sizes or args.k != k:
        return "SKIP", f"{what}: not in this run (--sizes/--k/--solvers)"
    c = cells.get((solver, n, m))
    if c is None or c.status == "n/a":
        return "SKIP", f"{what}: not run (--limit)"
    if not c.ok:
        return "FAIL", f"{what}: {c.status}" + (f" ({c.error})" if c.error else "")
    if c.cost_bound is None:  # m >= n + 1 and a finite k: the pattern is always achievable
        return "FAIL", f"{what}: E_p infinite, but every scene of the family is winnable"
    return ("PASS" if c.solve_s < TARGET_SECONDS else "FAIL",
            f"{what}: {c.solve_s:.2f} s, peak {c.peak_mb:.0f} MB, E_p {fmt_value(c.cost_bound)}")


def environment(args):
    meta = {"date": time.strftime("%Y-%m-%d %H:%M:%S %Z"), "symsynth commit": commit(),
            "machine": f"{platform.machine()}, {os.cpu_count()} CPUs, {platform.platform()}",
            "python": platform.python_version()}
    try:
        meta["load average at start"] = " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        pass
    try:
        from importlib.metadata import version
        meta["versions"] = f"symsynth {version('symsynth')}, dd {version('dd')}"
    except Exception:
        pass
    if args.colours:
        meta["family"] = (f"bench/gamefamily.py pattern_scene(n, m, k={args.k}, seed={args.seed}, "
                          f"colours={args.colours}): the sorting variant, n blocks in {args.colours} "
                          "colours, m locations, 2 Else samples, grasp top, F(pattern over colours)")
    else:
        meta["family"] = (f"bench/gamefamily.py pattern_scene(n, m, k={args.k}, seed={args.seed}): "
                          "n blocks, m locations, 2 Else samples, grasp top, F(pattern)")
    meta["settings"] = (f"time limit {args.timeout:g} s, memory limit "
                        + (f"{args.mem_limit:g} GB" if args.mem_limit else "none")
                        + (", --quick" if args.quick else "") + (", --no-skip" if args.no_skip else "")
                        + (f", --time-limit {args.time_limit:g} s per solve" if args.time_limit else ""))
    return meta


def parse_sizes(text):
    """'4x6,5x7' -> [(4, 6), (5, 7)]; ValueError naming the part that is not NxM."""
    out = []
    for part in text.split(","):
        part = part.strip()
        if not part:
            continue
        n, x, m = part.lower().partition("x")
        if not (x and n.isdigit() and m.isdigit()):
            raise ValueError(f"{part!r} is not NxM (e.g. 5x7)")
        out.append((int(n), int(m)))
    return out


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv and argv[0] == "--worker":
        solver, n, m, k, seed, out, colours, time_limit = argv[1:9]
        return worker(solver, int(n), int(m), int(k), int(seed), out, int(colours), float(time_limit))

    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--quick", action="store_true",
                   help=f"smoke run: sizes {','.join(f'{n}x{m}' for n, m in QUICK_SIZES)}, 30 s limit")
    p.add_argument("--sizes", default=None,
                   help="comma-separated NxM (default: " + ",".join(f"{n}x{m}" for n, m in SIZES) + ")")
    p.add_argument("--solvers", default="explicit,symbolic,forward")
    p.add_argument("--timeout", type=float, default=None, help="per run, s (default 600; 30 with --quick)")
    p.add_argument("--mem-limit", type=float, default=8.0, help="GB of resident memory per run (0: none)")
    p.add_argument("--k", type=int, default=3, help="human moves (default 3)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--colours", type=int, default=0, metavar="C",
                   help="the sorting variant: n blocks in C colours (default 0: every block its own colour)")
    p.add_argument("--no-skip", action="store_true", help="run larger sizes even after a failure")
    p.add_argument("--limit", action="append", default=[], metavar="SOLVER=NxM",
                   help="run SOLVER only up to size NxM (in the order of --sizes); repeatable")
    p.add_argument("--time-limit", type=float, default=0.0, metavar="S",
                   help="seconds of search given to every solver that takes time_limit (forward, andor, "
                        "compiled, auto); an answer not proven in time is the interval [lower, upper]")
    p.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"markdown file (default {DEFAULT_OUT})")
    args = p.parse_args(argv)
    if not args.time_limit >= 0:
        p.error(f"--time-limit {args.time_limit:g}: expected seconds >= 0 (0: none)")
    if args.timeout is not None and not args.timeout > 0:
        p.error(f"--timeout {args.timeout:g}: expected a positive number of seconds")
    args.timeout = args.timeout or (30.0 if args.quick else 600.0)
    if args.k < 0:
        p.error(f"--k {args.k}: expected a number of human moves >= 0")
    if not args.mem_limit >= 0:
        p.error(f"--mem-limit {args.mem_limit:g}: expected GB >= 0 (0: no limit)")
    try:
        sizes = parse_sizes(args.sizes) if args.sizes else (QUICK_SIZES if args.quick else SIZES)
    except ValueError as err:
        p.error(f"--sizes: {err}")
    for n, m in sizes:
        if m < n + 1:
            p.error(f"size {n}x{m}: m must be >= n + 1")
    solvers = [s.strip() for s in args.solvers.split(",") if s.strip()]
    if not sizes or not solvers:  # nothing to run, and --out would be overwritten with it
        p.error("--sizes and --solvers must each name at least one")

    from symsynth.solvers import SOLVERS
    unknown = [s for s in solvers if s.partition(":")[0] not in SOLVERS
               or s.partition(":")[2] not in ("", *VARIANTS)
               or s.partition(":")[2] == "reachable" and s.partition(":")[0] != "symbolic"]
    if unknown:
        p.error(f"unknown solver(s) {', '.join(unknown)}; registered: {', '.join(SOLVERS)} "
                "(NAME:plain: without the reduction by interchangeable objects; "
                "symbolic:reachable: the attractor on the positions a play reaches)")
    runnable = solvers
    limits: dict[str, tuple[int, int]] = {}
    for item in args.limit:
        name, _, size = item.partition("=")
        if name not in solvers or not size:
            p.error(f"--limit {item}: expected SOLVER=NxM with SOLVER among --solvers")
        if name in limits:
            p.error(f"--limit {item}: {name} is already limited to {limits[name][0]}x{limits[name][1]}")
        try:
            parsed = parse_sizes(size)
        except ValueError as err:
            p.error(f"--limit {item}: {err}")
        if len(parsed) != 1:
            p.error(f"--limit {item}: expected one size NxM")
        limits[name] = parsed[0]
        if limits[name] not in sizes:
            # a limit that matches no size would never stop the solver
            p.error(f"--limit {item}: {size} is not among the sizes "
                    f"({', '.join(f'{a}x{b}' for a, b in sizes)})")
    beyond: set[str] = set()

    meta = environment(args)
    meta["command"] = "`python bench/game_bench.py " + shlex.join(argv) + "`"
    cells: dict[tuple[str, int, int], Cell] = {}
    failed: dict[str, str] = {}
    bar = tqdm(total=len(sizes) * len(runnable), file=sys.stderr, unit="run")
    try:
        for n, m in sizes:
            for s in runnable:
                if s in beyond:
                    cells[(s, n, m)] = Cell(s, n, m, args.k, status="n/a")
                    bar.update()
                    continue
                if limits.get(s) == (n, m):
                    beyond.add(s)  # this size is the last
                if s in failed and not args.no_skip:
                    cells[(s, n, m)] = Cell(s, n, m, args.k, status=failed[s] + "*")
                    bar.update()
                    continue
                bar.set_description(f"{s} {n}x{m}")
                cell = run_cell(s, n, m, args.k, args.seed, args.timeout, args.mem_limit * 1024, args.colours,
                                args.time_limit)
                cells[(s, n, m)] = cell
                bar.update()
                if cell.ok:
                    extra = " ".join(f"{a}={fmt_num(b)}" for a, b in cell.stats.items())
                    value = (fmt_value(cell.cost_bound) if cell.lower is None
                             else f"in [{fmt_value(cell.lower)}, {fmt_value(cell.cost_bound)}]")
                    log(f"{s:>9} {n}x{m}: {cell.solve_s:8.3f} s  {cell.peak_mb:7.0f} MB  "
                        f"E_p {value}  states {fmt_num(cell.states)}  {extra}")
                else:
                    log(f"{s:>9} {n}x{m}: {cell.status} after {cell.wall_s:.0f} s, "
                        f"peak {cell.peak_mb:.0f} MB" + (f": {cell.error}" if cell.error else ""))
                    failed[s] = cell.status
            values = {s: cells[(s, n, m)].cost_bound for s in runnable
                      if cells[(s, n, m)].ok and cells[(s, n, m)].lower is None}
            if len(set(values.values())) > 1:
                log(f"!!!!!!!! MISMATCH at {n}x{m}: "
                    + ", ".join(f"{s} E_p = {fmt_value(v)}" for s, v in values.items()) + " !!!!!!!!")
    finally:
        bar.close()

    try:
        meta["load average at end"] = " ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        pass
    text, verdicts = report(sizes, solvers, cells, meta, args)
    print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text + "\n", encoding="utf-8")
    log(f"wrote {args.out}")
    if any(status == "MISMATCH" for status, _ in verdicts):
        return 2
    return 1 if any(status == "FAIL" for status, _ in verdicts) else 0


if __name__ == "__main__":
    sys.exit(main())
