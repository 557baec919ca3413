"""The game of docs/game-semantics.md §2–§5 as explicit, executable code.

One abstract state at a time: which moves the robot and the human have from
it, what they cost, and which atoms hold in it.  Every solver is checked
against this module; it is written to be read next to the spec.

Names of actions (the spec's, with the object added to `grab` and `drop`
for readability):

- robot: `transit(o,a)`, `grab(o)`, `transfer(l)`, `drop(o,l)`, and in
  scenes with contacts (semantics §4b) `slide(o,a,l')`: the object `o`
  slid by its contact `a` to the location `l'`.  One name for every
  displacement primitive: which primitive (push, pull, ...) carries it out
  is the contact's, physical detail the game does not read, and a name the
  game chose cannot collide with a plugin's;
- human: `move(o,t)` (a pass is not a move and is not listed here).

A name is what strategy files, run records and scripts hold; what a move
does -- its object, grasp, location, mode and anchors -- is a `Move`, which
`legal_robot_moves` and `legal_human_moves` list for a state.  Whoever
holds a name and a state (the simulator, a strategy read from a file) finds
the move by its name among those, rather than reading the name apart.

Costs are the spec's, in costmap units; `quantize` turns one into the
integer units the solvers add up.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from decimal import Decimal
from fractions import Fraction
from typing import NamedTuple

from symsynth.errors import InputError
from symsynth.scene.propositions import Proposition
from symsynth.scene.costmap import Costmap, Rule
from symsynth.scene.model import ELSE, EMPTY, HAND, Scene

EndEffector = str | tuple[str, str]  # ELSE, a location, or (object, grasp or contact)

@dataclass(frozen=True)
class State:
    """An abstract state `v = (at, grip, ee)` (semantics §2).

    `at[i]` is where `scene.objects[i]` is: a location, `ELSE` or `HAND`;
    `grip` is the grasp holding the object in the hand, None when empty;
    `ee` is `ELSE`, a location (holding) or `(object, grasp or contact)`
    (empty hand).
    """

    at: tuple[str, ...]
    grip: str | None
    ee: EndEffector

    def held(self) -> int | None:
        """Index of the object in the hand, None when the hand is empty."""
        return self.at.index(HAND) if HAND in self.at else None


def state_json(v: State, objects: tuple[str, ...]) -> dict[str, object]:
    """`{"at": {object: place}, "grip": g or None, "ee": place or [o, g]}`."""
    return {"at": dict(zip(objects, v.at)), "grip": v.grip,
            "ee": list(v.ee) if isinstance(v.ee, tuple) else v.ee}


def state_problems(scene: Scene, v: State) -> list[str]:
    """Why `v` is not a well-formed state of `scene` (semantics §2), empty
    when it is one: for states that come from outside (a file)."""
    names, places = scene.object_names, set(scene.locations) | {ELSE, HAND}
    problems = [f"{o} is at {p!r}, which is no location, Else or Hand"
                for o, p in zip(names, v.at) if p not in places]
    for place in [*scene.locations, HAND]:
        there = [o for o, p in zip(names, v.at) if p == place]
        if len(there) > 1:
            problems.append(f"{' and '.join(there)} are both at {place}")
    held = [o for o, p in zip(names, v.at) if p == HAND]
    if held and v.grip is None:
        problems.append(f"{held[0]} is in the hand but grip is none")
    elif not held and v.grip is not None:
        problems.append(f"grip is {v.grip!r} but the hand is empty")
    elif v.grip is not None and v.grip not in scene.grasps:
        problems.append(f"grip {v.grip!r} is not a grasp of the scene ({', '.join(scene.grasps)})")
    if held and v.ee != ELSE and v.ee not in scene.locations:
        problems.append(f"holding {held[0]}, ee must be Else or a location, not {v.ee!r}")
    if not held and v.ee != ELSE:
        if not (isinstance(v.ee, tuple) and len(v.ee) == 2 and v.ee[0] in names
                and v.ee[1] in scene.preimages):
            problems.append(f"with the hand empty, ee must be Else or [object, grasp or contact], "
                            f"not {v.ee!r}")
    return problems


def initial_state(scene: Scene) -> State:
    """Objects where the scene puts them, hand empty, robot at home."""
    return State(tuple(o.at for o in scene.objects), None, ELSE)


def decimal(x: float | Decimal | Fraction) -> Fraction:
    """The number `x` exactly: a float as the decimal it prints as (`repr`),
    so 0.1 is 1/10, not the binary float nearest to it; an int (a cost of
    9007199254740993, past a float's 2^53), a `Decimal` (a budget read from
    the command line) or a `Fraction` as it is.  Costs, resolutions and
    budgets are written as decimals in files and on the command line; read
    this way, `0.3 / 0.1` is exactly 3 and needs no tolerance."""
    if isinstance(x, (int, Decimal, Fraction)):  # (bool is no cost; an int is exact as it is)
        return Fraction(x)
    return Fraction(repr(float(x)))


def in_costmap_units(units: int, resolution: float) -> float:
    """`units` of `resolution` in the costmap's units, exactly: an int when
    it is whole (E_p of integer costs stays an integer however large; a
    float would round 4 x 9007199254740993 down), else the float nearest
    the exact decimal (3 units of 0.1 are 0.3).  A value past the float
    range that is not whole is rounded up to an int: never below E_p."""
    exact = units * decimal(resolution)
    if exact.denominator == 1:
        return exact.numerator
    try:
        return float(exact)
    except OverflowError:
        return math.ceil(exact)


@functools.lru_cache(maxsize=1 << 16)
def quantize(cost: float, resolution: float) -> int:
    """`cost` rounded up to whole units of `resolution`: ceil(c / r), computed
    exactly on the decimals (`decimal`).  Never below the cost: a positive
    cost is at least one unit however coarse `resolution` is (so every
    bound built from units stays sound), and `c` that is a multiple of `r`
    (0.3 of 0.1) is exactly `c / r` units."""
    return math.ceil(decimal(cost) / decimal(resolution))


def within(units: int, resolution: float, budget: float | Decimal) -> bool:
    """Whether `units * resolution <= budget`, exactly on the decimals
    (3 units of 0.1 fit a budget of 0.3; 321 units do not fit 320.9999995)."""
    return units * decimal(resolution) <= decimal(budget)


# -- robot (semantics §4, §5) --------------------------------------------------------

class Move(NamedTuple):
    """One move of the game from a state (semantics §4), with what it does:

    - `kind`: `transit`, `grab`, `transfer`, `drop`, `slide` (the robot's)
      or `move` (the human's); `action`: its name (`action_name`);
    - `obj`, `serves`: the object it reaches, grabs, carries, drops or moves,
      and that object's index in `scene.objects`;
    - `grasp`: the grasp or contact a transit reaches, the grasp a grab
      closes, the one the held object is held by (transfer, drop), the
      contact a slide pushes with; None for a human move;
    - `location`: where the object is then: the location a transfer carries
      it to, a drop sets it down on or a slide moves it to, the target of a
      human move (a location or `ELSE`); for a transit or grab, where it
      stands (`at[o]`);
    - `mode`, `starts`, `goals`: a transit's or transfer's mode and anchors
      (semantics §5: it moves in `mode` from one of `starts` to one of
      `goals`); None and () for the others;
    - `after`: the state it leads to;
    - `cost`: a robot move's cost in costmap units (semantics §5; inf: not
      available); None for a human move.

    (A named tuple rather than a frozen dataclass: the explicit solver makes
    one per edge of the game, and a named tuple is made several times
    faster.)
    """

    kind: str
    action: str
    obj: str
    serves: int
    grasp: str | None
    location: str
    after: State
    mode: str | None = None
    starts: tuple[str, ...] = ()
    goals: tuple[str, ...] = ()
    cost: float | None = None


def action_name(kind: str, *args: str) -> str:
    """The name of an action: `kind(a1,...,an)`, e.g. `transit(w1,top)`."""
    return f"{kind}({','.join(args)})"


def robot_action_names(scene: Scene) -> frozenset[str]:
    """The name of every robot action of `scene`, available or not, in any
    state."""
    objects, locations = scene.object_names, scene.locations
    return frozenset([action_name("transit", o, a) for o in objects for a in scene.preimages]
                     + [action_name("grab", o) for o in objects]
                     + [action_name("transfer", l) for l in locations]
                     + [action_name("drop", o, l) for o in objects for l in locations]
                     + [action_name("slide", o, a, l) for o in objects for a in scene.contacts
                        for l in locations])


def motions(scene: Scene, v: State) -> list[Move]:
    """The transits (hand empty) or transfers (holding) semantics §4 allows from
    `v`, with their cost: inf for those no costmap rule makes available."""
    names = scene.object_names
    held = v.held()
    S = starts(scene, v)
    moves = []
    if held is None:
        for i, o in enumerate(names):
            if v.at[i] == HAND:
                continue
            for g in scene.preimages:
                if v.ee != (o, g):
                    T = anchors(scene, v.at[i], g)
                    moves.append(Move("transit", action_name("transit", o, g), o, i, g, v.at[i],
                                      State(v.at, None, (o, g)), EMPTY, S, T, _motion(scene, v, EMPTY, S, T, i)))
        return moves
    o, grip = names[held], v.grip
    if grip is None:  # holding: the grip is the grasp (semantics §2)
        raise ValueError(f"a state holding {o} without a grasp: {v}")
    mode = f"{o}/{grip}"
    for l in scene.locations:
        if l not in v.at and v.ee != l:
            T = anchors(scene, l, grip)
            moves.append(Move("transfer", action_name("transfer", l), o, held, grip, l, State(v.at, grip, l),
                              mode, S, T, _motion(scene, v, mode, S, T, held)))
    return moves


def legal_robot_moves(scene: Scene, v: State) -> list[Move]:
    """Every available robot move from `v`, with its cost.

    Moves of infinite cost are not available and are left out.
    """
    moves = motions(scene, v)
    held = v.held()
    if held is None and isinstance(v.ee, tuple) and v.ee[1] in scene.grasps:
        o, g = v.ee
        i = scene.object_names.index(o)
        moves.append(Move("grab", action_name("grab", o), o, i, g, v.at[i],
                          State(_replace(v.at, i, HAND), g, v.at[i]), cost=scene.grab_cost))
    elif held is None and isinstance(v.ee, tuple):
        moves += slides(scene, v)
    elif held is not None and isinstance(v.ee, str) and v.grip is not None and v.ee in scene.locations \
            and v.ee not in v.at:  # (holding: ee is a place and grip a grasp, semantics §2)
        o = scene.object_names[held]
        at = _replace(v.at, held, v.ee)
        moves.append(Move("drop", action_name("drop", o, v.ee), o, held, v.grip, v.ee,
                          State(at, None, (o, v.grip)), cost=scene.drop_cost))
    return [m for m in moves if m.cost != math.inf]



def after_robot_action(scene: Scene, v: State, action: str) -> State:
    """The state the robot's `action` (by name) produces from `v`; it must be legal there."""
    found = [mv.after for mv in legal_robot_moves(scene, v) if mv.action == action]
    if not found:
        raise ValueError(f"internal error: {action!r} is not a legal robot move here")
    return found[0]


def slides(scene: Scene, v: State) -> list[Move]:
    """`slide(o,a,l')` from `v` (semantics §4b): the hand at contact `a` of
    `o`, which stands at a location `l`; one move per other free location,
    with its cost (inf where no slide rule is satisfied)."""
    if not isinstance(v.ee, tuple):  # the hand is at no object
        return []
    o, a = v.ee
    i = scene.object_names.index(o)
    start = v.at[i]
    if start not in scene.locations:
        return []  # an object at Else is grabbed, not slid
    costmap, free = costmap_of(scene), _free_for(scene, v, i)
    return [Move("slide", action_name("slide", o, a, l), o, i, a, l, State(_replace(v.at, i, l), None, v.ee),
                 cost=slide_cost(costmap, a, start, l, free))
            for l in scene.locations if l not in v.at]


def slide_rule(scene: Scene, v: State, move: Move) -> Rule | None:
    """The slide rule that gives a slide from `v` its cost (the least-cost
    satisfied one, whose evidence path the simulator follows); None when
    none is satisfied."""
    if move.grasp is None:  # a slide names its contact
        return None
    start = v.at[move.serves]
    satisfied = [r for r in costmap_of(scene).slide_rules(move.grasp, start, move.location)
                 if r.free <= _free_for(scene, v, move.serves)]
    return min(satisfied, key=lambda r: r.cost, default=None)


def motion_rule(scene: Scene, v: State, move: Move, start: str, goal: str) -> Rule | None:
    """The rule that gives a transit or transfer from `v` between anchors
    `start` and `goal` its cost (the least-cost satisfied one); None when
    none is satisfied."""
    if move.mode is None:
        return None
    free = _free_for(scene, v, move.serves)
    satisfied = [r for r in costmap_of(scene).rules(move.mode, start, goal) if r.free <= free]
    return min(satisfied, key=lambda r: r.cost, default=None)


def slide_cost(costmap: Costmap, contact: str, start: str, goal: str, free: frozenset[str]) -> float:
    """`slide(a, l, l', v, o)` when the places that count as free are `free`:
    the least cost of a satisfied slide rule, inf when none is."""
    return min((r.cost for r in costmap.slide_rules(contact, start, goal) if r.free <= free), default=math.inf)


def robot_moves(scene: Scene, v: State) -> list[tuple[str, State, float]]:
    """Every available robot action from `v` as (action, next state, cost):
    `legal_robot_moves` by name."""
    return [(m.action, m.after, m.cost) for m in legal_robot_moves(scene, v) if m.cost is not None]  # all have one


def anchors(scene: Scene, place: str, grasp: str) -> tuple[str, ...]:
    """`anchors(l, g) = {l/g}`; `anchors(Else, g) = {e/g : e in E}`."""
    if place == ELSE:
        return tuple(f"{e}/{grasp}" for e in scene.else_samples)
    return (f"{place}/{grasp}",)


def starts(scene: Scene, v: State) -> tuple[str, ...]:
    """The robot configurations `v` may stand for (semantics §5).  With the
    hand empty at Else: home and every anchor but the absent ones (the
    **choice** of semantics §5: every robot action ends at an anchor that
    exists, so the robot can never have stood at an absent one)."""
    if v.grip is not None and isinstance(v.ee, str):  # holding: ee is a place
        return anchors(scene, v.ee, v.grip)
    if isinstance(v.ee, tuple):
        o, g = v.ee
        return anchors(scene, v.at[scene.object_names.index(o)], g)
    return scene.present_anchors  # home and every x/a that exists: wherever the robot has been


def _motion(scene: Scene, v: State, mode: str, S: tuple[str, ...], T: tuple[str, ...],
            serves: int) -> float:
    """max over s in S, t in T of cost(mode, s, t, v, o); inf when S or T is empty."""
    return motion_cost(costmap_of(scene), mode, S, T, _free_for(scene, v, serves))


def motion_cost(costmap: Costmap, mode: str, S: tuple[str, ...], T: tuple[str, ...],
                free: frozenset[str]) -> float:
    """`motion(mode, S, T, o)` when the places that count as free are `free`:
    max over s in S, t in T of `_cost`; inf when S or T is empty."""
    if not S or not T:
        return math.inf
    return max(_cost(costmap, mode, s, t, free) for s in S for t in T)


def _cost(costmap: Costmap, mode: str, s: str, t: str, free: frozenset[str]) -> float:
    """The least cost of a satisfied rule; 0 if s = t; inf if none is satisfied."""
    if s == t:
        return 0.0
    return min((r.cost for r in costmap.rules(mode, s, t) if r.free <= free), default=math.inf)


def _free_for(scene: Scene, v: State, serves: int) -> frozenset[str]:
    """The places of L ∪ E that count as free for a motion serving object `serves`:
    a location holding no other object; every Else sample when no other object
    is at Else."""
    others = [a for i, a in enumerate(v.at) if i != serves]
    free = {l for l in scene.locations if l not in others}
    if ELSE not in others:
        free.update(scene.else_samples)
    return frozenset(free)


def costmap_of(scene: Scene) -> Costmap:
    """The scene's costmap; a scene without one is an input error."""
    if scene.costmap is None:
        where = f"{scene.source}: " if scene.source is not None else ""
        raise InputError(f"{where}scene {scene.name!r} has no costmap: give one (costmap: FILE, or "
                         "--costmap FILE) or, for a physical scene, compute it with a planner")
    return scene.costmap


# -- human (semantics §4) ------------------------------------------------------------

def legal_human_moves(scene: Scene, v: State) -> list[Move]:
    """Every human move from `v`; passing is not one."""
    moves = []
    aligned = v.ee if v.grip is not None else None  # a held object's place
    for i, o in enumerate(scene.object_names):
        if v.at[i] == HAND:
            continue
        for t in scene.locations + (ELSE,):
            if t != ELSE and (t in v.at or t == aligned):
                continue  # also excludes t = at[o]
            ee = ELSE if isinstance(v.ee, tuple) and v.ee[0] == o else v.ee
            moves.append(Move("move", action_name("move", o, t), o, i, None, t,
                              State(_replace(v.at, i, t), v.grip, ee)))
    return moves


def human_moves(scene: Scene, v: State) -> list[tuple[str, State]]:
    """Every human move from `v` as (action, next state): `legal_human_moves`
    by name."""
    return [(m.action, m.after) for m in legal_human_moves(scene, v)]


# -- propositions (semantics §3) -----------------------------------------------------

def letter(scene: Scene, props: Mapping[str, Proposition], v: State) -> frozenset[str]:
    """The keys of the atoms that hold in `v`."""
    true = set()
    for key, p in props.items():
        if p.kind == "at":
            holds = p.location in _places(scene, v, p.tag)
        elif p.kind == "holding":
            holds = HAND in _places(scene, v, p.tag)
        elif p.kind == "occupied":
            holds = p.location in v.at
        else:  # free
            holds = p.location not in v.at
        if holds:
            true.add(key)
    return frozenset(true)


def _places(scene: Scene, v: State, tag: str | None) -> set[str]:
    """Where the objects tagged `tag` are."""
    return {a for spec, a in zip(scene.objects, v.at) if tag in spec.tags}


def _replace(at: tuple[str, ...], i: int, value: str) -> tuple[str, ...]:
    return at[:i] + (value,) + at[i + 1:]
