#!/usr/bin/env python3
"""Benchmark: explicit products made from guards against the same products
made from moves (symsynth/automata/moves.py), side by side in one process.

    python bench/moves_products.py [--data DIR] [--out bench/results/moves-products.md]

Compiles instances of the public LTLf synthesis datasets (Nim, Random/Syft,
Random/Lydia, the counters; github.com/whitemech/finite-synthesis-datasets,
MIT) and, at every explicit product the composer makes whose operands have at
least 20 state pairs, times the product (with its minimization) both ways:
`explicit_product(..., moves_pairs=inf)` (guards; an operand given by its
moves has its edges split off first, not timed) and `moves_pairs=0`
(moves), CPU seconds; then the composer goes on as it would.  The table
lists every such product with the operands' sizes and successors per state,
both times and the ratio, sorted by the product of the successors per state
(what `MOVES_PAIRS` in compile.py thresholds on).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ltlf_families import MIRROR, read  # noqa: E402

INSTANCES = [f"Two-player-Game/Nim/nim_{h:02d}/System-first/nim_{h:02d}_{i:02d}.ltlf"
             for h, i in ((2, 2), (2, 4), (3, 1), (3, 2), (3, 3), (4, 1))]
INSTANCES += [f"Random/Syft/syft_{k}/00{i}.ltlf" for k in (2, 3, 4, 5) for i in (1, 4)]
INSTANCES += [f"Random/Lydia/case_0{k}_50/0{i}.ltlf" for k in (3, 5, 7) for i in (1, 2)]
INSTANCES += [f"Two-player-Game/Double-Counter/System-first/counters_0{k}.ltlf" for k in (3, 4)]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", type=Path, default=MIRROR)
    parser.add_argument("--out", type=Path, default=Path("bench/results/moves-products.md"))
    args = parser.parse_args(argv)

    import symsynth.automata.compose as compose_module  # (the composer calls explicit_product by this name)
    from symsynth.automata.tuning import MOVES_PAIRS
    from symsynth.automata import compile_ltlf
    from symsynth.automata import moves
    from symsynth.automata.progression import GuardedDFA, TooLarge

    product = compose_module.explicit_product

    def with_edges(d: GuardedDFA) -> GuardedDFA:
        """`d`, or a copy with its edges when it has only moves (`d` itself
        keeps its form: the composer's later choices are unchanged)."""
        if d.has_edges():
            return d
        return GuardedDFA(d.bdd, d.initial, d.accepting, moves.decode_all(d.bdd, d.moves))
    rows: list[dict] = []
    current = [""]

    def timed(a, b, op, max_edges, max_degree, pairs):
        clock = time.process_time()
        try:
            result = product(a, b, op, max_edges, max_degree, pairs)
            states = result.num_states
        except TooLarge as error:
            states = type(error).__name__
        return time.process_time() - clock, states

    def both(a, b, op, max_edges=None, max_degree=None, moves_pairs=MOVES_PAIRS):
        if a.num_states * b.num_states >= 20:
            ga, gb = with_edges(a), with_edges(b)  # (guards made beforehand: not part of either time)
            guards, size_g = timed(ga, gb, op, max_edges, None, float("inf"))  # (no turn to the moves)
            by_moves, size_m = timed(a, b, op, max_edges, max_degree, 0)
            rows.append({"instance": current[0], "op": op, "a": a.num_states, "b": b.num_states,
                         "da": a.num_edges / a.num_states, "db": b.num_edges / b.num_states,
                         "guards": guards, "moves": by_moves, "states": size_g, "states_moves": size_m})
        return product(a, b, op, max_edges, max_degree, moves_pairs)

    compose_module.explicit_product = both
    for path in INSTANCES:
        current[0] = Path(path).stem if "Random" not in path else f"{Path(path).parent.name}/{Path(path).stem}"
        print(current[0], flush=True)
        compile_ltlf(read(args.data, path), next_semantics="weak")
    rows.sort(key=lambda r: r["da"] * r["db"])
    lines = ["# Explicit products: guards against moves", "",
             f"Command: `python bench/moves_products.py`; load average at the end "
             f"{os.getloadavg()[0]:.1f}. CPU seconds of each product with its minimization, "
             "made both ways in one process (see the script's docstring). `successors` is "
             "the product of the operands' average successors per state; compile.py's "
             f"MOVES_PAIRS is {MOVES_PAIRS}.", "",
             "| instance | op | states | successors per state | successors | guards s | moves s | guards / moves | result |",
             "|---|---|---|---|---:|---:|---:|---:|---|"]
    for r in rows:
        if r["states"] != r["states_moves"]:  # (a limit reached one way only: the prefix product
            r["states"] = f"{r['states']} / {r['states_moves']}"  # on moves has no edge limit)
        lines.append(f"| {r['instance']} | {r['op']} | {r['a']} x {r['b']} | {r['da']:.1f} x {r['db']:.1f} | "
                     f"{r['da'] * r['db']:.0f} | {r['guards']:.4f} | {r['moves']:.4f} | "
                     f"{r['guards'] / max(r['moves'], 1e-9):.2f} | {r['states']} |")
    args.out.write_text("\n".join(lines) + "\n")
    print("wrote", args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
