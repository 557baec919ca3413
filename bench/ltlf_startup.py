#!/usr/bin/env python3
"""Benchmark: `symsynth dfa` as a process, two checkouts side by side (issue
31's start-up), with raw MONA in the same rounds.

    python bench/ltlf_startup.py --base /tmp/base-CHECKOUT [--now /tmp/CHECKOUT]
                                 [--only counter_02,...] [--reps 7] [--out bench/results/ltlf-startup.md]

Each round runs, for each formula, `symsynth dfa -f FILE` of `--now` (a
checkout, default the installed symsynth: then leave its files alone while
it runs), of `--base` (a checkout of an earlier commit, imported through
PYTHONPATH) with its bytecode compiled, of `--base` without bytecode
(PYTHONDONTWRITEBYTECODE=1 and its __pycache__ folders removed first: every
module compiled from source in every process, as the runs of
`ltlf_process.py` before its warm-up were), and `mona -q -u -w` on
ltlf2dfa's program: interleaved, so that the machine's load falls on all
alike.  Medians of CPU seconds (user + system of the process) and wall
seconds over the rounds.  The formulas: `ltlf_process.py`'s families, by
instance name (default: the nine it missed at commit d7effbb, and `a U b`).
"""

from __future__ import annotations

import argparse
import compileall
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_workers import MONA_FLAGS  # noqa: E402
from ltlf_families import MIRROR, mona_program, peer_text  # noqa: E402
from ltlf_generated import generated  # noqa: E402
from ltlf_process import DATASETS, dataset_formulas  # noqa: E402

MISSED = ("urright08,counter_02,counter_03,counter_06,nim_02_01,syft_1/001,syft_2/003,syft_3/003,syft_3/004")
FAMILIES = {"urright": "URright", "counter": "Single-Counter", "nim": "Nim", "syft": "Syft"}


def formulas(names: list[str]) -> list[tuple[str, str]]:
    found = {"a_U_b": "a U b"}
    for family in sorted({FAMILIES[n.split("_")[0].rstrip("0123456789")] for n in names if n != "a_U_b"}):
        items = generated([family])[family] if family not in DATASETS else dataset_formulas(MIRROR, family)
        found.update(items)
    return [(n, found[n]) for n in names]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", type=Path, required=True, help="a checkout of the earlier commit")
    parser.add_argument("--now", type=Path, help="a checkout of the later commit (default: the installed one)")
    parser.add_argument("--only", default="a_U_b," + MISSED)
    parser.add_argument("--reps", type=int, default=7)
    parser.add_argument("--out", type=Path, default=Path("bench/results/ltlf-startup.md"))
    args = parser.parse_args(argv)
    base = args.base.resolve()
    base_commit = subprocess.run(["git", "-C", str(base), "rev-parse", "--short", "HEAD"], capture_output=True,
                                 text=True, check=True).stdout.strip()
    import symsynth
    now = args.now.resolve() if args.now else Path(symsynth.__file__).resolve().parents[1]
    compileall.compile_dir(str(now / "symsynth"), quiet=1)
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    now_commit = subprocess.run(["git", "-C", str(now), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
    cold_base = Path(tempfile.mkdtemp(prefix="ltlf_startup_cold_")) / "base"
    shutil.copytree(base, cold_base, ignore=shutil.ignore_patterns("__pycache__", ".git"))
    compileall.compile_dir(str(base / "symsynth"), quiet=1)
    dfa = [sys.executable, "-m", "symsynth.cli", "dfa", "--max-states", "0", "-f"]
    setups = {
        "now": (dfa, {**env, "PYTHONPATH": str(now)} if args.now else env),
        "base": (dfa, {**env, "PYTHONPATH": str(base)}),
        "base, no bytecode": (dfa, {**env, "PYTHONPATH": str(cold_base), "PYTHONDONTWRITEBYTECODE": "1"}),
    }
    for command, environment in setups.values():  # (the parser tables cached, as after a first run)
        _once([*command[:-1], "a"], environment)
    items = formulas(args.only.split(","))
    cpu: dict[tuple[str, str], list[float]] = {}
    wall: dict[tuple[str, str], list[float]] = {}
    loads = []
    with tempfile.TemporaryDirectory(prefix="ltlf_startup_") as tmp:
        for name, text in items:
            spec = Path(tmp) / f"{name.replace('/', '_')}.ltlf"
            spec.write_text(text)
            from symsynth.logic import parse_ltlf
            Path(tmp, spec.stem + ".mona").write_text(mona_program(peer_text(parse_ltlf(text, next_semantics="weak"))))
        for _ in range(args.reps):
            loads.append(os.getloadavg()[0])
            for name, _text in items:
                spec = Path(tmp) / f"{name.replace('/', '_')}.ltlf"
                runs = {label: ([*command, str(spec)], environment) for label, (command, environment) in setups.items()}
                runs["MONA"] = (["mona", *MONA_FLAGS, str(spec.with_suffix(".mona"))], env)
                for label, (command, environment) in runs.items():
                    seconds, cpu_seconds = _once(command, environment)
                    wall.setdefault((name, label), []).append(seconds)
                    cpu.setdefault((name, label), []).append(cpu_seconds)
    labels = [*setups, "MONA"]
    lines = ["# `symsynth dfa` start-up: this commit against an earlier one, as processes", "",
             f"Command: `python bench/ltlf_startup.py --base CHECKOUT --only {args.only} --reps {args.reps}`; "
             f"now = {now_commit}, base = {base_commit}; {os.cpu_count()} cores shared with other jobs (load "
             f"average {min(loads):.1f} to {max(loads):.1f}). Medians over {args.reps} interleaved rounds of CPU "
             "seconds (user + system of the process) / wall seconds. `now` and `base` with their bytecode compiled "
             "and the parser's tables cached where that commit caches them; `base, no bytecode`: every module "
             "compiled from source in each process (PYTHONDONTWRITEBYTECODE=1, as this machine's environment "
             "sets it). Target: max(0.3 s, 2 x MONA) of CPU.", "",
             "| formula | " + " | ".join(labels) + " | target (now) |",
             "|---|" + "---:|" * len(labels) + "---|"]
    for name, _text in items:
        cells = [f"{statistics.median(cpu[name, label]):.3f} / {statistics.median(wall[name, label]):.3f}"
                 for label in labels]
        target = max(0.3, 2 * statistics.median(cpu[name, "MONA"]))
        verdict = "met" if statistics.median(cpu[name, "now"]) <= target else "MISSED"
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {verdict} |")
        print(lines[-1], flush=True)
    from symsynth.files import write_atomic
    write_atomic(args.out, "\n".join(lines) + "\n", "the benchmark table")
    shutil.rmtree(cold_base.parent)
    return 0


def _once(command: list[str], env: dict[str, str]) -> tuple[float, float]:
    """(wall seconds, CPU seconds) of one run, in a folder of no checkout
    (`python -m` puts the current folder first on the module path)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    clock = time.perf_counter()
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=60.0, cwd=tempfile.gettempdir())
    seconds = time.perf_counter() - clock
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)}: {done.stderr.strip()[-200:]}")
    return seconds, (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)


if __name__ == "__main__":
    sys.exit(main())
