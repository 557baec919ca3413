"""Every output file is written whole or not at all (symsynth/files.py):
a full disk or a file size limit is one message and exit 2, the old file
is kept, and no temporary file is left (issue 16, row 8: `costmap -o` to
/dev/full lost the old file, left it cut at 64 KB, and was an OSError
traceback; a `.partial` stayed in the cache)."""

from __future__ import annotations

import os
import resource
import subprocess
import sys

import pytest

from support.paper import SCENES
from symsynth.cli import main
from symsynth.files import write_atomic
from symsynth.errors import InputError

TOY = str(SCENES / "toy.yaml")


@pytest.mark.parametrize("argv, what", [
    (["solve", TOY, "-o", "/dev/full"], "strategy file"),
    (["dfa", "F a & G b", "--dot", "/dev/full"], "DOT file"),
    (["show", str(SCENES / "line.yaml"), "-o", "/dev/full"], "image"),
])
def test_a_full_disk_is_one_message(capsys, argv, what):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert f"cannot write {what} /dev/full: No space left on device" in err and "Traceback" not in err


def test_the_costmap_to_a_full_disk(line_costmap_scene, capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    assert main(["costmap", str(line_costmap_scene), "--method", "sg", "-o", "/dev/full"]) == 2
    err = capsys.readouterr().err
    assert "cannot write costmap file /dev/full: No space left on device" in err and "Traceback" not in err
    assert [p.suffix for p in (tmp_path / "cache").iterdir()] == [".json"]  # the cache holds the whole file only


@pytest.fixture
def line_costmap_scene(tmp_path):
    path = tmp_path / "line.yaml"
    path.write_text((SCENES / "line.yaml").read_text().replace("roadmap_size: 150", "roadmap_size: 20"))
    return path


def test_a_file_size_limit_keeps_the_old_file(tmp_path):
    """Under `ulimit -f`, the strategy file cannot be written whole: the
    command says so, the old file is untouched and nothing else is left."""
    target = tmp_path / "toy.strategy.json"
    target.write_text("the old strategy\n")

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (2048, 2048))
    # (the explicit solver: the compiled one would write numba's cache if it is cold)
    result = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", TOY, "--solver", "explicit",
                             "-o", str(target)],
                            capture_output=True, text=True, preexec_fn=limit, timeout=120)
    assert result.returncode == 2, result.stderr
    assert f"cannot write strategy file {target}: File too large" in result.stderr
    assert "Traceback" not in result.stderr
    assert target.read_text() == "the old strategy\n"
    assert sorted(os.listdir(tmp_path)) == ["toy.strategy.json"]


def test_write_atomic_replaces_whole_and_keeps_the_old_file_on_failure(tmp_path, monkeypatch):
    target = tmp_path / "out.txt"
    write_atomic(target, "first", "test file")
    assert target.read_text() == "first"
    write_atomic(target, "second", "test file")
    assert target.read_text() == "second"

    def fail(*_):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(os, "replace", fail)
    with pytest.raises(InputError, match="cannot write test file .*out.txt: No space left on device"):
        write_atomic(target, "third", "test file")
    assert target.read_text() == "second" and sorted(os.listdir(tmp_path)) == ["out.txt"]


def test_an_interrupt_mid_write_leaves_no_temporary(tmp_path, monkeypatch):
    import symsynth.files as files

    def interrupted(*_):
        raise KeyboardInterrupt
    monkeypatch.setattr(files.os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_atomic(tmp_path / "out.txt", "data", "test file")
    assert os.listdir(tmp_path) == []
