"""The package's layers, bottom to top, and that no module imports one
above its own: errors and the plugin registries; logic; automata; scene;
the simulator's pybullet helpers; planning; the game's rules; its solvers
and LTLf synthesis; execution; the application layer; the command line and
comparison runs.  (The issue that asked for it found symbolic/ importing
game/ while game/ imported symbolic/, and scene/ importing game/.)"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "symsynth"
RANK = {"__version__": 0, "errors": 0, "files": 0, "plugins": 0, "primitives": 0, "parallel": 0, "grammars": 0,
        "logic": 1, "automata": 2, "scene": 3, "bullet": 3.5, "planning": 4, "game": 5,
        "solvers": 6, "synthesis": 6, "execution": 7, "problem": 8, "bench": 9, "cli": 9, "testing": 9, "__main__": 10}


def layer(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__main__"


def test_every_module_has_a_layer():
    found = {layer(".".join(f.relative_to(PACKAGE.parent).with_suffix("").parts)) for f in PACKAGE.rglob("*.py")}
    assert found - {"__init__"} <= set(RANK), found - set(RANK)


def test_no_module_imports_a_layer_above_its_own():
    climbs = []
    for file in PACKAGE.rglob("*.py"):
        module = ".".join(file.relative_to(PACKAGE.parent).with_suffix("").parts)
        mine = RANK.get(layer(module), RANK["__main__"])
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "symsynth":
                targets = [node.module] if node.module != "symsynth" else [f"symsynth.{a.name}" for a in node.names]
                climbs += [f"{module} imports {t}" for t in targets if RANK[layer(t)] > mine]
            elif isinstance(node, ast.Import):
                climbs += [f"{module} imports {a.name}" for a in node.names
                           if a.name.startswith("symsynth.") and RANK[layer(a.name)] > mine]
    assert climbs == []
