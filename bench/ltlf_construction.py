#!/usr/bin/env python3
"""Benchmark: the DFA constructions side by side, in-process (issue 31, the
automatic choice of docs/ltlf.md, "Choosing the construction").

    python bench/ltlf_construction.py [--constructions auto,compositional] [--timeout 20]
                                      FAMILY[:FROM-TO] ...

Families: the generated ones of `bench/ltlf_generated.py` (ours: Rright,
URright, Uconj, AG, Dwyer, TV) and the datasets' of `bench/ltlf_families.py`
(Uright, GFand, Single-Counter, Double-Counter, Nim, Syft, Lydia), a slice
FROM-TO of each when given.  Per formula and construction, in a fresh
process each: the CPU seconds of `compile_ltlf` (plain X weak), the minimal
DFA's states, and which construction ran (`auto`: the rule's reason, and
whether the compositional construction was called).  One line of JSON per
formula on stdout.  The children import the installed symsynth (an editable
install: the working copy): to compare two commits, run it with
PYTHONPATH=CHECKOUT for each (running it from a checkout is not enough).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_families import MIRROR, instances, read  # noqa: E402
from ltlf_generated import generated  # noqa: E402

CHILD = r'''
import json, sys, time
from symsynth.automata import choice, compiler, compose
from symsynth.logic.parser import parse_ltlf
formula = parse_ltlf(sys.stdin.read(), next_semantics="weak")
reason = choice.rule(formula)
used = []
original = compose.Composer.compose
def counted(self, f):
    used.append(1)
    return original(self, f)
compose.Composer.compose = counted
backward = []
built_backward = compiler.backward_dfa
def counted_backward(*args, **kwargs):
    found = built_backward(*args, **kwargs)
    backward.append(1)
    return found
compiler.backward_dfa = counted_backward
start = time.process_time()
dfa = compiler.compile_ltlf(formula, construction=sys.argv[1])
dfa.make_delta()  # (a backward DFA's transition bits: timed, as before they were made on use)
print(json.dumps({"states": dfa.num_states, "cpu": round(time.process_time() - start, 3),
                  "ran": "compositional" if used else "backward" if backward else "progression",
                  "rule": reason}))
'''


def formulas(spec: str) -> list[tuple[str, str, str]]:
    family, _, part = spec.partition(":")
    ours = generated([family])
    if family in ours:
        items = ours[family]
    else:
        items = [(f"{Path(p).parent.name}/{Path(p).stem}", read(MIRROR, p)) for p in instances(MIRROR)[family]]
    if part:
        low, high = (int(x) for x in part.split("-"))
        items = items[low:high]
    return [(family, name, text) for name, text in items]


def run(text: str, construction: str, timeout: float) -> dict:
    try:
        done = subprocess.run([sys.executable, "-c", CHILD, construction], input=text, capture_output=True,
                              text=True, timeout=timeout, cwd="/")
    except subprocess.TimeoutExpired:
        return {"status": f"> {timeout:g} s wall"}
    if done.returncode != 0:
        return {"status": "error: " + (done.stderr.strip().splitlines() or ["?"])[-1][:100]}
    return json.loads(done.stdout)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("families", nargs="+", help="FAMILY or FAMILY:FROM-TO")
    parser.add_argument("--constructions", default="auto,compositional")
    parser.add_argument("--timeout", type=float, default=20.0, help="wall seconds per process")
    args = parser.parse_args(argv)
    for spec in args.families:
        for family, name, text in formulas(spec):
            row = {"family": family, "instance": name}
            for construction in args.constructions.split(","):
                row[construction] = run(text, construction, args.timeout)
            print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
