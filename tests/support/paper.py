"""The bundled scenes, and the paper's two on small roadmaps (the session
fixtures in conftest.py compute their costmaps once)."""

import dataclasses
from pathlib import Path

from symsynth.scene import load_scene

ROADMAP = 60  # vertices per mode: the paper's findings hold from here on (measured up to 150)
PLANNERS = {"arch": "pybullet", "line": "ompl-fcl"}  # one scene per built-in planner
SCENES = Path(__file__).resolve().parents[2] / "scenes"
DATA = Path(__file__).resolve().parents[1] / "data"


def small(name):
    """`scenes/NAME.yaml` with roadmaps of `ROADMAP` vertices."""
    scene = load_scene(SCENES / f"{name}.yaml")
    settings = dataclasses.replace(scene.geometry.planner, roadmap_size=ROADMAP, name=PLANNERS[name])
    return dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))
