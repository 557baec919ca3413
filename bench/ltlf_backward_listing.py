#!/usr/bin/env python3
"""How far the backward construction lists the states of a URright formula
within a CPU budget (issue 31: urright16, which no run has finished).

    python bench/ltlf_backward_listing.py N [--budget SECONDS] [--every SECONDS]

The loop of `backward.backward_dfa` without the moves (expand a state,
walk its successors, number the new ones), printing the states expanded
and found, CPU seconds and peak memory every `--every` seconds and at the
end (the budget spent or every state expanded).  Cap its memory from
outside (`prlimit --as=...`): the listing holds every state and every
composed set.
"""

from __future__ import annotations

import argparse
import resource
import time

from ltlf_generated import urright
from symsynth.automata.backward import Backward
from symsynth.automata.bdd import exits
from symsynth.automata.normal import nnf
from symsynth.automata.progression import Progression
from symsynth.logic import ast, parse_ltlf


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("n", type=int, help="URright's size (even)")
    parser.add_argument("--budget", type=float, default=900.0, help="CPU seconds")
    parser.add_argument("--every", type=float, default=60.0, help="CPU seconds between two lines")
    args = parser.parse_args(argv)
    [(name, text)] = urright([args.n])
    formula = nnf(parse_ltlf(text))
    progression = Progression([a.key for a in ast.atoms(formula)])
    began = time.process_time()
    automaton = Backward(progression, formula)
    print(f"{name}: {len(automaton.step)} obligations, {automaton.bdd.count(automaton.reach, len(automaton.step)):,.0f} "
          f"reachable vectors, {time.process_time() - began:.1f} s", flush=True)
    start = automaton.initial()
    index, order, walked, said = {start: 0}, [start], set(), began
    for done, state in enumerate(order, 1):
        for node in exits(progression.bdd, automaton.successors(state), len(progression.atom_keys), walked):
            if node not in index:
                index[node] = len(order)
                order.append(node)
        now = time.process_time()
        if now - said >= args.every or now - began >= args.budget or done == len(order):
            said = now
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
            print(f"{now - began:.0f} s CPU: {done:,} expanded, {len(order):,} found, peak {peak:.2f} GB", flush=True)
            if now - began >= args.budget:
                break
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
