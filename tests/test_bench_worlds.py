"""`symsynth bench` with the axis `worlds: [kinematic, physics]`: each run
also plays its strategy once in that world, and the rows say whether the
abstraction held there.  On push-small with its contact 22 cm beside the
box the kinematic world carries the box along (completed, error 0), the
physical one leaves it on l1: not completed, |l1 - l2| = 18 cm from where
the abstraction puts it.  The good push completes in both.  60-vertex
roadmaps, no human moves (k = 0)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from symsynth.bench.experiment import load_experiment
from symsynth.bench.results import number, read_rows
from symsynth.cli import main

DATA = Path(__file__).parent / "data"


def push(folder: Path, aside: float) -> Path:
    data = yaml.safe_load((DATA / "push-small.yaml").read_text())
    data["contacts"]["behind"]["xyz"] = [-0.155, aside, 0.12]
    if aside:
        data["contacts"]["behind"]["absent_at"] = ["e1"]
    data["planner"]["roadmap_size"] = 60
    data["name"] = f"push{aside}"
    path = folder / f"push-{aside}.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_the_physical_world_tells_the_push_beside_the_box_from_the_good_one(tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    good, bad = push(tmp_path, 0.0), push(tmp_path, 0.22)
    experiment = tmp_path / "worlds.yaml"
    experiment.write_text(f"""\
name: worlds
scenes:
  - {{file: "{good}", label: good}}
  - {{file: "{bad}", label: bad}}
methods: [sg]
worlds: [kinematic, physics]
cache: true
limits: {{seconds: 300, memory_mb: 4096}}
""")
    cells = load_experiment(experiment).cells
    assert cells == ("good sg ompl-fcl roadmap=60 symbolic k=0 world=kinematic",
                     "good sg ompl-fcl roadmap=60 symbolic k=0 world=physics",
                     "bad sg ompl-fcl roadmap=60 symbolic k=0 world=kinematic",
                     "bad sg ompl-fcl roadmap=60 symbolic k=0 world=physics")
    assert main(["bench", str(experiment), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 0
    rows = {(r["label"], r["world"]): r for r in read_rows(tmp_path / "out" / "results.csv")}
    assert all(r["status"] == "ok" for r in rows.values()), rows
    for world in ("kinematic", "physics"):
        assert rows["good", world]["completed"] == "1" and number(rows["good", world]["placement_error"]) <= 0.01
    assert rows["bad", "kinematic"]["completed"] == "1" and number(rows["bad", "kinematic"]["placement_error"]) == 0
    assert rows["bad", "physics"]["completed"] == "0"
    assert number(rows["bad", "physics"]["placement_error"]) == pytest.approx(math.dist((0.5, 0, 0), (0.68, 0, 0)),
                                                                             abs=0.005)
    assert int(rows["bad", "physics"]["state_divergences"]) >= 1 and rows["bad", "physics"]["soundness_bugs"] == "0"
    table = (tmp_path / "out" / "table.md").read_text()
    assert "| bad sg ompl-fcl roadmap=60 symbolic k=0 world=physics | 1/1 |" in table


def test_an_abstract_scene_has_no_world(tmp_path):
    experiment = tmp_path / "abstract.yaml"
    experiment.write_text(f"""\
name: abstract
scenes:
  - {{file: "{Path(__file__).parents[1] / 'scenes' / 'toy.yaml'}"}}
worlds: [kinematic, physics]
""")
    (run,) = load_experiment(experiment).runs
    assert run.world is None and "world" not in run.cell


def test_an_unknown_world_is_named(tmp_path, capsys):
    experiment = tmp_path / "bad.yaml"
    experiment.write_text(f"name: bad\nscenes:\n  - {{file: \"{DATA / 'push-small.yaml'}\"}}\nworlds: [mujoco]\n")
    assert main(["bench", str(experiment), "-o", str(tmp_path / "out")]) == 2
    assert "worlds" in capsys.readouterr().err
