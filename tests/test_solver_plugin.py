"""A third-party game solver, one module and one entry point with no change
to symsynth: `tests/plugins/symsynth-plain` is installed with pip into a
folder of its own, `solve --solver plain` uses it, and its own tests,
symsynth's solver suite in one line, pass."""

from __future__ import annotations

import json
import subprocess
import sys

from support.plugin_repos import environment, install, run_own_tests

TOY = "scenes/toy.yaml"


def test_the_plugin_solves_and_passes_its_own_tests(tmp_path):
    installed = install("symsynth-plain", tmp_path / "site")
    done = run_own_tests("symsynth-plain", installed, tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "48 passed" in done.stdout  # the suite: 8 hand-solved games, 40 generated ones
    solved = [subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", TOY, "--json", "--solver", solver],
                             capture_output=True, text=True, env=environment(installed)) for solver in ("plain", "explicit")]
    assert [s.returncode for s in solved] == [0, 0], solved[0].stderr
    plain, explicit = (json.loads(s.stdout)["cost_bound"] for s in solved)
    assert plain == explicit is not None
