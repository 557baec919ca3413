#!/usr/bin/env python3
"""The backward construction's minimal DFA of a URright formula, counted and
checked on random traces (issue 31: urright16, session 25).

    python bench/ltlf_backward_check.py N [--traces 3000] [--seed 16]

Runs `backward.backward_dfa` on urrightN (no transition bits: the DFA as
its numbered diagram, numbered.py), prints its states, listed nodes and
accepting states, CPU and wall seconds and peak memory, then reads random
traces (1-40 letters, each atom true with one probability per trace among
0.1 ... 0.9) through the diagram and compares each verdict with a direct
evaluation of p1 U (p2 R (... pN)) position by position from the end,
itself first compared with `holds` on 300 short traces.  Cap its memory
from outside (`prlimit --as=...`).
"""

from __future__ import annotations

import argparse
import random
import time

from ltlf_generated import urright
from symsynth.automata.backward import backward_dfa
from symsynth.automata.normal import nnf
from symsynth.automata.progression import Progression
from symsynth.logic import ast, holds, parse_ltlf


def peak_gb() -> float:
    with open("/proc/self/status") as status:
        fields = dict(line.split(":", 1) for line in status)
    return int(fields["VmHWM"].split()[0]) / 1e6


def direct(n: int, trace: list[frozenset]) -> bool:
    """urrightN on `trace`: U at odd positions of the chain, R at even ones."""
    last = len(trace) - 1
    value = [f"p{n}" in letter for letter in trace]
    for i in range(n - 1, 0, -1):
        left, out = [f"p{i}" in letter for letter in trace], [False] * len(trace)
        for k in range(last, -1, -1):
            later = k < last and out[k + 1]
            if i % 2:  # f U g = g | (f & X[!] (f U g))
                out[k] = value[k] or (left[k] and later)
            else:  # f R g = g & (f | WX (f R g))
                out[k] = value[k] and (left[k] or k == last or later)
        value = out
    return value[0]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", type=int, help="URright's size")
    parser.add_argument("--traces", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=16)
    args = parser.parse_args(argv)
    [(name, text)] = urright([args.n])
    parsed = parse_ltlf(text, next_semantics="weak")
    formula = nnf(parsed)
    cpu, wall = time.process_time(), time.time()
    dfa = backward_dfa(Progression([a.key for a in ast.atoms(formula)]), formula)
    diagram = dfa.numbered
    print(f"{name}: {diagram.num_states:,} states, {len(diagram.var):,} listed nodes, "
          f"{sum(dfa.accepting):,} accepting; {time.process_time() - cpu:.1f} s CPU, "
          f"{time.time() - wall:.1f} s wall, peak {peak_gb():.2f} GB", flush=True)
    atoms, var, low, high, roots = list(diagram.atoms), diagram.var, diagram.low, diagram.high, diagram.roots

    def accepts(trace: list[frozenset]) -> bool:
        state = 0
        for letter in trace:
            node = roots[state]
            while node >= len(roots):
                k = node - len(roots)
                node = high[k] if atoms[var[k]] in letter else low[k]
            state = node
        return dfa.accepting[state]

    rng = random.Random(args.seed)
    for _ in range(300):  # the direct evaluation against the reference semantics
        trace = [frozenset(a for a in atoms if rng.random() < 0.5) for _ in range(rng.randint(1, 5))]
        if not direct(args.n, trace) == holds(parsed, trace) == accepts(trace):
            raise SystemExit(f"disagree on {trace}")
    accepted = disagreements = 0
    for _ in range(args.traces):
        p = rng.choice([0.1, 0.3, 0.5, 0.7, 0.9])
        trace = [frozenset(a for a in atoms if rng.random() < p) for _ in range(rng.randint(1, 40))]
        verdict = accepts(trace)
        accepted += verdict
        disagreements += verdict != direct(args.n, trace)
    print(f"random traces: {args.traces}, accepted {accepted}, disagreements {disagreements}")
    return 1 if disagreements else 0


if __name__ == "__main__":
    raise SystemExit(main())
