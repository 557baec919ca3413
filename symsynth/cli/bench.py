"""`symsynth bench`: an experiment file's runs, their CSV, table and plots."""

from __future__ import annotations

import argparse
import shlex
import sys
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.bench.experiment import load_experiment
from symsynth.bench.results import markdown_table, read_rows
from symsynth.bench.runner import run_experiment
from symsynth.cli import options
from symsynth.errors import InputError
from symsynth.files import write_atomic

DESCRIPTION = """\
Run every cell of an experiment file (YAML; docs/bench.md) for each of its
seeds, each run in a child process with the file's time and memory limits:

  symsynth bench EXPERIMENT.yaml [-o DIR] [--executor local|ray] [--address ADDR]
                 [--jobs N] [--resume] [--trials N]

Output in DIR (default results/NAME, NAME the experiment's):
  results.csv    one row per run, appended as each run ends (columns in
                 docs/bench.md): settings, exit status (ok, timeout,
                 out-of-memory, error and its message), abstraction and
                 synthesis time by phase, E_p, positions, BDD peak nodes,
                 DFA states, peak memory, roadmap sizes, versions, machine;
  table.md       mean ± std per cell over its runs that ended ok;
  sweep.png      with 'plots: {x: PARAM}': PARAM against abstraction time
                 and E_p, a line per setting (the paper's Fig. 4 layout);
  breakdown.png  time per phase per cell;  scaling.png  positions vs time.

--resume runs only what results.csv lacks (after an interrupt, say); a
failed run has its row and is not run again.  --executor ray runs on Ray
(pip install 'symsynth[ray]'): --address joins a cluster, none starts a
local one with --jobs CPUs.  The same seeds give the same rows on either
executor, timings aside.

Exit status: 0 when every run ended ok, 1 when one did not, 2 on bad input."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("bench", help=COMMANDS["bench"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("experiment", type=Path, help="the experiment file (YAML)")
    parser.add_argument("-o", "--output", type=Path, metavar="DIR",
                        help="folder of the results (default: results/NAME)")
    parser.add_argument("--resume", action="store_true",
                        help="keep DIR's results.csv and run only the runs it lacks")
    parser.add_argument("--trials", type=options.count, metavar="N",
                        help="only the first N seeds of the file's (a quick look; --resume without "
                             "--trials completes it later)")
    options.add_executor(parser, "runs at once (default: 1, so that timings do not compete; "
                                 "each physical run also uses a process per core for its roadmaps)",
                         default_jobs=1)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    experiment = load_experiment(args.experiment)
    if args.trials is not None:
        experiment = experiment.first_trials(args.trials)
    folder = args.output or Path("results") / experiment.name
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(f"cannot make the results folder {folder}: {error.strerror or error}") from None
    options.check_writable(folder / "table.md", "table")
    try:
        done = run_experiment(experiment, folder, options.executor(args), resume=args.resume)
    except KeyboardInterrupt:
        print(f"symsynth bench: the runs that ended are in {folder / 'results.csv'}; to run the others, "
              f"give the same command with --resume", file=sys.stderr)
        raise
    ids = {run.id for run in experiment.runs}
    rows = [row for row in read_rows(done.path) if row["run"] in ids]  # not those of other --trials
    command = "symsynth " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if sys.argv[1:2] == ["bench"] \
        else f"symsynth bench {shlex.quote(str(args.experiment))}"
    table = (f"# {experiment.name}\n\n{experiment.description.strip()}\n\n`{command}`: "
             f"{len(rows)} runs, mean ± std over each cell's runs that ended ok.\n\n"
             + markdown_table(rows, experiment.cells))
    write_atomic(folder / "table.md", table.replace("\n\n\n", "\n\n"), "table")
    from symsynth.bench import plots  # matplotlib: only when plotting

    made = ["results.csv", "table.md"]
    if experiment.plot_x is not None and plots.sweep(rows, experiment.plot_x, folder / "sweep.png"):
        made.append("sweep.png")
    plots.breakdown(rows, experiment.cells, folder / "breakdown.png")
    plots.scaling(rows, folder / "scaling.png")
    made += ["breakdown.png", "scaling.png"]
    if plots.run_costs(rows, experiment.cells, folder / "run-costs.png"):
        made.append("run-costs.png")
    failed = sum(row["status"] != "ok" for row in rows)
    print(f"bench      {experiment.name}: {done.ran} runs now, {done.skipped} already done, "
          f"{len(rows)} rows; {failed} not ok")
    print(f"wrote      {', '.join(str(folder / name) for name in made)}")
    print()
    print(markdown_table(rows, experiment.cells), end="")
    return 1 if failed else 0
