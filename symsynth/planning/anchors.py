"""Anchors (semantics §5) as robot configurations, and the motions a mode needs.

`x/g` is the pre-image of grasp `g` for an object standing at `x`, found by
the planner's inverse kinematics seeded at home.  A contact's anchors are
seeded instead with the same contact's anchor at the nearest place solved
before (the first at home): a slide joins two of them by following the hand
in small inverse kinematics steps (`slides.py`), which stays on one branch
of the arm's solutions, so its anchors must be on one branch too; seeded at
home each, they fell on different ones, and the slide ended with a
joint-space turn of the whole arm that left the hand where it was.  An anchor that cannot be
reached, or where the robot collides with a static obstacle or with the
object standing at `x`, is an error naming it: a scene with a silently
missing anchor would make the game unrealizable for reasons nobody sees.
The scene may instead declare it absent (`absent_at: [x]` on the grasp or
contact: semantics §5's absent anchors); a declared anchor is not looked
for, gets no configuration, and the costmap records it under `absent`.
"""

from __future__ import annotations

from symsynth.planning.methods import Query
from symsynth.planning.protocol import Config, Mode, Planner, PlannerError
from symsynth.scene.geometry import point_text
from symsynth.scene.model import HOME, Scene, geometry_of


def place_of(anchor: str) -> str | None:
    return None if anchor == HOME else _place(anchor)


def _place(anchor: str) -> str:
    """The place of an anchor `x/a` (not `home`)."""
    return anchor.rsplit("/", 1)[0]


def anchor_configs(planner: Planner, scene: Scene) -> dict[str, Config]:
    """Every anchor's configuration; all failures are reported together."""
    geometry = geometry_of(scene)
    home = tuple(geometry.robot.home)
    configs: dict[str, Config] = {HOME: home}
    problems = []
    if planner.contacts(Mode(), home).static:
        problems.append(f"{HOME}: the robot collides with itself or a static obstacle")
    for place, pose in geometry.places.items():
        for grasp in scene.preimages:  # grasps and contacts
            name = f"{place}/{grasp}"
            if name in geometry.absent:
                continue
            target = pose @ geometry.hand_frame(grasp).pre_image()  # world frame
            seed = _seed(scene, configs, place, grasp) if grasp in geometry.contacts else home
            config = planner.inverse_kinematics(target, seed)
            if config is None:
                problems.append(f"{name}: unreachable (no inverse kinematics solution within the joint "
                                f"limits for the end-effector at {point_text(target.xyz)})")
                continue
            contacts = planner.contacts(Mode(), config)
            if contacts.static:
                problems.append(f"{name}: the robot collides with itself or a static obstacle there")
            elif place in contacts.locations:
                problems.append(f"{name}: the robot touches the object standing at {place}; "
                                "increase the grasp's approach distance")
            else:
                configs[name] = config
    if problems:
        raise PlannerError(f"{len(problems)} anchor{'s' if len(problems) > 1 else ''} cannot be used:\n"
                           + "\n".join(f"  {p}" for p in problems)
                           + "\n(where a grasp or contact cannot be used by design, declare it: "
                           "absent_at: [PLACE] on the grasp or contact)")
    return configs


def _seed(scene: Scene, configs: dict[str, Config], place: str, contact: str) -> Config:
    """The configuration of `contact`'s anchor at the place nearest `place`
    among those solved so far, or home when there is none."""
    places = geometry_of(scene).places
    solved = [x for x in places if f"{x}/{contact}" in configs]
    if not solved:
        return configs[HOME]
    here = places[place].xyz
    nearest = min(solved, key=lambda x: sum((a - b) ** 2 for a, b in zip(places[x].xyz, here)))
    return configs[f"{nearest}/{contact}"]


def mode_queries(scene: Scene, mode: Mode) -> tuple[Query, ...]:
    """The anchor pairs a mode's actions can ask for (semantics §4, §5):
    transits go from any anchor to any `x/a` (a grasp or a contact); transfers holding `o` with `g`
    go from `x/g` (`x` in L or E) to `l/g` (`l` in L).

    `always`: the object a transit goes to fetch stands at its target.
    `never`: a transfer's target must be free, and while the hand holds an
    object over a location of interest nobody can put anything there (spec
    §4: the human's move needs "not (holding and ee = t)"), so a transfer
    starting over `x ∈ L` has `x` free."""
    locations = set(scene.locations)
    places = scene.locations + scene.else_samples
    if mode.object is None:
        targets = [f"{x}/{a}" for x in places for a in scene.preimages]
        return tuple(Query(s, t, always=frozenset({_place(t)}))
                     for s in (HOME,) + tuple(targets) for t in targets if s != t)
    g = mode.grasp
    result = []
    for x in places:
        for l in scene.locations:
            if x == l:
                continue
            never = {l} | ({x} & locations)
            result.append(Query(f"{x}/{g}", f"{l}/{g}", never=frozenset(never)))
    return tuple(result)

