#!/usr/bin/env python3
"""Benchmark: where the time of `symsynth synth` goes, phase by phase.

    python bench/synth_phases.py [PATH ...] [--data DIR] [--compose-up-to STATES] [--out FILE.md]

Each PATH is a `.ltlf` of the LTLf synthesis datasets (github.com/whitemech/
finite-synthesis-datasets, MIT; read from `--data`, a checkout or the bare
mirror, as in bench/synth_families.py) with its `.part`; default:
Double-Counter 01..06, System-first.  One process, the instances in turn,
CPU seconds (`time.process_time`) of each phase, agent first, X weak:

- dfa: `compile_ltlf`;
- game: `solve_realizability` (the fixpoint, with the clustered transition
  relation it builds past its first rounds: its clusters and nodes are
  listed; "-" where the game ended before);
- strategy: the BDD strategy (`symbolic_strategy`) and its JSON text;
- machine: the explicit machine and its JSON text, where it fits;
- compose: the earlier fixpoint, `bdd.let(delta, Acc | W)` each round,
  side by side in the same process (so the same load), on DFAs of at most
  `--compose-up-to` states; its rounds must equal the game's (exit 1
  otherwise).  It runs last, in the manager the others warmed (CUDD's
  computed table): that favours it (Double-Counter 05: 6.9 s here, 17 s
  in a process of its own).

The machine's load average is recorded at start and end.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_families import MIRROR, read  # noqa: E402
from provenance import commit  # noqa: E402

from symsynth.automata import compile_ltlf  # noqa: E402
from symsynth.logic import parse_ltlf  # noqa: E402
from symsynth.synthesis import read_partition, solve_realizability  # noqa: E402
from symsynth.synthesis import symbolic_strategy as symbolic  # noqa: E402
from symsynth.synthesis.machine import TooLarge, strategy_machine, write_json  # noqa: E402

COUNTERS = [f"Two-player-Game/Double-Counter/System-first/counters_{n:02d}.ltlf" for n in range(1, 7)]
PHASES = ("dfa", "game", "strategy", "machine", "compose")


def composed_rounds(dfa, partition):
    """The earlier fixpoint (agent first): Pre(Acc | W) with the transition
    functions substituted into Acc | W every round."""
    bdd = dfa.bdd
    xs = {a for a in dfa.atoms if a in partition.inputs}
    ys = {a for a in dfa.atoms if a in partition.outputs}
    rounds, win, old = [], bdd.false, None
    while win != old:
        old = win
        after = bdd.let(dict(dfa.delta), dfa.accepting | win) if dfa.bits else dfa.accepting | win
        win = win | bdd.exist(ys, bdd.forall(xs, after))  # \E y: \A x: (Acc | W)(delta)
        if win != old:
            rounds.append(win)
    return rounds


def phases(data: Path, path: str, compose_up_to: int, work: Path) -> dict:
    (work / "s.part").write_text(read(data, path[:-len(".ltlf")] + ".part"))
    partition = read_partition(work / "s.part")
    formula = parse_ltlf(read(data, path), source=path, next_semantics="weak")
    row: dict = {"instance": Path(path).stem}
    clock = time.process_time()

    def lap(name: str) -> None:
        nonlocal clock
        now = time.process_time()
        row[name] = now - clock
        clock = now
    dfa = compile_ltlf(formula)
    dfa.make_delta()  # (a backward DFA's transition bits: in "dfa", as before they were made on use)
    lap("dfa")
    game = solve_realizability(dfa, partition)
    lap("game")
    built = game.preimage.built
    row["relation"] = f"{len(game.preimage.clusters)} / {game.preimage.nodes:,}" if built else "-"
    row |= {"states": dfa.num_states, "bits": len(dfa.bits), "rounds": len(game.rounds),
            "realizable": game.realizable}
    if game.realizable:
        symbolic.write_json(symbolic.symbolic_strategy(game))
        lap("strategy")
        try:
            write_json(strategy_machine(game))
        except TooLarge:
            row["machine"] = None
        else:
            lap("machine")
    if dfa.num_states <= compose_up_to:
        clock = time.process_time()
        rounds = composed_rounds(dfa, partition)
        lap("compose")
        row["same_rounds"] = rounds == game.rounds
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("paths", nargs="*", default=COUNTERS)
    parser.add_argument("--data", type=Path, default=MIRROR)
    parser.add_argument("--compose-up-to", type=int, default=5000, metavar="STATES",
                        help="time the earlier fixpoint on DFAs of at most this many states")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args(argv)
    load_start, started = os.getloadavg(), time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for path in args.paths:
            row = phases(args.data, path, args.compose_up_to, Path(work))
            rows.append(row)
            print(" ".join(f"{k}={v:.3f}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()),
                  flush=True)
    load_end = os.getloadavg()

    def cell(row, name):
        value = row.get(name)
        return "-" if value is None else f"{value:.2f}"
    lines = ["| instance | DFA states | state bits | rounds | " + " | ".join(PHASES) + " | relation: clusters / nodes |",
             "|---|---:|---:|---:|" + "---:|" * len(PHASES) + "---|"]
    for row in rows:
        lines.append(f"| {row['instance']} | {row['states']:,} | {row['bits']} | {row['rounds']} | "
                     + " | ".join(cell(row, p) for p in PHASES)
                     + f" | {row['relation']} |")
    text = (f"`python bench/synth_phases.py{''.join(' ' + a for a in (argv or sys.argv[1:]))}`; symsynth commit "
            f"{commit()}; started {started}; load average (1/5/15 min) at start "
            f"{'/'.join(f'{x:.1f}' for x in load_start)}, at end {'/'.join(f'{x:.1f}' for x in load_end)}; "
            "CPU seconds per phase (module doc of bench/synth_phases.py).\n\n" + "\n".join(lines) + "\n")
    print(text)
    if args.out is not None:
        args.out.write_text(text)
    return 0 if all(r.get("same_rounds", True) for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
