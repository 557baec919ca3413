"""A plain (non-editable) build ships the grammar and works from the wheel alone."""

import subprocess
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_wheel_ships_grammar_and_compiles(tmp_path):
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(wheels), str(ROOT)],
                   check=True, capture_output=True)
    (wheel,) = wheels.glob("symsynth-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert "symsynth/grammars/ltlf.lark" in names
    # every package of the source tree is listed in pyproject.toml
    sources = {p.relative_to(ROOT).as_posix() for p in (ROOT / "symsynth").rglob("*.py")}
    assert sources <= set(names), sorted(sources - set(names))

    target = tmp_path / "site"
    subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "-q", "--target", str(target),
                    str(wheel)], check=True, capture_output=True)
    probe = ("import symsynth, symsynth.automata as a; "
             "print(symsynth.__file__); print(a.compile_ltlf('G(p -> F q)').num_states)")
    out = subprocess.run([sys.executable, "-s", "-c", probe], cwd=tmp_path, check=True,
                         capture_output=True, text=True, env={"PYTHONPATH": str(target)}).stdout.split()
    assert out[0].startswith(str(target)), out  # imported from the wheel, not the checkout
    assert out[1] == "3"  # initial, satisfied, pending


def test_the_default_options_leave_the_summary_line_to_the_user():
    """addopts held -q, so `pytest -q` (-qq) dropped the "N passed" line."""
    import shlex
    import tomllib
    from pathlib import Path

    config = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())
    addopts = shlex.split(config["tool"]["pytest"]["ini_options"]["addopts"])
    assert not [o for o in addopts if o in ("-q", "--quiet") or (o.startswith("-q") and set(o[1:]) == {"q"})]
