"""The LTLf subcommands load only what they use (issue 31): each runs in a
fresh interpreter, and what it imported is read from `sys.modules`.  (Not
timed: the time is measured in docs/benchmarks.md.)"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

#: What `dfa` and `synth` must never import: the game's solvers and their
#: numba kernels, the scene and motion planning, plots, the benchmarks, and
#: the libraries only those use (networkx and tqdm too: 70 and 40 ms;
#: decimal, for budgets, and importlib.resources with zipfile, which found
#: the grammar files: 1-3 ms each).
FORBIDDEN = ("numba", "scipy", "pybullet", "ompl", "matplotlib", "fcl", "trimesh", "yaml",
             "networkx", "tqdm", "decimal", "zipfile", "importlib.resources", "symsynth.solvers", "symsynth.bench", "symsynth.game",
             "symsynth.scene", "symsynth.planning", "symsynth.execution", "symsynth.problem",
             "symsynth.cli.solve", "symsynth.cli.bench", "symsynth.cli.costmap")

PROGRAM = """
import json, sys
from symsynth.cli import main
code = main(sys.argv[1:])
print(json.dumps({"code": code, "modules": sorted(sys.modules)}))
"""


def loaded(*argv: str) -> tuple[int, list[str]]:
    """The exit code and the modules of `symsynth ARGV` in a fresh interpreter
    (its stderr a pipe: no terminal, no progress bar)."""
    done = subprocess.run([sys.executable, "-c", PROGRAM, *argv], capture_output=True, text=True,
                          check=True)
    result = json.loads(done.stdout.strip().splitlines()[-1])
    return result["code"], result["modules"]


def forbidden(modules: list[str]) -> list[str]:
    return [m for m in modules if any(m == f or m.startswith(f + ".") for f in FORBIDDEN)]


@pytest.mark.parametrize("argv", [
    ("dfa", "a U b"),
    ("dfa", "--json", "G(a -> F b)"),
])
def test_dfa_imports_only_the_ltlf_compiler(argv):
    code, modules = loaded(*argv)
    assert code == 0
    assert "symsynth.automata" in modules  # (it did compile)
    assert forbidden(modules) == []


def test_synth_imports_only_the_compiler_and_the_game_on_the_dfa(tmp_path):
    (tmp_path / "s.ltlf").write_text("G(a -> X[!] b)")
    (tmp_path / "s.part").write_text(".inputs: a\n.outputs: b\n")
    code, modules = loaded("synth", str(tmp_path / "s.ltlf"), "--part", str(tmp_path / "s.part"),
                           "-o", str(tmp_path / "s.json"))
    assert code in (10, 20)
    assert "symsynth.synthesis" in modules
    assert forbidden(modules) == []


def test_synth_on_tlsf_imports_no_more():
    """The TLSF reader (lark and the evaluation of GLOBAL) adds no solver."""
    from pathlib import Path
    chomp = Path(__file__).parent / "data" / "tlsf-fin" / "chomp.tlsf"
    code, modules = loaded("synth", str(chomp), "--param", "N=1")
    assert code == 10
    assert "symsynth.synthesis.tlsf" in modules
    assert forbidden(modules) == []


def test_the_check_sees_a_forbidden_import():
    """The same probe on `solve --help`, which imports the solvers: the
    check is able to fail."""
    code, modules = loaded("solve", "--help")
    assert code == 0
    assert "symsynth.solvers" in forbidden(modules)


def test_help_still_lists_every_subcommand(capsys):
    from symsynth.cli import COMMANDS, main
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for name in COMMANDS:
        assert f"    {name} " in out
    for name in ("dfa", "solve", "costmap", "show", "simulate", "synth", "bench"):
        assert name in COMMANDS


def test_the_command_list_imports_no_command():
    """`symsynth --help` lists every command with its line from `COMMANDS`
    without importing any command's module (they load the solvers, the
    scene and pybullet: 0.7 s before this, measured in the commit)."""
    from symsynth.cli import COMMANDS
    done = subprocess.run([sys.executable, "-c", PROGRAM, "--help"], capture_output=True, text=True,
                          check=True)
    listing = done.stdout
    for name, line in COMMANDS.items():
        assert name in listing and line.split()[0] in listing
    result = json.loads(listing.strip().splitlines()[-1])
    assert result["code"] == 0
    assert [m for m in result["modules"] if m.startswith("symsynth.cli.")] == []
