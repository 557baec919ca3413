"""The type checker: mypy, configured in pyproject.toml's [tool.mypy], finds
no error in symsynth/, planners/ and primitives/.

The plugin packages are installed under other names (symsynth_planners,
symsynth_primitives: pyproject's package-dir), which an editable install
provides through an import hook mypy cannot follow; so they are checked
through links of those names, and their imports of each other resolve.
mypy's cache is kept in pytest's cache directory (.pytest_cache), so a
second run reads it (measured on 2 cores: cold 13-14 s of CPU, 53 s of wall
clock at load average 7.7; warm 1.5 s of CPU)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from mypy import api

ROOT = Path(__file__).resolve().parents[1]
#: Directory -> the import name it is installed under.
PACKAGES = {"symsynth": "symsynth", "planners": "symsynth_planners", "primitives": "symsynth_primitives"}


@pytest.fixture(scope="module")
def workspace(request, tmp_path_factory) -> Path:
    """A directory that outlives the run if pytest's cache is on (mypy's
    cache and the packages' links under their import names)."""
    cache = getattr(request.config, "cache", None)  # none with -p no:cacheprovider
    return cache.mkdir("mypy") if cache is not None else tmp_path_factory.mktemp("mypy")


def _mypy(workspace: Path, *targets: str) -> tuple[int, str]:
    out, err, status = api.run(["--config-file", str(ROOT / "pyproject.toml"),
                                "--cache-dir", str(workspace / "cache"), "--show-absolute-path", "--no-error-summary", *targets])
    return status, out + err


def _targets(workspace: Path) -> list[str]:
    links = workspace / "packages"
    links.mkdir(exist_ok=True)
    targets = []
    for directory, name in PACKAGES.items():
        link = links / name
        if not link.is_symlink() or link.resolve() != ROOT / directory:
            link.unlink(missing_ok=True)
            link.symlink_to(ROOT / directory, target_is_directory=True)
        targets.append(str(link))
    return targets


def test_mypy_finds_no_error(workspace):
    status, text = _mypy(workspace, *_targets(workspace))
    # Shown with the repository's paths rather than the links'.
    for directory, name in PACKAGES.items():
        text = text.replace(str(workspace / "packages" / name), directory)
    errors = [line for line in text.splitlines() if ": error:" in line]
    assert status == 0 and not errors, f"{len(errors)} mypy errors:\n{text}"


def test_the_configuration_checks_unannotated_functions(workspace, tmp_path):
    """What the configuration promises: the body of a function without
    annotations is checked (check_untyped_defs), and an untyped
    third-party package of the list is no error while a missing module of
    our own is."""
    module = tmp_path / "sample.py"
    module.write_text("import fcl\nimport symsynth_nowhere\n\n"
                      "def unannotated():\n    return 1 + 'one'\n", encoding="utf-8")
    status, text = _mypy(workspace, str(module))
    assert status == 1
    lines = sorted(re.findall(r"sample\.py:(\d+): error", text))
    assert lines == ["2", "5"], text
