"""What a fresh user of `symsynth bench` met (issue 33): a log that stays
empty until the end, Ctrl-C without a word on --resume, a missing scene
file reported only once the other mistakes were fixed, plots that join
single runs into zig-zags."""

from __future__ import annotations

from symsynth.bench import runner
from symsynth.cli import main
from support.paper import SCENES

TINY = f"""\
name: tiny
scenes:
  - {{file: "{SCENES / 'toy.yaml'}"}}
solvers: [explicit]
k: [0]
seeds: [0, 1]
limits: {{seconds: 60, memory_mb: 2048}}
"""


def test_a_log_gets_a_line_per_finished_run(tmp_path, capsys):
    """With stderr no terminal (a log), there is no bar: a line per run as
    it ends, so that the log shows the experiment going on."""
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if line.startswith("tiny: run ")]
    assert len(lines) == 2
    assert lines[0].startswith("tiny: run 1 of 2: ") and ", seed 0: ok, " in lines[0]
    assert lines[1].startswith("tiny: run 2 of 2: ") and ", seed 1: ok, " in lines[1]


def test_ctrl_c_says_how_to_resume(tmp_path, capsys, monkeypatch):
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY)

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr("symsynth.cli.bench.run_experiment", interrupted)
    assert main(["bench", str(path), "-o", str(tmp_path / "out")]) == 130
    err = capsys.readouterr().err
    assert "--resume" in err and str(tmp_path / "out" / "results.csv") in err


def test_a_missing_scene_file_is_reported_with_the_other_problems(tmp_path, capsys):
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY.replace("toy.yaml", "no-such-scene.yaml").replace("k: [0]", "k: [0]\ncolour: red"))
    assert main(["bench", str(path)]) == 2
    err = capsys.readouterr().err
    assert "no-such-scene.yaml" in err and "unknown key 'colour'" in err


def test_each_run_gets_the_scene_the_experiment_loaded(tmp_path, monkeypatch):
    """The parent loads every scene to check the file, and each run's
    process loaded it again: the runs now get the loaded scene, and never
    read the file (the file is gone before they start)."""
    import shutil

    from symsynth.bench import worker
    from symsynth.bench.experiment import load_experiment

    folder = tmp_path / "scenes"
    folder.mkdir()
    for name in ("toy.yaml", "toy.costmap.json"):
        shutil.copy(SCENES / name, folder / name)
    path = tmp_path / "tiny.yaml"
    path.write_text(TINY.replace(str(SCENES / "toy.yaml"), str(folder / "toy.yaml")))
    experiment = load_experiment(path)
    shutil.rmtree(folder)
    sent = []

    def measured_here(spec):
        sent.append(spec)
        return worker.measure(spec) | {"status": "ok"}  # in this process, from what the child would get
    monkeypatch.setattr(runner, "execute", measured_here)
    from symsynth.parallel import LocalPool

    done = runner.run_experiment(experiment, tmp_path, LocalPool(1))
    assert done.ran == 2 and done.failed == 0 and all("scene" in spec for spec in sent)
    rows = (tmp_path / "results.csv").read_text()
    assert rows.count(",17,") >= 2  # E_p of the toy with k = 0, from the scene the parent loaded
