"""The example third-party plugins of tests/plugins/, each a repository of
its own (pyproject.toml, a package, tests/): installed as a user would
(pip, into a folder of their own) and their own tests run there, with
symsynth's conformance suites (`symsynth.testing`)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

PLUGINS = Path(__file__).resolve().parents[1] / "plugins"


def install(name: str, target: Path) -> Path:
    """tests/plugins/NAME installed with pip into `target` (its build backend
    comes from the package index or pip's cache); returns `target`."""
    done = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                           str(PLUGINS / name)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return target


def environment(installed: Path, **more: str) -> dict[str, str]:
    """The environment of a process that sees the installed plugin."""
    return dict(os.environ, PYTHONPATH=str(installed), **more)


def run_own_tests(name: str, installed: Path, workspace: Path) -> subprocess.CompletedProcess:
    """pytest run on a copy of the plugin's repository (its tests/ and its
    pytest settings, nothing of symsynth's), the plugin installed."""
    copy = workspace / name
    shutil.copytree(PLUGINS / name, copy, ignore=shutil.ignore_patterns("*.egg-info", "build", "__pycache__"))
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist"],
                          cwd=copy, capture_output=True, text=True,
                          env=environment(installed, SYMSYNTH_CACHE=str(workspace / "cache")))
