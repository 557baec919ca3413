"""A third-party simulated human, one module and one entry point with no
change to symsynth: `tests/plugins/symsynth-fickle` is installed with pip
into a folder of its own; `simulate --human fickle` gives it the budgets it
says it needs (not only a human named adversarial gets them), and its own
tests, symsynth's human suite in one line, pass."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from support.plugin_repos import environment, install, run_own_tests

PUSH = Path(__file__).parent / "data" / "push-small.yaml"


def test_the_plugin_plays_with_budgets_and_passes_its_own_tests(tmp_path):
    installed = install("symsynth-fickle", tmp_path / "site")
    done = run_own_tests("symsynth-fickle", installed, tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "3 passed" in done.stdout
    out = {}  # push-small: with k = 0 the human has no move, but budgets are computed for it all the same
    for human in ("fickle", "random"):
        run = subprocess.run([sys.executable, "-m", "symsynth.cli", "simulate", "--world", "kinematic", str(PUSH), "--human", human,
                              "--json", "--move-probability", "1"], capture_output=True, text=True,
                             env=environment(installed, SYMSYNTH_CACHE=str(tmp_path / "cache")))
        assert run.returncode == 0, run.stderr
        out[human] = json.loads(run.stdout)
    assert out["fickle"]["runs"][0]["completed"]
    # the whole strategy explored for the human that needs budgets, not for the one that does not
    assert isinstance(out["fickle"]["strategy"]["positions"], int) and out["random"]["strategy"]["positions"] is None
