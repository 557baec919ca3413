"""The conformance suite of human models (semantics §9): every model a
plugin registers in `symsynth.human_models` must pass it, and symsynth's
own `random(P)` does (tests/test_human_models.py).

Run it from pytest as every suite of `symsynth.testing` is run, with the
model's text as a scene writes it standing for the plugin's name::

    from symsynth.testing import conformance

    TestMine = conformance("human-model", "mine(0.2)")

It checks, on every human turn of a small scene (one to three blocks, some
at Else, with 0 to 2 moves left): a distribution of exact fractions, one
probability per legal move, each in [0, 1], summing to exactly 1; only the
pass when no move is left; the same answer twice (the solvers and the
simulator must see the same model); the name read back as the same model;
draws that follow the distribution within a generous bound; and, for a
model that says it is uniform over the moves (`pass_probability`), that
its distribution is that.
"""

from __future__ import annotations

import random
from fractions import Fraction
from itertools import product

from symsynth.game.abstraction import State, legal_human_moves
from symsynth.game.human_model import HumanModel, draw, parse_model
from symsynth.scene.load import scene_from_data
from symsynth.scene.model import ELSE, HAND, Scene
from symsynth.testing import Conformance


def conformance_scene() -> Scene:
    """Three blocks, three locations, one Else sample, no task."""
    motions = [{"mode": "empty", "from": "home", "to": f"{x}/top", "rules": [{"free": [], "cost": 1}]}
               for x in ("l1", "l2", "l3", "e1")]
    return scene_from_data({
        "name": "human-model-conformance",
        "objects": {"a": {"tags": ["block"], "at": "l1"}, "b": {"tags": ["block", "red"], "at": "Else"},
                    "c": {"tags": ["block"], "at": "l3"}},
        "locations": ["l1", "l2", "l3"], "else_samples": ["e1"], "grasps": ["top"],
        "human": {"k": 2}, "task": "F(at(red, l2))",
        "costmap": {"format": "symsynth.costmap/1", "motions": motions}})


def human_turns(scene: Scene) -> list[tuple[State, int]]:
    """States of `scene` with moves left 0..2: each object on a location, at
    Else or in the hand (one at most), the hand at Else or above a location."""
    places = list(scene.locations) + [ELSE, HAND]
    turns = []
    for at in product(places, repeat=len(scene.objects)):
        if any(at.count(p) > 1 for p in [*scene.locations, HAND]):
            continue
        held = HAND in at
        for ee in ([ELSE, *[l for l in scene.locations if l not in at]] if held else [ELSE]):
            v = State(tuple(at), "top" if held else None, ee)
            turns += [(v, h) for h in range(3)]
    return turns


class HumanModelConformance(Conformance):
    """`self.name`: the model as a scene writes it (`random(0.3)`)."""

    def model(self) -> HumanModel:
        return parse_model(self.name, f"{type(self).__name__}")

    def test_is_a_model_with_a_name(self):
        model = self.model()
        assert isinstance(model, HumanModel)
        assert isinstance(model.name, str) and model.name

    def test_distributions_are_exact_and_complete(self):
        model, scene = self.model(), conformance_scene()
        for v, h in human_turns(scene):
            moves = legal_human_moves(scene, v) if h > 0 else []
            stay, each = model.distribution(v, h, moves)
            assert isinstance(stay, Fraction) and all(isinstance(p, Fraction) for p in each), (v, h)
            assert len(each) == len(moves), (v, h)
            assert 0 <= stay <= 1 and all(0 <= p <= 1 for p in each), (v, h)
            assert stay + sum(each) == 1, (v, h)
            if not moves:
                assert stay == 1, (v, h)

    def test_same_answer_twice(self):
        model, scene = self.model(), conformance_scene()
        for v, h in human_turns(scene)[:60]:
            moves = legal_human_moves(scene, v) if h > 0 else []
            assert model.distribution(v, h, moves) == model.distribution(v, h, moves)

    def test_name_reads_back_as_the_same_model(self):
        model, scene = self.model(), conformance_scene()
        again = parse_model(model.name, "name")
        assert again.name == model.name
        for v, h in human_turns(scene)[:60]:
            moves = legal_human_moves(scene, v) if h > 0 else []
            assert again.distribution(v, h, moves) == model.distribution(v, h, moves)

    def test_uniform_models_say_so_truly(self):
        model, scene = self.model(), conformance_scene()
        uniform = getattr(model, "pass_probability", None)
        if uniform is None:
            return
        for v, h in human_turns(scene):
            moves = legal_human_moves(scene, v) if h > 0 else []
            stay, each = model.distribution(v, h, moves)
            assert stay == uniform(h, len(moves)), (v, h)
            assert len(set(each)) <= 1, (v, h)

    def test_draws_follow_the_distribution(self):
        model, scene = self.model(), conformance_scene()
        v = State(("l1", ELSE, "l3"), None, ELSE)
        moves = legal_human_moves(scene, v)
        stay, _ = model.distribution(v, 1, moves)
        rng = random.Random(7)
        picks = [draw(model, rng, v, 1, moves) for _ in range(4000)]
        assert all(p is None or p in moves for p in picks)
        passes = sum(p is None for p in picks) / len(picks)
        assert abs(passes - float(stay)) < 0.05  # 4000 draws: about 7 standard deviations at worst
