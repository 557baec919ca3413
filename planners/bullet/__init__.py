"""The `pybullet` planner plugin: collision checking and inverse kinematics
by PyBullet in a private, headless physics client (`planner.BulletPlanner`)."""

from symsynth_planners.bullet.planner import BulletPlanner

__all__ = ["BulletPlanner"]
