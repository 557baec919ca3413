"""Scenes: the objects, locations, grasps and human of a manipulation problem,
loaded from YAML and validated, and the conditional costmap format."""

from symsynth.scene.costmap import Costmap, Provenance, Rule, load_costmap, write_costmap
from symsynth.scene.load import load_scene, scene_from_data
from symsynth.scene.model import ObjectSpec, Scene

__all__ = ["Costmap", "Provenance", "Rule", "load_costmap", "write_costmap", "load_scene",
           "scene_from_data", "ObjectSpec", "Scene"]
