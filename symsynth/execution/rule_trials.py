"""A costmap's rules tried in the physical world (`symsynth costmap verify
--physics`, `symsynth costmap --min-success`): does the object end where
the rule says, how often, over seeded randomized worlds?

A *subject* is one rule tried with one object:

- a **transfer** rule (mode `o/g`, from anchor `x/g` to `y/g`): `o` stands
  on `x`, the robot on the path's first configuration; the game's `grab`
  primitive closes the hand on `o` (it must then be held by the fingers and
  lifted: within `POSITION` of where the grasp puts it in the hand, at
  least half the approach above `x`), the robot follows the rule's evidence
  path holding it, and the `drop` primitive sets it down on `y`, where it
  must settle within `POSITION` (the observation's tolerance).  A
  principal play's transfer that starts with the object already in the
  hand (carried on from an earlier transfer) is tried from the grab: the
  object grabbed where the play grabbed it, the earlier transfers' paths
  followed first (`Subject.rest`, `Subject.lead`).  So the
  grab, the carry and the drop of the rule are tried together, and the
  grab's own rate is kept apart (`Rate.grabs`).
- a **slide** rule (contact `a`, from location `x` to `y`): `slide_trial`
  (`execution.trial`) with each object of a distinct shape (a slide rule
  serves every object: `planning.slides` builds it for each shape); it must
  end within `POSITION` of `y`, and have moved only while the robot
  touched it (`Outcome.untouched` under `UNTOUCHED`): a primitive that sets
  the object's pose fails however well it aims.

The other objects respect the rule's `free` set: each stands where the
scene puts it (or where a given state does, `placement`) unless that place
is in `free` or is one of the rule's two places, in which case it is
removed (an object at Else stands on its own pose in the scene, which is
an Else sample's when it lies within `POSITION` of one).  (Slides are tried with the slid object alone, as `slide_trial`
builds its world: removing every other object respects any `free` set.)
A location that rests on other objects (the arch's `top`) is supported
only if the placement puts them there: with the scene's initial placement
a drop on it falls to the table, and its rule is rightly reported as
failing from there.  Trial `t` of every subject uses seed `seed + t`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

from symsynth.errors import SymsynthError
from symsynth.execution.hand_motions import Approaches
from symsynth.execution.observe import POSITION, distance, place_at
from symsynth.execution.physics import PhysicsWorld, Randomization
from symsynth.execution.trial import slide_trial
from symsynth.game.abstraction import Move, State
from symsynth.planning.protocol import Config, Planner
from symsynth.primitive_registry import prehensile_primitives
from symsynth.scene.costmap import Costmap, Rule
from symsynth.scene.model import ELSE, EMPTY, HAND, Scene, geometry_of

#: metres an object may move while nothing of the robot touched it in a
#: slide (settling, a pushed object coasting past `trial.COAST`)
UNTOUCHED = 0.005


@dataclass(frozen=True)
class Subject:
    """One rule of a costmap tried with one object."""

    kind: str  # "transfer" or "slide"
    key: tuple[str, str, str]  # the costmap's key: (mode, from-anchor, to-anchor) or (contact, from, to)
    index: int  # the rule's index under its key
    obj: str
    hold: str  # the grasp (transfer) or contact (slide)
    start: str  # places: locations or Else samples
    goal: str
    rule: Rule = field(compare=False)
    #: Transfers: where the object is grabbed, when not at `start` (a play's
    #: transfer that starts holding it, e.g. above a place where it cannot
    #: rest), and the configurations from that place's anchor to the rule's
    #: first one (the play's earlier transfers while holding it).
    rest: str | None = None
    lead: tuple[Config, ...] = field(default=(), compare=False)

    @property
    def label(self) -> str:
        what = f"{self.kind} {self.key[0]} {self.key[1]} -> {self.key[2]} #{self.index}"
        if self.rest is not None:
            what += f" (grabbed at {self.rest})"
        return what if self.kind == "transfer" else f"{what} ({self.obj})"


@dataclass(frozen=True)
class Tried:
    """One trial: whether the object ended where the rule says, how far
    from it (metres), and why not."""

    success: bool
    error: float
    reason: str = ""
    grabbed: bool | None = None  # transfer: whether the grab held and lifted the object


@dataclass(frozen=True)
class Rate:
    subject: Subject
    trials: tuple[Tried, ...]

    @property
    def successes(self) -> int:
        return sum(t.success for t in self.trials)

    @property
    def rate(self) -> float:
        return self.successes / len(self.trials) if self.trials else 0.0

    @property
    def grabs(self) -> int | None:
        """Transfers: the trials whose grab held and lifted the object."""
        return None if self.subject.kind != "transfer" else sum(bool(t.grabbed) for t in self.trials)

    @property
    def worst_error(self) -> float:
        return max((t.error for t in self.trials), default=0.0)

    @property
    def reasons(self) -> list[str]:
        """The distinct reasons of the failed trials, most frequent first."""
        counts: dict[str, int] = {}
        for t in self.trials:
            if not t.success:
                counts[t.reason] = counts.get(t.reason, 0) + 1
        return sorted(counts, key=lambda r: -counts[r])

    def to_json(self) -> dict[str, object]:
        s = self.subject
        return {"kind": s.kind, "key": list(s.key), "rule": s.index, "object": s.obj, "from": s.start,
                "to": s.goal, "free": sorted(s.rule.free), "cost": s.rule.cost, "trials": len(self.trials),
                "successes": self.successes, "rate": self.rate, "grabs": self.grabs,
                "worst_error": round(self.worst_error, 5), "reasons": self.reasons}


def subjects(scene: Scene, costmap: Costmap) -> list[Subject]:
    """Every transfer and slide rule of `costmap` with evidence, with its
    object(s) (module doc); transits move no object and are left out."""
    found = []
    for (mode, s, t), rules in sorted(costmap.motions.items()):
        if mode == EMPTY:
            continue
        obj, grasp = mode.split("/")
        for i, rule in enumerate(rules):
            if rule.path:
                found.append(Subject("transfer", (mode, s, t), i, obj, grasp, s.split("/")[0], t.split("/")[0],
                                     rule))
    shapes = geometry_of(scene).shapes
    distinct = list({repr(shapes[o]): o for o in reversed(scene.object_names)}.values())[::-1]
    for (contact, s, t), rules in sorted(costmap.slides.items()):
        for i, rule in enumerate(rules):
            if rule.path:
                found += [Subject("slide", (contact, s, t), i, obj, contact, s, t, rule) for obj in distinct]
    return found


def initial_placement(scene: Scene) -> dict[str, str]:
    """Where the scene puts each object (a place, or `ELSE` for one off every place)."""
    return {o.name: o.at for o in scene.objects}


def state_placement(scene: Scene, state: State) -> dict[str, str]:
    """Where an abstract state puts each object; one in the hand stands
    nowhere, one at Else where the scene puts it if it starts there."""
    initial = initial_placement(scene)
    return {o: at for o, at in zip(scene.object_names, state.at)
            if at != HAND and (at != ELSE or initial[o] == ELSE)}


def trial_scene(scene: Scene, subject: Subject, placement: Mapping[str, str]) -> Scene:
    """The scene of one trial: the subject's object on its start, the others
    where `placement` puts them unless the rule needs that place free."""
    rest = subject.start if subject.rest is None else subject.rest
    taken = subject.rule.free | {subject.start, subject.goal, rest}
    specs, initial = {o.name: o for o in scene.objects}, geometry_of(scene).initial
    objects = [dataclasses.replace(specs[subject.obj], at=rest)]
    for name, at in placement.items():
        # an object at Else stands on its scene pose, which may be an Else sample's
        where = place_at(scene, initial[name]) if at == ELSE and name in initial else at
        if name != subject.obj and where not in taken:
            objects.append(dataclasses.replace(specs[name], at=at))
    return dataclasses.replace(scene, objects=tuple(objects), task=None)


def transfer_trial(scene: Scene, planner: Planner, subject: Subject, placement: Mapping[str, str], *,
                   randomization: Randomization | None = None, seed: int = 0) -> Tried:
    """Grab, carry along the rule's path, drop (module doc), in a physical
    world of its own."""
    geometry = geometry_of(scene)
    grab, drop = prehensile_primitives()
    obj, grasp, goal = subject.obj, subject.hold, subject.goal
    path, rest = subject.rule.path or (), subject.start if subject.rest is None else subject.rest
    world = PhysicsWorld(trial_scene(scene, subject, placement), randomization=randomization, seed=seed)
    try:
        world.set_config((subject.lead or path)[0])
        world.settle()
        approaches = Approaches(planner)
        before = world.poses[obj].xyz[2]
        grabbed = State((HAND,), grasp, rest)
        try:
            grab.execute(world, approaches, Move("grab", f"grab({obj})", obj, 0, grasp, rest, grabbed))
        except SymsynthError as error:
            return Tried(False, float("inf"), f"grab failed: {error}", False)
        held = _held(world, obj, grasp, before)
        if held:
            return Tried(False, float("inf"), f"grab: {held}", False)
        world.follow(subject.lead + path)
        if world.held != obj or _held(world, obj, grasp, before):
            return Tried(False, distance(world.poses[obj], geometry.places[goal]), "slipped during the transfer",
                         True)
        after = State((goal,), None, (obj, grasp))
        try:
            drop.execute(world, approaches, Move("drop", f"drop({obj},{goal})", obj, 0, grasp, goal, after))
        except SymsynthError as error:
            return Tried(False, float("inf"), f"drop failed: {error}", True)
        error_ = distance(world.poses[obj], geometry.places[goal])
        if error_ > POSITION:
            return Tried(False, error_, "did not settle on the location", True)
        return Tried(True, error_, "", True)
    finally:
        world.close()


def _held(world: PhysicsWorld, obj: str, grasp: str, floor: float) -> str:
    """Why `obj` is not held with `grasp` and lifted, '' when it is."""
    if world.held != obj or not world.fingers_touch(obj):
        return "the fingers do not hold the object"
    g = world.geometry.grasps[grasp]
    in_hand = world.ee_pose() @ g.pose.inverse()
    if distance(world.poses[obj], in_hand) > POSITION:
        return f"held {distance(world.poses[obj], in_hand) * 100:.1f} cm off the grasp"
    if world.poses[obj].xyz[2] - floor < g.approach / 2:
        return "not lifted"
    return ""


def slide_tried(scene: Scene, subject: Subject, *, randomization: Randomization | None = None,
                seed: int = 0, primitive: object = None) -> Tried:
    """`slide_trial` judged: within `POSITION` of the goal, moved only by contact."""
    out = slide_trial(scene, subject.obj, subject.hold, subject.start, subject.goal, subject.rule.path or (),
                      primitive=primitive, randomization=randomization, seed=seed)
    if out.untouched > UNTOUCHED:
        return Tried(False, out.error, f"moved {out.untouched * 100:.1f} cm while nothing touched it")
    if not out.success:
        return Tried(False, out.error, "did not end on the location")
    return Tried(True, out.error)


def rates(scene: Scene, planner: Planner, chosen: Iterable[Subject], trials: int, *,
          randomization: Randomization | None = None, seed: int = 0,
          placement: Mapping[str, str] | None = None,
          progress: Callable[[], None] | None = None) -> list[Rate]:
    """Each subject tried `trials` times, trial `t` with seed `seed + t`;
    the other objects where `placement` puts them (default: the scene's
    initial placement).  `progress` is called after every trial."""
    found = []
    for subject in chosen:
        where = initial_placement(scene) if placement is None else placement
        tried = []
        for t in range(trials):
            if subject.kind == "transfer":
                tried.append(transfer_trial(scene, planner, subject, where, randomization=randomization,
                                            seed=seed + t))
            else:
                tried.append(slide_tried(scene, subject, randomization=randomization, seed=seed + t))
            if progress is not None:
                progress()
        found.append(Rate(subject, tuple(tried)))
    return found

