"""The scene as the game sees it (semantics §1): plain, frozen values.

`Scene` is the abstract form of semantics §7; the physical form (robot, poses,
shapes) extends it with geometry that only the planners read.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

from symsynth.errors import InputError
from symsynth.logic import ast
from symsynth.scene.costmap import Costmap
from symsynth.scene.geometry import Geometry

ELSE = "Else"
HAND = "Hand"
HOME = "home"
EMPTY = "empty"


@dataclass(frozen=True)
class ObjectSpec:
    """A movable object; its own name is always one of its tags."""

    name: str
    tags: frozenset[str]
    at: str  # a location of interest or ELSE


@dataclass(frozen=True)
class Scene:
    name: str
    objects: tuple[ObjectSpec, ...]
    locations: tuple[str, ...]
    else_samples: tuple[str, ...]
    grasps: tuple[str, ...]
    #: Contacts (semantics §1, v2): pre-images of displacement primitives,
    #: disjoint from the grasps; a scene without them is a v1 scene.
    contacts: tuple[str, ...] = ()
    grab_cost: float = 5.0
    drop_cost: float = 5.0
    k: int = 0
    task: str | None = None
    #: The human model of `human: {model: ...}` as written (semantics §9), e.g.
    #: "random(0.3)"; `game.human_model.parse_model` reads it.  None: no model.
    human_model: str | None = None
    #: `file:line: human.model`, for messages about the model's arguments
    human_model_where: str = field(default="human.model", compare=False)
    costmap: Costmap | None = None
    #: Classes of interchangeable objects the scene declares (`interchangeable:`),
    #: None to let the solvers find them (game/symmetry.py checks a declaration).
    declared_classes: tuple[tuple[str, ...], ...] | None = None
    #: `file:line: interchangeable.i` of each declared class, for messages
    declared_where: tuple[str, ...] = field(default=(), compare=False)
    source: Path | None = field(default=None, compare=False)
    geometry: Geometry | None = field(default=None, compare=False)  # physical scenes only
    #: The task as the loader parsed it, (text, formula): `game.solution.task_formula`
    #: reads the formula from here while `task` is that text (a task is parsed once).
    parsed: tuple[str, ast.Formula] | None = field(default=None, compare=False, repr=False)

    @property
    def object_names(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.objects)

    @property
    def tags(self) -> frozenset[str]:
        return frozenset(t for o in self.objects for t in o.tags)

    def tagged(self, tag: str) -> tuple[str, ...]:
        """Names of the objects that carry `tag`."""
        return tuple(o.name for o in self.objects if tag in o.tags)

    @property
    def preimages(self) -> tuple[str, ...]:
        """G ∪ P: what the end-effector can be aimed at on an object (a
        grasp to close, a contact to slide from)."""
        return self.grasps + self.contacts

    def without_contacts(self) -> Scene:
        """The scene with no contacts (a v1 scene): no contact anchors, no
        motions to or from them in its costmap, no slides; physical contacts
        and their primitives' costs gone too.  For comparing a scene with
        and without its displacement primitives."""
        if not self.contacts:
            return self
        contacts = set(self.contacts)

        def aimed(anchor: str) -> bool:
            return anchor.rsplit("/", 1)[-1] in contacts

        costmap = None if self.costmap is None else replace(self.costmap, slides={}, motions={
            key: rules for key, rules in self.costmap.motions.items() if not (aimed(key[1]) or aimed(key[2]))},
            absent=frozenset(a for a in self.costmap.absent if not aimed(a)))
        geometry = None if self.geometry is None else replace(self.geometry, contacts={}, primitive_costs={})
        return replace(self, contacts=(), costmap=costmap, geometry=geometry)

    @property
    def modes(self) -> tuple[str, ...]:
        """`empty` and `o/g` for every object and grasp (semantics §5)."""
        return (EMPTY,) + tuple(f"{o.name}/{g}" for o in self.objects for g in self.grasps)

    @property
    def anchors(self) -> tuple[str, ...]:
        """`home` and `x/a` for x in L ∪ E and a in G ∪ P (semantics §5),
        absent ones included (`present_anchors` leaves them out)."""
        places = self.locations + self.else_samples
        return (HOME,) + tuple(f"{x}/{a}" for x in places for a in self.preimages)

    @property
    def present_anchors(self) -> tuple[str, ...]:
        """`anchors` but those the costmap lists as absent (no robot
        configuration: semantics §5's **choice**), in the same order: where
        the robot may have been."""
        absent = frozenset() if self.costmap is None else self.costmap.absent
        return tuple(a for a in self.anchors if a not in absent)


def geometry_of(scene: Scene) -> Geometry:
    """The scene's geometry; an abstract scene (no 'robot' key) is an input error."""
    if scene.geometry is None:
        raise InputError(f"scene {scene.name!r} is abstract (no 'robot' key): it has no geometry")
    return scene.geometry
