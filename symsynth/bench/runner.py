"""An experiment's runs on an executor, each row appended to the CSV as its
run ends; --resume skips the runs the CSV already has."""

from __future__ import annotations

import base64
import pickle
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from tqdm import tqdm

from symsynth.bench.experiment import Experiment, Run
from symsynth.bench.results import RowWriter, drop_partial_line, read_rows
from symsynth.bench.worker import execute
from symsynth.errors import InputError
from symsynth.parallel import Executor
from symsynth.scene import Scene

RESULTS = "results.csv"


@dataclass(frozen=True)
class Done:
    """What a call of `run_experiment` did."""

    path: Path
    ran: int
    skipped: int  # already in the CSV (--resume)
    failed: int  # of those that ran: timeout, out-of-memory or error


def run_row(run: Run, measured: dict[str, Any]) -> dict[str, Any]:
    """The CSV row of `run`: its settings, then what the child measured
    (which names the planner and roadmap size the scene chose)."""
    return {"run": run.id, "cell": run.cell, "label": run.label, "params": run.params,
            "scene_file": run.scene_file, "seed": run.seed, "method": run.method, "planner": run.planner,
            "solver": run.solver, "k": run.k, "budget": run.budget, "resolution": run.resolution,
            "roadmap_size": run.roadmap_size, "contacts": "on" if run.contacts else "off",
            "world": run.world, "objective": run.objective, "human_model": run.human_model} | measured


def packed(scene: Scene | None) -> dict[str, str]:
    """The scene as loaded in this process, for a run's process (`worker.scene_of`):
    pickled, in base64 to travel in the run's JSON; nothing when there is none."""
    return {} if scene is None else {"scene": base64.b64encode(pickle.dumps(scene)).decode("ascii")}


def _timed(spec: dict[str, Any]) -> dict[str, Any]:
    """`execute` with the run's wall-clock seconds, parent's view (start-up included)."""
    clock = time.perf_counter()
    measured = execute(spec)
    return measured | {"seconds_run": time.perf_counter() - clock}


def run_experiment(experiment: Experiment, folder: Path, executor: Executor, resume: bool = False) -> Done:
    """Run what the CSV in `folder` lacks (all of it without `resume`, when
    there must be no CSV yet); rows are appended as runs end."""
    path = folder / RESULTS
    if path.exists() and not resume and path.stat().st_size > 0:
        raise InputError(f"{path} exists: give --resume to run what it lacks, or another -o folder")
    if resume:
        drop_partial_line(path)
    done = {row["run"] for row in read_rows(path)}
    pending = [run for run in experiment.runs if run.id not in done]
    failed, ended = 0, len(experiment.runs) - len(pending)
    with RowWriter(path) as writer, tqdm(total=len(experiment.runs), initial=len(experiment.runs) - len(pending),
                                         desc=experiment.name, unit="run", disable=None) as bar:
        unfinished = dict.fromkeys(range(len(pending)))  # in the order the runs start
        _show(bar, pending, unfinished)
        with executor as running:
            specs = [run.to_json() | packed(experiment.scenes.get(run.scene_file)) for run in pending]
            for i, measured in running.imap(_timed, specs):
                writer.append(run_row(pending[i], measured))
                failed += measured.get("status") != "ok"
                del unfinished[i]
                _show(bar, pending, unfinished)
                bar.update()
                ended += 1
                if bar.disable:  # no bar (stderr is a log, not a terminal): a line per run instead
                    print(finished_line(experiment.name, ended, len(experiment.runs), pending[i], measured),
                          file=sys.stderr, flush=True)
    return Done(path, len(pending), len(experiment.runs) - len(pending), failed)


def finished_line(name: str, n: int, total: int, run: Run, measured: dict[str, Any]) -> str:
    """One line for a finished run, for a log: which, how it ended, how long."""
    status = measured.get("status", "?")
    if status != "ok" and measured.get("error"):
        status += f" ({str(measured['error'])[:120]})"
    return f"{name}: run {n} of {total}: {run.cell}, seed {run.seed}: {status}, {measured['seconds_run']:.1f} s"


def _show(bar: tqdm, pending: list[Run], unfinished: dict[int, None]) -> None:
    """The earliest run not finished: the one running (with --jobs N, the first of N)."""
    if unfinished:
        run = pending[next(iter(unfinished))]
        bar.set_postfix_str(f"{run.cell}, seed {run.seed}")
