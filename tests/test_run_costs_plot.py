"""`symsynth bench`'s run costs of an objective (semantics §9): the plays of
the expected-cost strategy against its model on the wait scene (EX = 12.5 -
4P by hand, docs/game-semantics.md §9) stay within B and average EX; the
plot of their distribution per cell is written, sized by its cells, and
left out when no cell has plays."""

from __future__ import annotations

import json
import math
from pathlib import Path

from PIL import Image

from symsynth.bench import plots
from symsynth.bench.results import COLUMNS
from symsynth.bench.worker import PLAYS, _run_costs
from symsynth.game.human_model import parse_model
from symsynth.scene import load_scene
from symsynth.solvers.objectives import solve_objective

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def _row(cell: str, costs: list[float] | None, ep: float, budget: str = "") -> dict[str, str]:
    row = dict.fromkeys(COLUMNS, "")
    row |= {"cell": cell, "status": "ok", "E_p": str(ep), "budget": budget,
            "run_costs": "" if costs is None else json.dumps(costs)}
    return row


def test_the_plays_stay_within_B_and_average_EX_and_their_plot_is_written(tmp_path):
    s = solve_objective(load_scene(SCENES / "wait.yaml"), objective="expected", model=parse_model("random:0.3"),
                        solver="explicit")
    costs = _run_costs(s, seed=5)
    assert costs is not None and len(costs) == PLAYS  # every play wins
    assert max(costs) <= 21
    mean = sum(costs) / len(costs)
    sd = math.sqrt(sum((c - mean) ** 2 for c in costs) / (len(costs) - 1))
    assert abs(mean - (12.5 - 4 * 0.3)) <= 4 * sd / math.sqrt(len(costs)) + s.epsilon
    rows = [_row("wait expected", costs, 21.0), _row("wait expected", costs[:10], 21.0),
            _row("wait expected B=30", costs, 21.0, "30"), _row("wait worst", None, 21.0)]
    path = tmp_path / "run-costs.png"
    assert plots.run_costs(rows, ["wait expected", "wait expected B=30", "wait worst"], path)
    with Image.open(path) as image:
        assert image.format == "PNG"
        assert image.size == (plots.RUN_COSTS_WIDTH * plots.DPI, round((1.5 + 0.5 * 2) * plots.DPI))
        assert len(image.getcolors(1 << 16) or range(1 << 16)) > 10  # drawn, not blank
    assert not plots.run_costs([_row("wait worst", None, 21.0)], ["wait worst"], tmp_path / "none.png")
    assert not (tmp_path / "none.png").exists()
