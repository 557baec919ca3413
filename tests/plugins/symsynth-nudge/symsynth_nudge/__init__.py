"""`nudge`: slide an object sideways, to the left of the way the hand faces
at the contact (90 degrees, within 20), along the table."""

from __future__ import annotations

import math

from symsynth.execution.hand_motions import slide
from symsynth.planning.slides import direction, slide_rule


class Nudge:
    name = "nudge"
    kind = "displacement"
    fixed_cost = 1.0

    def slides(self, scene, planner, contact, anchors):
        fixed = scene.geometry.primitive_costs.get(self.name, self.fixed_cost)
        rules = []
        for start in scene.locations:
            for goal in scene.locations:
                if start != goal and self._leftwards(scene, contact, start, goal):
                    for obj in scene.object_names:
                        rule = slide_rule(scene, planner, obj, contact, start, goal, anchors, fixed)
                        if rule is not None:
                            rules.append(rule)
                        break  # one shape in the scenes it is meant for
        return rules

    def _leftwards(self, scene, contact, start, goal):
        facing = scene.geometry.places[start] @ scene.geometry.hand_frame(contact).pose
        x, y = facing.matrix()[:2, 2]
        gx, gy = (b - a for a, b in zip(scene.geometry.places[start].xyz[:2], scene.geometry.places[goal].xyz[:2]))
        left = x * gy - y * gx > 0  # the goal lies to the left of the facing direction
        return left and abs(direction(scene, contact, start, goal) - math.pi / 2) <= math.radians(20)

    def execute(self, world, move, path):
        return slide(world, move, path)
