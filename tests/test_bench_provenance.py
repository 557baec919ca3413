"""The commit a benchmark run records (bench/provenance.py), checked on a
repository made here: its hash, `-dirty` once a tracked file changes (an
untracked one does not count), `unrecorded` outside git."""

from __future__ import annotations

import subprocess

from bench.provenance import commit


def git(root, *args):
    return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, check=True).stdout.strip()


def test_the_commit_of_a_checkout(tmp_path):
    repo = tmp_path / "repo"
    repo.mkdir()
    git(repo, "init", "-q")
    (repo / "a.txt").write_text("one\n")
    git(repo, "add", "a.txt")
    git(repo, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "first")
    head = git(repo, "rev-parse", "--short", "HEAD")
    assert commit(repo) == head
    (repo / "new.txt").write_text("untracked\n")
    assert commit(repo) == head
    (repo / "a.txt").write_text("two\n")
    assert commit(repo) == head + "-dirty"


def test_outside_a_checkout(tmp_path):
    assert commit(tmp_path) == "unrecorded"
