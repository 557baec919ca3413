"""The abstract state of semantics §2 as bit-vectors, and its predicates.

Variables, in the order they are declared (the order matters for BDD size):
`grip` over G + [none], `ee` over [Else] + L + O x (G + P), then for each object
`o`: `at.o` over L + [Else, Hand] (each object's bits together, every bit
next to its primed copy).  The game (`solvers.bdd.arena`) declares the human's
counter and the DFA above them and the cost and budget bits below.

Every set built here is conjoined with the range invariants of the
variables it mentions, so unused bit patterns never count as states.
"""

from __future__ import annotations

from dataclasses import dataclass

from symsynth.automata.bdd import BDD, Function
from symsynth.game.abstraction import EndEffector, State
from symsynth.scene.propositions import Proposition
from symsynth.scene.model import ELSE, HAND, Scene
from symsynth.solvers.bdd.bitvec import Domain


@dataclass
class StateEncoding:
    """Domains of one scene's abstract state, with value <-> code tables."""

    bdd: BDD
    scene: Scene
    at: dict[str, Domain]
    grip: Domain
    ee: Domain
    at_values: tuple[str, ...]            # L + (Else, Hand)
    grip_values: tuple[str | None, ...]   # G + (None,)
    ee_values: tuple[EndEffector, ...]    # (Else,) + L + ((o, a), ...), a in G + P

    @classmethod
    def declare(cls, bdd: BDD, scene: Scene) -> StateEncoding:
        grip_values = scene.grasps + (None,)
        grip = Domain.declare(bdd, "#grip", len(grip_values))
        ee_values: tuple[EndEffector, ...] = ((ELSE,) + scene.locations
                                              + tuple((o, a) for o in scene.object_names for a in scene.preimages))
        ee = Domain.declare(bdd, "#ee", len(ee_values))
        at_values = scene.locations + (ELSE, HAND)
        at = {o: Domain.declare(bdd, f"#at.{o}", len(at_values)) for o in scene.object_names}
        return cls(bdd, scene, at, grip, ee, at_values, grip_values, ee_values)

    @property
    def domains(self) -> list[Domain]:
        return [self.grip, self.ee] + list(self.at.values())

    # -- atomic predicates ---------------------------------------------------
    def at_is(self, obj: str, where: str, primed: bool = False) -> Function:
        """at[obj] = where (a location, Else or Hand)."""
        return self.at[obj].eq(self.bdd, self.at_values.index(where), primed)

    def grip_is(self, grasp: str | None, primed: bool = False) -> Function:
        return self.grip.eq(self.bdd, self.grip_values.index(grasp), primed)

    def ee_is(self, value: object, primed: bool = False) -> Function:
        return self.ee.eq(self.bdd, self.ee_values.index(value), primed)

    def occupied(self, location: str, primed: bool = False) -> Function:
        """Some object stands at `location`."""
        result = self.bdd.false
        for o in self.scene.object_names:
            result |= self.at_is(o, location, primed)
        return result

    def holding(self, primed: bool = False) -> Function:
        return ~self.grip_is(None, primed)

    def proposition(self, prop: Proposition, primed: bool = False) -> Function:
        """The set of states where a task proposition (semantics §3) holds."""
        bdd = self.bdd
        where = prop.place
        if prop.kind == "occupied":
            return self.occupied(where, primed)
        if prop.kind == "free":
            return ~self.occupied(where, primed)
        result = bdd.false
        for o in self.scene.tagged(prop.named_tag):
            result |= self.at_is(o, where, primed)
        return result

    # -- invariants ------------------------------------------------------------
    def well_formed(self, primed: bool = False) -> Function:
        """Range invariants and the well-formedness rules of semantics §2."""
        bdd, scene = self.bdd, self.scene
        result = bdd.true
        for dom in self.domains:
            result &= dom.invariant(bdd, primed)
        objects = scene.object_names
        for i, o in enumerate(objects):
            for p in objects[i + 1:]:
                # at most one object per location, at most one in the hand
                for where in scene.locations + (HAND,):
                    result &= ~(self.at_is(o, where, primed) & self.at_is(p, where, primed))
        in_hand = bdd.false
        for o in objects:
            in_hand |= self.at_is(o, HAND, primed)
        # grip = none  <->  the hand is empty
        result &= bdd.apply("<=>", self.grip_is(None, primed), ~in_hand)
        # holding => ee in L + {Else}
        holding_ok = self.ee_is(ELSE, primed)
        for loc in scene.locations:
            holding_ok |= self.ee_is(loc, primed)
        result &= ~in_hand | holding_ok
        # empty hand => ee in {Else} + O x (G + P)   (ee = (o, a) with at[o] != Hand
        # then holds by itself: nothing is in the hand)
        at_location = bdd.false
        for loc in scene.locations:
            at_location |= self.ee_is(loc, primed)
        result &= in_hand | ~at_location
        return result

    def state(self, at: dict[str, str], grip: str | None, ee: object,
              primed: bool = False) -> Function:
        """The cube of one abstract state."""
        result = self.grip_is(grip, primed) & self.ee_is(ee, primed)
        for o, where in at.items():
            result &= self.at_is(o, where, primed)
        return result

    def encode(self, v: State, primed: bool = False) -> Function:
        """The cube of an explicit `State` (objects in scene order)."""
        return self.state(dict(zip(self.scene.object_names, v.at)), v.grip, v.ee, primed)

    def assignment(self, v: State, primed: bool = False) -> dict[str, bool]:
        """The bit values of an explicit `State`, for `let`."""
        values = (self.grip.assignment(self.grip_values.index(v.grip), primed)
                  | self.ee.assignment(self.ee_values.index(v.ee), primed))
        for o, where in zip(self.scene.object_names, v.at):
            values |= self.at[o].assignment(self.at_values.index(where), primed)
        return values

    def decode(self, assignment: dict[str, bool], primed: bool = False) -> State:
        """The explicit `State` of a satisfying assignment."""
        at = tuple(self.at_values[self.at[o].decode(assignment, primed)]
                   for o in self.scene.object_names)
        return State(at, self.grip_values[self.grip.decode(assignment, primed)],
                     self.ee_values[self.ee.decode(assignment, primed)])

    def bits(self, primed: bool = False) -> list[str]:
        """Every bit of the state (primed copies when `primed`)."""
        return [b for dom in self.domains for b in (dom.primed if primed else dom.bits)]

    def initial(self) -> Function:
        """Spec §2: objects where the scene puts them, hand empty, ee = Else."""
        return self.state({o.name: o.at for o in self.scene.objects}, None, ELSE)
