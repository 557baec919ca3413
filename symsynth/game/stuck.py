"""Why the robot has no action in a state: each action it could take, and
what it lacks (semantics §4, §4b, §5), for the counter play's last state."""

from __future__ import annotations

import math

from symsynth.game.abstraction import Move, State, costmap_of, motions, slides
from symsynth.scene.model import ELSE, Scene

MAX_REASONS = 3  # missing motions listed per action


def stuck_reasons(scene: Scene, v: State) -> list[str]:
    """Why each action the robot could take in `v` is unavailable (semantics §4, §5)."""
    held = v.held()
    wanted = motions(scene, v)
    reasons: list[str] = []
    if held is None and not wanted:
        reasons.append("there is no object to reach")
    if held is not None:
        o = scene.object_names[held]
        if v.ee == ELSE:  # with ee at a (free) location, drop would be available
            reasons.append(f"drop({o},...): {o} is held but not aligned with a location")
        if not wanted:
            reasons.append(f"transfer: {o} is held and every other location is occupied")
    if held is None and isinstance(v.ee, tuple) and v.ee[1] in scene.contacts:
        reasons += _why_no_slide(scene, v)
    return reasons + [_why(scene, m) for m in wanted]


def _why_no_slide(scene: Scene, v: State) -> list[str]:
    """Why the robot, at contact `a` of `o`, cannot slide `o` to each place
    it cannot (semantics §4b); nothing for the slides it can make."""
    if not isinstance(v.ee, tuple):  # the hand is at no contact
        return []
    o, a = v.ee
    start = v.at[scene.object_names.index(o)]
    name = f"slide({o},{a},...)"
    if start not in scene.locations:
        return [f"{name}: {o} is at {ELSE}, and only an object at a location of interest is slid"]
    targets = [l for l in scene.locations if l not in v.at]
    if not targets:
        return [f"{name}: every other location is occupied"]
    available = {m.location for m in slides(scene, v) if m.cost != math.inf}
    unruled = [l for l in targets if not costmap_of(scene).slide_rules(a, start, l)]
    blocked = [l for l in targets if l not in unruled and l not in available]
    reasons = []
    if unruled:
        reasons.append(f"{name}: the costmap has no slide rule for {a} from {start} to {', '.join(unruled)}")
    if blocked:
        reasons.append(f"{name}: the costmap's slide rules for {a} from {start} to {', '.join(blocked)} "
                       "all need a location free that is occupied")
    return reasons


def _why(scene: Scene, m: Move) -> str:
    action, mode = m.action, m.mode
    if mode is None:  # motions() gives transits and transfers, which have a mode
        raise ValueError(f"{action} is no motion")
    if not m.goals:
        return f"{action}: the object is at {ELSE} and the scene has no else_samples"
    if not m.starts:
        return f"{action}: the hand is at {ELSE} and the scene has no else_samples"
    missing = [f"{s} -> {t}" for s in m.starts for t in m.goals
               if s != t and not costmap_of(scene).rules(mode, s, t)]
    if not missing:
        return (f"{action}: the costmap's rules for {mode} to {', '.join(m.goals)} all need "
                "a location free that is occupied")
    more = f" (and {len(missing) - MAX_REASONS} more)" if len(missing) > MAX_REASONS else ""
    return (f"{action}: the costmap has no motion for mode {mode} from "
            f"{', '.join(missing[:MAX_REASONS])}{more}")
