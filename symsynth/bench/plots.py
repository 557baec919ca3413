"""The figures of an experiment's rows (matplotlib, written as PNG files
whole or not at all):

- `sweep.png`, the paper's Fig. 4 layout: a scene parameter (`plots: {x: ...}`,
  e.g. the number of obstacles) against the abstraction time and against
  the resource bound E_p, one line per setting (method, planner, solver...),
  mean with a ±std band;
- `breakdown.png`: where each cell's time went (anchors, roadmaps, edge
  checks, graph searches, synthesis), means over its runs that ended ok;
- `scaling.png`: game positions against synthesis time, a line per solver
  and scene label through the means of its cells (±std bars), log-log;
- `run-costs.png` (objectives of semantics §9 with a human model): per
  cell, the distribution of the costs of its strategy's plays against the
  model (`run_costs`), with E_p and the budget B marked.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

from symsynth.bench.results import by_cell, mean_std, number  # noqa: E402
from symsynth.files import atomic_output  # noqa: E402

#: Pixels per inch of every figure; sizes below are in inches.
DPI = 100
SWEEP_SIZE = (10, 4)
BREAKDOWN_WIDTH = 10
SCALING_SIZE = (6, 4.5)
RUN_COSTS_WIDTH = 8

PHASES = (("anchors", "seconds_anchors"), ("roadmaps", "seconds_roadmaps"),
          ("edge checks", "seconds_edge_checks"), ("graph searches", "seconds_searches"),
          ("synthesis", "seconds_synthesis"))


def _save(figure, path: Path) -> None:
    with atomic_output(path, "plot") as temporary:
        figure.savefig(temporary, format="png", dpi=DPI)
    plt.close(figure)


def _ok(rows: Sequence[dict[str, str]]) -> list[dict[str, str]]:
    return [r for r in rows if r["status"] == "ok"]


def sweep(rows: Sequence[dict[str, str]], x: str, path: Path) -> bool:
    """The Fig. 4 layout over parameter `x`; False (nothing written) when no
    run has that parameter."""
    lines: dict[str, dict[float, list[dict[str, str]]]] = {}
    for row in _ok(rows):
        params = json.loads(row["params"] or "{}")
        if x not in params or number(str(params[x])) is None:
            continue
        rest = ", ".join(f"{k}={v}" for k, v in params.items() if k != x)
        setting = " ".join(part for part in (row["label"], rest, row["method"], row["planner"] if
                                             row["method"] else "", row["solver"]) if part)
        lines.setdefault(setting, {}).setdefault(float(params[x]), []).append(row)
    if not lines:
        return False
    figure, axes = plt.subplots(1, 2, figsize=SWEEP_SIZE)
    for axis, column, label in ((axes[0], "seconds_abstraction", "abstraction time (s)"),
                                (axes[1], "E_p", "resource bound E_p")):
        for setting, points in sorted(lines.items()):
            xs, means, stds = [], [], []
            for value in sorted(points):
                found = [v for v in (number(r[column]) for r in points[value]) if v is not None
                         and math.isfinite(v)]
                if found:
                    mean, std = mean_std(found)
                    xs.append(value)
                    means.append(mean)
                    stds.append(std)
            if not xs:
                continue
            axis.plot(xs, means, marker="o", label=setting)
            axis.fill_between(xs, [m - s for m, s in zip(means, stds)], [m + s for m, s in zip(means, stds)],
                              alpha=0.2)
        axis.set_xlabel(x)
        axis.xaxis.set_major_locator(MaxNLocator(integer=True))  # a count of obstacles has no halves
        axis.set_ylabel(label)
        axis.grid(alpha=0.3)
    axes[1].legend(fontsize="small")
    figure.tight_layout()
    _save(figure, path)
    return True


def breakdown(rows: Sequence[dict[str, str]], cells: Sequence[str], path: Path) -> None:
    """Stacked horizontal bars, one per cell in the experiment's order; the
    legend above the bars, off the data."""
    found = by_cell(_ok(rows))
    shown = [cell for cell in cells if cell in found]
    figure, axis = plt.subplots(figsize=(BREAKDOWN_WIDTH, 1.5 + 0.4 * max(len(shown), 1)), layout="constrained")
    left = [0.0] * len(shown)
    for name, column in PHASES:
        widths = []
        for cell in shown:
            values = [v for v in (number(r[column]) for r in found[cell]) if v is not None]
            widths.append(sum(values) / len(found[cell]) if values else 0.0)
        axis.barh(range(len(shown)), widths, left=left, label=name)
        left = [a + b for a, b in zip(left, widths)]
    axis.set_yticks(range(len(shown)), shown, fontsize="small")
    axis.invert_yaxis()
    axis.set_xlabel("mean seconds per run\n(roadmaps, edge checks: summed over the worker processes)",
                    fontsize="small")
    figure.legend(fontsize="small", loc="outside upper center", ncols=len(PHASES), frameon=False)
    _save(figure, path)


def scaling(rows: Sequence[dict[str, str]], path: Path) -> None:
    """Positions against synthesis seconds, a series per solver and scene
    label: each cell one point, the mean of its runs with a bar of ±1 std
    (a point per run joined by lines zig-zags when the runs of a cell
    differ); log-log, the legend beside the axes."""
    figure, axis = plt.subplots(figsize=SCALING_SIZE, layout="constrained")
    series: dict[str, dict[str, tuple[list[float], list[float]]]] = {}
    for row in _ok(rows):
        size, seconds = number(row["positions"]), number(row["seconds_synthesis"])
        if size and seconds:
            sizes, times = series.setdefault(f"{row['solver']}, {row['label']}", {}).setdefault(row["cell"], ([], []))
            sizes.append(size)
            times.append(seconds)
    for name, cells in sorted(series.items()):
        points = sorted((mean_std(sizes)[0], *mean_std(times)) for sizes, times in cells.values())
        axis.errorbar([p[0] for p in points], [p[1] for p in points], yerr=[p[2] for p in points],
                      marker="o", linestyle="-", capsize=3, label=name)
    if series:
        axis.set_xscale("log")
        axis.set_yscale("log")
        figure.legend(fontsize="small", loc="outside right upper")
    axis.set_xlabel("game positions the solver represented")
    axis.set_ylabel("synthesis time (s), mean ± std of a cell's runs")
    axis.grid(alpha=0.3, which="both")
    _save(figure, path)


def run_costs(rows: Sequence[dict[str, str]], cells: Sequence[str], path: Path) -> bool:
    """Box plots of the cells' play costs (all their runs' `run_costs`
    together), one row per cell in the experiment's order, with E_p (|) and
    B (x, E_p when no budget was given) of its first run marked; whether
    any cell had plays to show (else no file)."""
    found = by_cell(_ok(rows))
    shown: list[tuple[str, list[float], float | None, float | None]] = []
    for cell in cells:
        costs = [c for r in found.get(cell, []) if r.get("run_costs") for c in json.loads(r["run_costs"])]
        if costs:
            first = found[cell][0]
            ep = number(first["E_p"])
            shown.append((cell, costs, ep, number(first["budget"]) or ep))
    if not shown:
        return False
    figure, axis = plt.subplots(figsize=(RUN_COSTS_WIDTH, 1.5 + 0.5 * len(shown)), layout="constrained")
    axis.boxplot([costs for _, costs, _, _ in shown], orientation="horizontal", widths=0.5)
    for y, (_, _, ep, budget) in enumerate(shown, 1):
        if ep is not None and math.isfinite(ep):
            axis.plot([ep], [y], "|", color="black", markersize=16, label="E_p" if y == 1 else None)
        if budget is not None and math.isfinite(budget):
            axis.plot([budget], [y], "x", color="tab:red", markersize=9, label="B" if y == 1 else None)
    axis.set_yticks(range(1, len(shown) + 1), [cell for cell, _, _, _ in shown], fontsize="small")
    axis.invert_yaxis()
    axis.set_xlabel("cost of a play against the human model (costmap units, in the game)", fontsize="small")
    figure.legend(fontsize="small", loc="outside upper center", ncols=2, frameon=False)
    _save(figure, path)
    return True
