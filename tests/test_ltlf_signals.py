"""SIGTERM and Ctrl-C end `symsynth dfa` and `symsynth synth` within a
second or two even in the middle of a long BDD operation (issue 31: a
Python signal handler waits until CUDD returns, minutes at worst).

The work: the until chain p1 U (p2 U (... U p25)), whose construction
spends most of its time in single CUDD calls of seconds each (a
substitution over 25 atoms and obligations: one call lasts from about
3.4 s to 14.3 s into the run here).  The signal comes 5 s into it.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

CHAIN = 25


def chain(n: int) -> str:
    text = f"p{n}"
    for i in range(n - 1, 0, -1):
        text = f"p{i} U ({text})"
    return text


def start(argv: list[str], cwd, sigint) -> subprocess.Popen:
    """The command in a process of its own, started with SIGINT's action
    `sigint` (a terminal's foreground job has the default one, a shell's
    background job SIGINT ignored)."""
    return subprocess.Popen([sys.executable, "-m", "symsynth.cli", *argv], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, sigint))


def ended_after(argv: list[str], signum: int, cwd) -> tuple[int, float, str]:
    """(return code, seconds from the signal to the exit, stderr)."""
    process = start(argv, cwd, signal.SIG_DFL)
    time.sleep(5.0)
    assert process.poll() is None, "the command ended before the signal: no long work to interrupt"
    clock = time.monotonic()
    process.send_signal(signum)
    try:
        _, err = process.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        return process.returncode, 60.0, ""
    return process.returncode, time.monotonic() - clock, err


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_dfa_ends_at_once_on_a_signal(tmp_path, signum):
    (tmp_path / "chain.ltlf").write_text(chain(CHAIN))
    code, seconds, err = ended_after(["dfa", "-f", "chain.ltlf", "--dot", "chain.dot"], signum, tmp_path)
    assert seconds < 2.0
    assert code == -signum  # ended by the signal (128 + signum in a shell)
    assert "Traceback" not in err
    assert os.listdir(tmp_path) == ["chain.ltlf"]  # no DOT file, no temporary left


def test_synth_ends_at_once_on_sigterm(tmp_path):
    (tmp_path / "chain.ltlf").write_text(chain(CHAIN))
    (tmp_path / "chain.part").write_text(".inputs: " + " ".join(f"p{i}" for i in range(1, CHAIN + 1, 2)) +
                                         "\n.outputs: " + " ".join(f"p{i}" for i in range(2, CHAIN + 1, 2)) + "\n")
    code, seconds, _ = ended_after(["synth", "chain.ltlf", "--part", "chain.part", "-o", "s.json"],
                                   signal.SIGTERM, tmp_path)
    assert code == -signal.SIGTERM
    assert seconds < 2.0
    assert sorted(os.listdir(tmp_path)) == ["chain.ltlf", "chain.part"]


def test_an_ignored_sigint_stays_ignored(tmp_path):
    """A background job started with SIGINT ignored goes on after a SIGINT
    (stopping.killable must not give it back its default action); SIGTERM
    still ends it."""
    (tmp_path / "chain.ltlf").write_text(chain(CHAIN))
    process = start(["dfa", "-f", "chain.ltlf"], tmp_path, signal.SIG_IGN)
    try:
        time.sleep(2.0)
        assert process.poll() is None, "the command ended before the signal: no long work to interrupt"
        process.send_signal(signal.SIGINT)
        time.sleep(1.0)
        assert process.poll() is None, "an ignored SIGINT ended the command"
        process.send_signal(signal.SIGTERM)
        process.communicate(timeout=60)
        assert process.returncode == -signal.SIGTERM
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
