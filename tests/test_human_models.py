"""Human models as plugins (semantics §9): the built-in random(P) and a
third-party model (`tests/plugins/symsynth-tidy`, installed with pip into a
folder of its own) pass the conformance suite; the scene key and the flag
give clear errors; the third-party model is solved (by the explicit
solver: it is not uniform over the moves) to the value solved by hand."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest

from symsynth.errors import InputError
from symsynth.game.human_model import RandomModel, parse_model
from symsynth.testing import conformance
from symsynth.testing.human_model import HumanModelConformance

HERE = Path(__file__).parent
PLUGIN = HERE / "plugins" / "symsynth-tidy"
WAIT = HERE.parent / "scenes" / "wait.yaml"


TestRandom = conformance("human-model", "random(0.3)", "random(0)", "random:1")  # as a plugin's repository would


def test_random_is_exact_on_the_decimals():
    model = parse_model("random(0.3)")
    assert model.name == "random(0.3)" and isinstance(model, RandomModel)
    assert model.pass_probability(1, 4) == Fraction(7, 10) and model.pass_probability(0, 4) == 1


@pytest.mark.parametrize("text, message", [
    ("random(1.5)", "random(P) needs 0 <= P <= 1, found 1.5"),
    ("random(x)", "random(P) needs a number 0 <= P <= 1, found 'x'"),
    ("random", "random takes one argument"),
    ("chaos:0.1", "unknown human model 'chaos'; installed human models: random"),
    ("random 0.3", "expected NAME(ARGS) or NAME:ARGS"),
])
def test_bad_models_are_named(text, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        parse_model(text, "--human-model")


def test_the_scene_key_is_checked_where_it_is_written(tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text(WAIT.read_text().replace("model: random(0.3)", "model: random(2)")
                     .replace("wait.costmap.json", str(WAIT.with_name("wait.costmap.json"))))
    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(scene), "--objective", "expected"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert f"{scene}:40: human.model: random(P) needs 0 <= P <= 1, found 2" in done.stderr
    flag = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(scene), "--objective", "expected",
                           "--human-model", "random:0.5", "--json"], capture_output=True, text=True)
    assert flag.returncode == 0, flag.stderr  # the flag wins over the scene
    assert json.loads(flag.stdout)["expected_cost"] == pytest.approx(12.5 - 4 * 0.5)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    target = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", "--target", str(target),
                           str(PLUGIN)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return target


def test_a_third_party_model_conforms(installed, monkeypatch):
    monkeypatch.syspath_prepend(str(installed))

    suite = HumanModelConformance()
    suite.name = "tidy(1/2)"
    for name in dir(suite):
        if name.startswith("test_"):
            getattr(suite, name)()


def test_a_third_party_model_is_solved(installed):
    """wait.yaml against tidy(P), by hand: tidying b is the only move, so
    waiting never pays (it is worth 17 > 13 at the hand): at the hand
    13 + 4P after the human's turn, 17 + 4P at the start's robot turn, and
    (1 - P)(17 + 4P) + 17 P = 17 + 4P - 4P^2 = 18 at P = 1/2."""
    env = dict(os.environ, PYTHONPATH=str(installed))
    done = subprocess.run([sys.executable, "-m", "symsynth.cli", "solve", str(WAIT), "--objective", "expected",
                           "--human-model", "tidy:1/2", "--json"], capture_output=True, text=True, env=env)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert out["expected_cost"] == pytest.approx(18.0, abs=1e-9) and out["solver"] == "explicit"
    assert out["human_model"] == "tidy(1/2)" and out["attained"] is True


def test_the_simulated_random_human_is_the_model():
    """RandomHuman draws with random(P) over the abstraction's legal moves
    (b to l2, b to Else in wait.yaml: P/2 each), then a world option of the
    move drawn; a move with no option in the world is a pass."""
    from symsynth.execution.human import Option, RandomHuman, Turn
    from symsynth.game.abstraction import initial_state, legal_human_moves
    from symsynth.scene import load_scene

    scene = load_scene(WAIT)
    v = initial_state(scene)
    moves = legal_human_moves(scene, v)
    assert sorted(m.action for m in moves) == ["move(b,Else)", "move(b,l2)"]
    options = tuple(Option(m.action, "b", None, None) for m in moves)  # type: ignore[arg-type]
    human = RandomHuman(3, 0.3, scene)
    picks = [human.choose(Turn((v, None, 1), 0, None, options)) for _ in range(6000)]
    share = {a: sum(p is not None and p.action == a for p in picks) / len(picks) for a in ("move(b,l2)",
                                                                                        "move(b,Else)")}
    assert abs(share["move(b,l2)"] - 0.15) < 0.02 and abs(share["move(b,Else)"] - 0.15) < 0.02
    only_else = tuple(o for o in options if o.action == "move(b,Else)")  # the world forbids b to l2
    picks = [human.choose(Turn((v, None, 1), 0, None, only_else)) for _ in range(6000)]
    assert abs(sum(p is None for p in picks) / len(picks) - 0.85) < 0.02
    assert all(human.choose(Turn((v, None, 0), 0, None, options)) is None for _ in range(200))
