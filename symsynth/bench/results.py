"""The results of an experiment: the CSV's columns, its rows appended one
whole line at a time, read back for --resume, and the table of mean ± std
per cell.

A row is written with one `write` of one line, flushed and synced, so a
process killed at any moment leaves whole rows and at most a last line
without its newline, which `read_rows` drops (that run is done again).
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import statistics
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from symsynth.errors import InputError, read_text
from symsynth.files import check_regular

#: The CSV's columns, in order (docs/bench.md says what each holds).
COLUMNS = (
    # the run
    "run", "cell", "label", "params", "scene_file", "seed", "method", "planner", "solver", "k", "budget",
    "resolution", "roadmap_size", "contacts", "objective", "human_model",
    # how it ended
    "status", "error",
    # abstraction (physical scenes; empty when the costmap came from the cache or the scene)
    "seconds_abstraction", "seconds_anchors", "seconds_roadmaps", "seconds_edge_checks", "seconds_searches",
    "roadmaps", "roadmap_vertices", "roadmap_edges", "edge_checks", "graph_searches", "costmap_rules",
    "costmap_cached", "planner_workers",
    # synthesis
    "seconds_prepare", "seconds_synthesis", "synthesis_phases", "E_p", "units", "realizable", "positions",
    "bdd_peak_nodes", "dfa_states", "expected_cost", "class", "cooperative_cost", "run_costs",
    # the machine
    "peak_memory_mb", "versions", "host", "cpus", "load", "started", "seconds_run",
    # the strategy run in a world (axis worlds: a random human, the run's seed)
    "world", "completed", "within_tolerance", "placement_error", "state_divergences", "soundness_bugs", "cost",
    "seconds_simulation", "cpu_seconds_simulation",
)
#: Columns that differ between two runs of the same cell and seed
#: (timings, memory, the machine's state); the others must not.
MEASURED = frozenset(c for c in COLUMNS if c.startswith(("seconds_", "cpu_seconds_"))) | {
    "synthesis_phases", "peak_memory_mb", "host", "load", "started", "planner_workers"}
#: Columns of numbers the table and plots average.
NUMBERS = ("seconds_abstraction", "seconds_synthesis", "E_p", "positions", "bdd_peak_nodes",
           "peak_memory_mb", "roadmap_vertices")


def format_row(row: dict[str, Any]) -> str:
    """One CSV line (with its newline) of `row`'s `COLUMNS`."""
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow([_cell(row.get(column)) for column in COLUMNS])
    return out.getvalue()


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, (dict, list)):
        return json.dumps(value, sort_keys=True)
    if isinstance(value, float):
        return repr(round(value, 6)) if math.isfinite(value) else str(value)
    return str(value)


class RowWriter:
    """Appends rows to the CSV, the header first if the file is new or empty."""

    def __init__(self, path: Path):
        self.path = path
        try:
            self.file = open(path, "a", encoding="utf-8", newline="")
        except OSError as error:
            raise InputError(f"cannot write results {path}: {error.strerror or error}") from None
        if self.file.tell() == 0:
            self._write(",".join(COLUMNS) + "\n")

    def append(self, row: dict[str, Any]) -> None:
        self._write(format_row(row))

    def _write(self, line: str) -> None:
        try:
            self.file.write(line)  # one line, one write: whole or (if killed in it) without its newline
            self.file.flush()
            os.fsync(self.file.fileno())
        except OSError as error:
            raise InputError(f"cannot write results {self.path}: {error.strerror or error}") from None

    def close(self) -> None:
        self.file.close()

    def __enter__(self) -> RowWriter:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


#: The largest results.csv read back (a row is about a kilobyte).
MAX_RESULTS = 256 << 20


def read_rows(path: Path) -> list[dict[str, str]]:
    """The whole rows of a results CSV (a last line without its newline is a
    row cut short and is dropped); none if the file does not exist.  A file
    with other columns is refused: it was written by another version."""
    if not path.exists():
        return []
    check_regular(path, "results file")
    text = read_text(path, "results file", limit=MAX_RESULTS)
    if not text.endswith("\n"):
        text = text[:text.rfind("\n") + 1]
    reader = csv.DictReader(io.StringIO(text))
    if reader.fieldnames is not None and tuple(reader.fieldnames) != COLUMNS:
        raise InputError(f"{path} has other columns than symsynth bench writes; give another -o folder")
    return list(reader)


def drop_partial_line(path: Path) -> None:
    """Cut a last line without its newline off the CSV (a row a killed
    process did not finish), so the next row starts on a line of its own."""
    try:
        with open(path, "rb+") as file:
            data = file.read()
            if data and not data.endswith(b"\n"):
                file.truncate(data.rfind(b"\n") + 1)
    except FileNotFoundError:
        return


# -- the table -----------------------------------------------------------------

def number(text: str) -> float | None:
    try:
        return float(text) if text != "" else None
    except ValueError:
        return None


def by_cell(rows: Iterable[dict[str, str]]) -> dict[str, list[dict[str, str]]]:
    cells: dict[str, list[dict[str, str]]] = {}
    for row in rows:
        cells.setdefault(row["cell"], []).append(row)
    return cells


def mean_std(values: list[float]) -> tuple[float, float]:
    return statistics.fmean(values), statistics.stdev(values) if len(values) > 1 else 0.0


def _summary(values: list[float | None], digits: int) -> str:
    """`mean ± std` of the finite values; `inf` counts the runs without a
    winning strategy (E_p infinite)."""
    found = [v for v in values if v is not None and math.isfinite(v)]
    text = ""
    if found:
        mean, std = mean_std(found)
        text = f"{mean:.{digits}f} ± {std:.{digits}f}" if len(found) > 1 else f"{mean:.{digits}f}"
    return text or "—"


TABLE = (("runs ok", None), ("abstraction s", "seconds_abstraction"), ("synthesis s", "seconds_synthesis"),
         ("E_p", "E_p"), ("positions", "positions"), ("BDD peak nodes", "bdd_peak_nodes"),
         ("peak MB", "peak_memory_mb"), ("completed", "completed"), ("placement error m", "placement_error"),
         ("simulation s", "seconds_simulation"))


#: Digits shown of a column's mean (the others: 2 for seconds, else 0).
DIGITS = {"peak_memory_mb": 1, "completed": 2, "placement_error": 4}
#: Columns a run may leave empty (a cached costmap, no world): "—" when all do.
OPTIONAL = ("seconds_abstraction", "completed", "placement_error", "seconds_simulation")


def markdown_table(rows: list[dict[str, str]], cells: Iterable[str]) -> str:
    """Mean ± std over the runs of each cell that ended ok, cells in the
    experiment's order; E_p over the runs with a winning strategy (`inf n`:
    n runs had none); failures counted by status."""
    found = by_cell(rows)
    lines = ["| cell | " + " | ".join(name for name, _ in TABLE) + " |",
             "|---|" + "---:|" * len(TABLE)]
    for cell in cells:
        runs = found.get(cell, [])
        ok = [r for r in runs if r["status"] == "ok"]
        failed: dict[str, int] = {}
        for r in runs:
            if r["status"] != "ok":
                failed[r["status"]] = failed.get(r["status"], 0) + 1
        count = f"{len(ok)}/{len(runs)}" + "".join(f" ({n} {s})" for s, n in sorted(failed.items()))
        values = [count]
        for _, column in TABLE[1:]:
            digits = DIGITS.get(column, 2 if column.startswith("seconds") else 0)
            if column in OPTIONAL and all(r[column] == "" for r in ok):
                values.append("—")
                continue
            values.append(_summary([number(r[column]) for r in ok], digits))
            if column == "E_p":
                infinite = sum(r["E_p"] == "inf" for r in ok)
                if infinite:
                    values[-1] += f" (inf {infinite})"
        lines.append(f"| {cell} | " + " | ".join(values) + " |")
    return "\n".join(lines) + "\n"
