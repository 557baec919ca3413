"""`symsynth bench` on a small experiment: two abstract scenes (toy and the
abstract arch at k = 1), two solvers, two seeds: 8 runs of well under a
second each.  Its rows must equal `symsynth solve` on the same cells, its
files exist (the PNGs are images of the documented size), an experiment
killed half-way and resumed gives the rows of one run straight through,
Ray gives the rows of the local pool, and a malformed file is one message
with its line and key path (exit 2).
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from PIL import Image

from symsynth.bench import plots
from symsynth.bench.results import COLUMNS, MEASURED, read_rows
from symsynth.cli import main
from support.paper import SCENES

EXPERIMENT = f"""\
name: tiny
description: two tiny scenes, two solvers, two seeds
scenes:
  - {{file: "{SCENES / 'toy.yaml'}"}}
  - {{file: "{SCENES / 'arch-abstract.yaml'}", label: arch}}
solvers: [symbolic, explicit]
k: [1]
seeds: [0, 1]
limits: {{seconds: 60, memory_mb: 2048}}
"""
RUNS = 8


def write_experiment(folder: Path, text: str = EXPERIMENT) -> Path:
    path = folder / "tiny.yaml"
    path.write_text(text)
    return path


def stable(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """The rows without the columns that differ from run to run (timings,
    memory, the machine's state), sorted by run."""
    return sorted(({c: v for c, v in row.items() if c not in MEASURED} for row in rows),
                  key=lambda row: row["run"])


def cli(*argv: str, env: dict | None = None, **kwargs) -> subprocess.Popen:
    """symsynth in a process of its own."""
    return subprocess.Popen([sys.executable, "-W", "default", "-m", "symsynth.cli", *argv],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=os.environ | (env or {}), **kwargs)


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    """The experiment run once straight through on the local pool: (folder, rows, exit status)."""
    folder = tmp_path_factory.mktemp("bench")
    status = main(["bench", str(write_experiment(folder)), "-o", str(folder / "out"), "--jobs", "2"])
    return folder / "out", read_rows(folder / "out" / "results.csv"), status


def test_files_and_rows(straight):
    out, rows, status = straight
    assert status == 0
    assert len(rows) == RUNS and len({row["run"] for row in rows}) == RUNS
    assert all(row["status"] == "ok" and row["error"] == "" for row in rows)
    header = (out / "results.csv").read_text().splitlines()[0]
    assert header == ",".join(COLUMNS)
    for row in rows:
        assert float(row["seconds_synthesis"]) > 0 and float(row["peak_memory_mb"]) > 10
        assert float(row["seconds_prepare"]) == 0.0  # symbolic and explicit: nothing to compile
        assert int(row["dfa_states"]) >= 2
        assert json.loads(row["versions"])["symsynth"]
        assert (row["bdd_peak_nodes"] != "") == (row["solver"] == "symbolic")
    table = (out / "table.md").read_text()
    assert "| toy symbolic k=1 | 2/2 |" in table and "| arch explicit k=1 | 2/2 |" in table
    assert "| 50 ± 0 |" in table and "| 339 ± 0 |" in table
    for name, size in (("breakdown.png", (plots.BREAKDOWN_WIDTH, 1.5 + 0.4 * 4)),
                       ("scaling.png", plots.SCALING_SIZE)):
        with Image.open(out / name) as image:
            assert image.format == "PNG"
            assert image.size == (round(size[0] * plots.DPI), round(size[1] * plots.DPI))
            assert len(image.getcolors(1 << 16) or range(1 << 16)) > 10  # drawn, not blank
    assert not (out / "sweep.png").exists()  # no plots.x in the file


def test_rows_equal_solve(straight, capsys):
    """Every row's numbers are those of `symsynth solve` on the same cell."""
    _, rows, _ = straight
    for row in rows:
        capsys.readouterr()
        assert main(["solve", row["scene_file"], "--solver", row["solver"], "--k", row["k"], "--json"]) == 0
        solved = json.loads(capsys.readouterr().out)
        assert float(row["E_p"]) == solved["cost_bound"]
        assert int(row["units"]) == solved["units"]
        assert int(row["positions"]) == solved["states"]
        assert row["realizable"] == "" and solved["realizable"] is None
        assert set(json.loads(row["synthesis_phases"])) == set(solved["seconds"])
        if row["solver"] == "symbolic":
            assert int(row["bdd_peak_nodes"]) == solved["stats"]["peak_nodes"]


def test_resume_after_kill(straight, tmp_path):
    """SIGKILL half-way leaves whole rows; --resume runs the rest and the CSV
    holds the rows of the straight run (timings aside), each once."""
    out = tmp_path / "out"
    experiment = write_experiment(tmp_path)
    process = cli("bench", str(experiment), "-o", str(out), "--jobs", "1")
    results = out / "results.csv"
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and process.poll() is None:
        if results.exists() and results.read_text().count("\n") >= 3:  # header and two rows
            break
        time.sleep(0.02)
    process.send_signal(signal.SIGKILL)
    process.communicate()
    kept = read_rows(results)
    assert 2 <= len(kept) < RUNS, "the experiment ended before it was killed"
    assert results.read_text().endswith("\n")
    assert main(["bench", str(experiment), "-o", str(out), "--resume"]) == 0
    assert stable(read_rows(results)) == stable(straight[1])
    assert [row["run"] for row in read_rows(results)][:len(kept)] == [row["run"] for row in kept]


def test_resume_drops_a_cut_row(straight, tmp_path):
    """A last line without its newline (a run killed in the write) is run again."""
    out = tmp_path / "out"
    out.mkdir()
    lines = (straight[0] / "results.csv").read_text().splitlines(keepends=True)
    (out / "results.csv").write_text("".join(lines[:4]) + lines[4][:30])
    assert main(["bench", str(write_experiment(tmp_path)), "-o", str(out), "--resume"]) == 0
    assert stable(read_rows(out / "results.csv")) == stable(straight[1])


def test_no_overwrite_without_resume(straight, tmp_path, capsys):
    assert main(["bench", str(write_experiment(tmp_path)), "-o", str(straight[0])]) == 2
    assert "exists: give --resume" in capsys.readouterr().err


def test_ray_rows_equal_local(straight, tmp_path):
    """A local Ray instance gives the local pool's rows, timings aside."""
    out = tmp_path / "out"
    done = cli("bench", str(write_experiment(tmp_path)), "-o", str(out), "--executor", "ray", "--jobs", "2")
    stdout, stderr = done.communicate(timeout=120)
    assert done.returncode == 0, stderr
    assert stable(read_rows(out / "results.csv")) == stable(straight[1])


@pytest.mark.parametrize("change, where, message", [
    (("solvers: [symbolic, explicit]", "solvers: [symbolic, nope]"), "tiny.yaml:6: solvers.1:",
     "'nope' is not one of"),
    (("seeds: [0, 1]", "seeds: [0, 1]\ntrails: 3"), "tiny.yaml:9: trails:", "unknown key 'trails'"),
    (("toy.yaml\"}", "missing.yaml\"}"), "tiny.yaml:4: scenes.0.file:", "cannot read scene"),
    (("k: [1]", "k: [-1]"), "tiny.yaml:7: k.0:", "less than the minimum of 0"),
    (("seeds: [0, 1]", "seeds: [0, 1]\ntrials: 2"), "tiny.yaml:8: seeds:", "not both"),
    (("k: [1]", "k: [1"), "tiny.yaml:8: not valid YAML", "expected ',' or ']'"),
    (("toy.yaml\"}", "toy-{n}.yaml\"}"), "tiny.yaml:4: scenes.0.file:", "the file names n"),
])
def test_malformed_experiment(tmp_path, capsys, change, where, message):
    path = write_experiment(tmp_path, EXPERIMENT.replace(*change))
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("symsynth bench: ") and "Traceback" not in err
    assert where in err and message in err, err
    assert not (tmp_path / "out").exists()


def test_costmap_on_ray_is_the_local_file(tmp_path):
    """`symsynth costmap --executor ray` writes the file the local build does."""
    scene = tmp_path / "line.yaml"
    scene.write_text((SCENES / "line.yaml").read_text().replace("roadmap_size: 150", "roadmap_size: 30"))
    files = {}
    for executor in ("local", "ray"):
        files[executor] = tmp_path / f"{executor}.json"
        done = cli("costmap", str(scene), "--no-cache", "-o", str(files[executor]), "--executor", executor,
                   "--jobs", "2")
        _, stderr = done.communicate(timeout=120)
        assert done.returncode == 0, stderr
    assert files["local"].read_bytes() == files["ray"].read_bytes()
    assert len(json.loads(files["local"].read_text())["motions"]) > 20


def test_csv_rows_are_whole_lines(straight):
    """Every line of the CSV is one row of every column (fields hold no newline)."""
    text = (straight[0] / "results.csv").read_text()
    assert all(len(fields) == len(COLUMNS) for fields in csv.reader(text.splitlines()))


@pytest.mark.parametrize("limits, status, message", [
    ("{seconds: 0.2}", "timeout", "still running after the limit of 0.2 s"),
    ("{memory_mb: 100}", "out-of-memory", "beyond 100 MB"),
])
def test_limits_end_a_run_with_its_status(tmp_path, capsys, limits, status, message):
    """A run past its limit is a row with that status (exit 1), not the end of the experiment."""
    path = tmp_path / "limits.yaml"
    path.write_text(f'name: limits\nscenes: [{{file: "{SCENES / "arch-abstract.yaml"}"}}]\n'
                    f"solvers: [explicit]\nlimits: {limits}\n")
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 1
    [row] = read_rows(tmp_path / "out" / "results.csv")
    assert row["status"] == status and message in row["error"], row["error"]
    assert f"0/1 (1 {status})" in capsys.readouterr().out


def test_first_trials_then_the_rest(straight, tmp_path, capsys):
    """--trials 1 runs seed 0 of every cell; --resume then adds the rest."""
    out, experiment = tmp_path / "out", write_experiment(tmp_path)
    assert main(["bench", str(experiment), "-o", str(out), "--trials", "1", "--jobs", "2"]) == 0
    rows = read_rows(out / "results.csv")
    assert len(rows) == RUNS // 2 and {row["seed"] for row in rows} == {"0"}
    assert "| toy symbolic k=1 | 1/1 |" in (out / "table.md").read_text()
    assert main(["bench", str(experiment), "-o", str(out), "--resume", "--jobs", "2"]) == 0
    assert stable(read_rows(out / "results.csv")) == stable(straight[1])


def test_contacts_on_and_off_is_an_axis(tmp_path, capsys):
    """scenes/push-abstract.yaml at k = 0 (hand-solved in its comments):
    E_p 10 with its contact, no strategy without it (the box cannot be
    grasped where it stands)."""
    path = tmp_path / "contacts.yaml"
    path.write_text(f"""\
name: contacts
scenes:
  - {{file: "{SCENES / 'push-abstract.yaml'}", label: push}}
solvers: [symbolic, explicit]
k: [0]
contacts: [on, off]
limits: {{seconds: 60, memory_mb: 2048}}
""")
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 0
    capsys.readouterr()
    rows = read_rows(tmp_path / "out" / "results.csv")
    found = {(row["solver"], row["contacts"]): row["E_p"] for row in rows}
    assert found == {("symbolic", "on"): "10", ("explicit", "on"): "10",  # (integer costs: an exact int)
                     ("symbolic", "off"): "inf", ("explicit", "off"): "inf"}
    assert {row["cell"] for row in rows if row["contacts"] == "off"} == {
        "push symbolic k=0 contacts=off", "push explicit k=0 contacts=off"}
