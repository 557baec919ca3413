"""Which world `simulate` runs a scene in when none is asked for:
`default_world`, physics unless an object is wider across the fingers than
they open (`unheld`), which the robot's URDF tells (`gripper_opening`)."""

from __future__ import annotations

from symsynth import bullet
from symsynth.bullet import pybullet
from symsynth.scene.model import Scene


def gripper_opening(scene: Scene) -> float:
    """How far the robot's fingers (its `fixed` prismatic joints, held
    open) travel to close, in metres: 8 cm for the Panda's two 4 cm."""
    assert scene.geometry is not None
    client = bullet.client()
    try:
        loaded = bullet.load_robot(client, scene.geometry.robot)
        return sum(value - loaded.infos[j][8] for j, value in loaded.held.items()
                   if loaded.infos[j][2] == pybullet.JOINT_PRISMATIC)
    finally:
        client.disconnect()


def unheld(scene: Scene) -> list[str]:
    """Why the physical world cannot carry the scene's strategies: each
    object and grasp the costmap may hold it with (`robot: {opening}` lets
    them, or the scene gives none) that is wider across the fingers than
    they open, e.g. `b is 14 cm across the fingers of grasp top`."""
    geometry = scene.geometry
    if geometry is None or not scene.objects or not geometry.grasps:
        return []
    opening = gripper_opening(scene)
    found = []
    for obj in scene.object_names:
        for grasp in geometry.grasps:
            width = geometry.across_fingers(obj, grasp)
            allowed = geometry.robot.opening is None or (width is not None and width <= geometry.robot.opening)
            if width is not None and allowed and width > opening + 1e-9:
                found.append(f"{obj} is {100 * width:.0f} cm across the fingers of grasp {grasp}, "
                             f"which open {100 * opening:.0f} cm")
    return found


def default_world(scene: Scene) -> tuple[str, list[str]]:
    """`simulate`'s world when none is asked for: `physics` for a scene
    with a robot and objects whose every grasp the fingers can close on,
    else `kinematic`, with the reasons (`unheld`)."""
    if scene.geometry is None or not scene.objects:
        return "kinematic", ["the scene has no objects to move"]
    why = unheld(scene)
    return ("kinematic" if why else "physics"), why
