"""The game on classes of interchangeable objects (`game.symmetry`): which
class stands on each location, instead of where each object is.

The objects fall into *kinds*: each class of interchangeable objects is one
kind, every other object a kind of its own.  A state of the game modulo the
renamings within classes (an *orbit*) is

- `loc.l`, for each location `l`: the kind standing on `l`, or nothing;
- `hand`: the kind in the hand, or nothing, and `grip` as before;
- `ee`: `Else`, a location `l` (holding, above `l`), `(l, a)` (hand empty,
  at grasp or contact `a` of the object standing on `l`), or
  `(Else, c, a)` (hand empty, at `a` of an object of kind `c` at Else).

How many objects of a kind are at Else is not stored: it is the kind's size
less those on locations and in the hand (`else_count`).  Two real states
have the same code iff a renaming within classes maps one to the other, so
the codes are the orbits (`tests/test_symbolic_classes.py` counts them).

The relations are semantics §4's moves between orbits: from the code of `v`,
the code of every `w` a real move leads to, with the move's cost.  Moves that
stay within an orbit are real moves too (a transit from one white block at
Else to another, the human moving one of them within Else): they add a letter
to the trace and are kept.  A motion's cost reads where the object it
serves stands (`free_for`): the free places of semantics §5 are those no
*other* object stands on, which depends on that place only.

The task's atoms read the codes directly: `at(X, l)` is `loc.l` in the
kinds tagged `X` (a class's members carry the same tags the task reads),
`at(X, Else)` a kind tagged `X` with an object at Else.

Variables, top to bottom: h | DFA | grip | hand | loc.l1 ... loc.lm | ee |
c e.  With `ee` below the locations (unlike the per-object encoding, where
it must come first to name the object before its bits) and the robot's
families joined into one relation, the sorting family (bench/gamefamily.py,
2 colours, k = 3) took 20.6 CPU s at 6 x 8 against 29.5 s with `ee` above
and one relation per family (5 x 7: 2.5 s against 4.2 s).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

from symsynth.automata.bdd import BDD, Function
from symsynth.game.abstraction import State, anchors
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND, HOME, Scene
from symsynth.scene.propositions import Proposition
from symsynth.solvers.bdd.arena import Arena
from symsynth.solvers.bdd.bitvec import Domain

#: `free_for`'s second argument: where the object a motion serves stands
#: (a location, `ELSE`, or `HAND`).
Served = str


def kinds_of(scene: Scene, classes: Sequence[Sequence[int]]) -> tuple[tuple[int, ...], ...]:
    """Every object's kind: the classes, and each other object alone, in the
    order of their first members."""
    grouped = {i for c in classes for i in c}
    kinds = [tuple(c) for c in classes] + [(i,) for i in range(len(scene.objects)) if i not in grouped]
    return tuple(sorted(kinds))


def at_most(bdd: BDD, preds: Sequence[Function], n: int) -> Function:
    """At most `n` of `preds` hold (false for n < 0)."""
    if n < 0:
        return bdd.false
    # count[j]: exactly j of the predicates seen so far hold, j = 0..n
    count = [bdd.true] + [bdd.false] * n
    for p in preds:
        count = [(~p & count[0])] + [(~p & count[j]) | (p & count[j - 1]) for j in range(1, n + 1)]
    result = bdd.false
    for u in count:
        result |= u
    return result


@dataclass
class ClassEncoding:
    """Domains of the class encoding (module doc), with the map from real states."""

    bdd: BDD
    scene: Scene
    kinds: tuple[tuple[int, ...], ...]
    loc: dict[str, Domain]
    hand: Domain
    grip: Domain
    ee: Domain
    grip_values: tuple[str | None, ...]   # G + (None,)
    ee_values: tuple[object, ...]         # (Else,) + L + ((l, a), ...) + ((Else, c, a), ...)

    @classmethod
    def declare(cls, bdd: BDD, scene: Scene, kinds: tuple[tuple[int, ...], ...]) -> ClassEncoding:
        grip_values = scene.grasps + (None,)
        grip = Domain.declare(bdd, "#grip", len(grip_values))
        hand = Domain.declare(bdd, "#hand", len(kinds) + 1)  # 0: empty, c + 1: kind c
        loc = {l: Domain.declare(bdd, f"#loc.{l}", len(kinds) + 1) for l in scene.locations}
        ee_values = ((ELSE,) + scene.locations
                     + tuple((l, a) for l in scene.locations for a in scene.preimages)
                     + tuple((ELSE, c, a) for c in range(len(kinds)) for a in scene.preimages))
        ee = Domain.declare(bdd, "#ee", len(ee_values))
        return cls(bdd, scene, kinds, loc, hand, grip, ee, grip_values, ee_values)

    @property
    def domains(self) -> list[Domain]:
        return [self.grip, self.hand] + list(self.loc.values()) + [self.ee]

    # -- atomic predicates ---------------------------------------------------
    def loc_is(self, location: str, kind: int | None, primed: bool = False) -> Function:
        """loc[location] = kind (None: nothing stands there)."""
        return self.loc[location].eq(self.bdd, 0 if kind is None else kind + 1, primed)

    def hand_is(self, kind: int | None, primed: bool = False) -> Function:
        return self.hand.eq(self.bdd, 0 if kind is None else kind + 1, primed)

    def grip_is(self, grasp: str | None, primed: bool = False) -> Function:
        return self.grip.eq(self.bdd, self.grip_values.index(grasp), primed)

    def ee_is(self, value: object, primed: bool = False) -> Function:
        return self.ee.eq(self.bdd, self.ee_values.index(value), primed)

    def occupied(self, location: str, primed: bool = False) -> Function:
        return ~self.loc_is(location, None, primed)

    def holding(self, primed: bool = False) -> Function:
        return ~self.grip_is(None, primed)

    def _placed(self, kind: int, primed: bool) -> list[Function]:
        """One predicate per place an object of `kind` can take other than Else."""
        return ([self.loc_is(l, kind, primed) for l in self.scene.locations]
                + [self.hand_is(kind, primed)])

    def else_count_at_least(self, kind: int, n: int, primed: bool = False) -> Function:
        """At least n objects of `kind` at Else: at most |kind| - n elsewhere."""
        return at_most(self.bdd, self._placed(kind, primed), len(self.kinds[kind]) - n)

    def else_total_at_most(self, n: int, primed: bool = False) -> Function:
        """At most n objects at Else, of any kind: at least (objects - n)
        on locations or in the hand."""
        placed = [self.occupied(l, primed) for l in self.scene.locations] + [self.holding(primed)]
        return ~at_most(self.bdd, placed, len(self.scene.objects) - n - 1)

    def _tagged(self, tag: str) -> list[int]:
        return [c for c, members in enumerate(self.kinds)
                if tag in self.scene.objects[members[0]].tags]

    def proposition(self, prop: Proposition, primed: bool = False) -> Function:
        """The orbits where a task proposition (semantics §3) holds."""
        bdd = self.bdd
        where = prop.place
        if prop.kind == "occupied":
            return self.occupied(where, primed)
        if prop.kind == "free":
            return ~self.occupied(where, primed)
        result = bdd.false
        for c in self._tagged(prop.named_tag):
            if prop.kind == "holding":
                result |= self.hand_is(c, primed)
            elif where == ELSE:
                result |= self.else_count_at_least(c, 1, primed)
            else:
                result |= self.loc_is(where, c, primed)
        return result

    # -- invariants ------------------------------------------------------------
    def well_formed(self, primed: bool = False) -> Function:
        """Range invariants, and the codes of semantics §2's well-formed states."""
        bdd, scene = self.bdd, self.scene
        result = bdd.true
        for dom in self.domains:
            result &= dom.invariant(bdd, primed)
        for c, members in enumerate(self.kinds):
            # no more objects of a kind on locations and in the hand than it has
            result &= at_most(bdd, self._placed(c, primed), len(members))
        # grip = none  <->  the hand is empty
        result &= bdd.apply("<=>", self.grip_is(None, primed), self.hand_is(None, primed))
        above = bdd.false
        for l in scene.locations:
            above |= self.ee_is(l, primed)
        # holding => ee in {Else} + L; empty hand => ee not in L
        holding = self.holding(primed)
        result &= (holding & (self.ee_is(ELSE, primed) | above)) | (~holding & ~above)
        for l in scene.locations:
            for a in scene.preimages:
                # ee = (l, a) => an object stands on l
                result &= ~self.ee_is((l, a), primed) | self.occupied(l, primed)
        for c in range(len(self.kinds)):
            aimed = bdd.false
            for a in scene.preimages:
                aimed |= self.ee_is((ELSE, c, a), primed)
            # ee = (Else, c, a) => an object of kind c at Else
            result &= ~aimed | self.else_count_at_least(c, 1, primed)
        return result

    # -- real states ------------------------------------------------------------
    @functools.cached_property
    def kind_of(self) -> dict[int, int]:
        """Object index -> its kind."""
        return {i: c for c, members in enumerate(self.kinds) for i in members}

    def code(self, v: State) -> tuple[dict[str, int], int, int, int]:
        """The orbit of a real state: (loc values, hand value, grip index, ee index)."""
        kind = self.kind_of
        names = self.scene.object_names
        loc = dict.fromkeys(self.scene.locations, 0)
        hand = 0
        for i, where in enumerate(v.at):
            if where == HAND:
                hand = kind[i] + 1
            elif where != ELSE:
                loc[where] = kind[i] + 1
        ee: str | tuple = v.ee
        if isinstance(v.ee, tuple):
            o, a = v.ee
            i = names.index(o)
            ee = (ELSE, kind[i], a) if v.at[i] == ELSE else (v.at[i], a)
        return loc, hand, self.grip_values.index(v.grip), self.ee_values.index(ee)

    def assignment(self, v: State, primed: bool = False) -> dict[str, bool]:
        """The bit values of the orbit of a real `State`, for `let`."""
        loc, hand, grip, ee = self.code(v)
        values = (self.grip.assignment(grip, primed) | self.hand.assignment(hand, primed)
                  | self.ee.assignment(ee, primed))
        for l, value in loc.items():
            values |= self.loc[l].assignment(value, primed)
        return values

    def encode(self, v: State, primed: bool = False) -> Function:
        """The cube of the orbit of a real `State`."""
        return self.bdd.cube(self.assignment(v, primed))

    def bits(self, primed: bool = False) -> list[str]:
        return [b for dom in self.domains for b in (dom.primed if primed else dom.bits)]


class ClassArena(Arena):
    """`Arena` on the class encoding: the same fixpoint reads it unchanged."""

    # Another encoding behind the interface the fixpoint reads (bits,
    # propositions, well_formed); the per-object relations of `Arena` are
    # all overridden here, so none of them meets a ClassEncoding.
    enc: ClassEncoding  # type: ignore[assignment]

    def __init__(self, scene: Scene, formula: ast.Formula, k: int, resolution: float,
                 classes: Sequence[Sequence[int]]):
        self.kinds = kinds_of(scene, classes)
        super().__init__(scene, formula, k, resolution)

    def _declare_state(self) -> ClassEncoding:  # type: ignore[override]
        return ClassEncoding.declare(self.bdd, self.scene, self.kinds)

    def _robot_relations(self) -> dict[str, Function]:
        robot = {"transit": self._transit(), "grab": self._grab(), "transfer": self._transfer(),
                 "drop": self._drop()}
        if self.scene.contacts:
            robot["slide"] = self._slide()
        merged = self.bdd.false
        for relation in robot.values():
            merged |= relation
        return {"robot": merged}

    # -- costs -------------------------------------------------------------------
    def free_for(self, place: str, served: Served) -> Function:
        """`place` in L ∪ E counts as free for a motion serving an object that
        stands at `served` (a location, Else or the hand): no other object on
        a location; no other object at Else for an Else sample."""
        key = (place, served)
        if key not in self._free:
            enc = self.enc
            if place in self.scene.locations:
                self._free[key] = self.bdd.true if place == served else ~enc.occupied(place)
            else:
                self._free[key] = enc.else_total_at_most(1 if served == ELSE else 0)
        return self._free[key]

    # -- frames ----------------------------------------------------------------------
    def _keep(self, locations=(), grip: bool = False, hand: bool = False, ee: bool = False) -> Function:
        """The named parts of v' equal those of v."""
        bdd, enc = self.bdd, self.enc
        result = bdd.true
        for l in locations:
            result &= enc.loc[l].unchanged(bdd)
        for keep, dom in ((grip, enc.grip), (hand, enc.hand), (ee, enc.ee)):
            if keep:
                result &= dom.unchanged(bdd)
        return result

    def _others(self, *locations: str) -> list[str]:
        return [l for l in self.scene.locations if l not in locations]

    def _copy(self, source: str, target: str | None) -> Function:
        """loc[target]' = loc[source] (hand' when `target` is None), someone standing on `source`."""
        enc = self.enc
        result = self.bdd.false
        for c in range(len(self.kinds)):
            after = enc.hand_is(c, primed=True) if target is None else enc.loc_is(target, c, primed=True)
            result |= enc.loc_is(source, c) & after
        return result

    # -- robot families (semantics §4) ------------------------------------------------
    def _empty_starts(self) -> dict[str, Function]:
        """s -> [s in S(v)] for an empty hand: from ee = Else every anchor
        (and home); from ee = (l, a) the anchor l/a; from ee = (Else, c, a)
        every Else sample's anchor of a."""
        enc, scene = self.enc, self.scene
        anywhere = enc.ee_is(ELSE)
        starts = {HOME: anywhere}
        for a in scene.preimages:
            for l in scene.locations:
                starts[f"{l}/{a}"] = anywhere | enc.ee_is((l, a))
            at_else = anywhere
            for c in range(len(self.kinds)):
                at_else |= enc.ee_is((ELSE, c, a))
            for e in scene.else_samples:
                starts[f"{e}/{a}"] = at_else
        return starts

    def _transit(self) -> Function:
        """transit(o, a): ee' = (l, a) for the object on l, or (Else, c, a)
        for one of kind c at Else; ee != ee' unless another object of kind c
        is at Else (the transit goes from one to the other)."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        starts = self._empty_starts()
        moves = bdd.false
        for a in scene.preimages:
            for l in scene.locations:
                cost = self.motion(EMPTY, starts, {f"{l}/{a}": bdd.true}, l)
                moves |= (enc.occupied(l) & ~enc.ee_is((l, a)) & enc.ee_is((l, a), primed=True) & cost)
            goals = dict.fromkeys(anchors(scene, ELSE, a), bdd.true)
            cost = self.motion(EMPTY, starts, goals, ELSE)
            for c in range(len(self.kinds)):
                target = (ELSE, c, a)
                # another object than the one ee is at, when ee is at one of kind c
                other = ~enc.ee_is(target) | enc.else_count_at_least(c, 2)
                moves |= (enc.else_count_at_least(c, 1) & other
                          & enc.ee_is(target, primed=True) & cost)
        return enc.grip_is(None) & moves & self._keep(scene.locations, grip=True, hand=True)

    def _grab(self) -> Function:
        """grab: ee = (l, g): the kind on l into the hand, ee' = l; ee =
        (Else, c, g): one of kind c into the hand, ee' = Else; grip' = g."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        moves = bdd.false
        for g in scene.grasps:
            for l in scene.locations:
                moves |= (enc.ee_is((l, g)) & self._copy(l, None) & enc.loc_is(l, None, primed=True)
                          & enc.ee_is(l, primed=True) & enc.grip_is(g, primed=True)
                          & self._keep(self._others(l)))
            for c in range(len(self.kinds)):
                moves |= (enc.ee_is((ELSE, c, g)) & enc.hand_is(c, primed=True)
                          & enc.ee_is(ELSE, primed=True) & enc.grip_is(g, primed=True)
                          & self._keep(scene.locations))
        return enc.grip_is(None) & moves & self.at_least(self.units(scene.grab_cost))

    def _transfer(self) -> Function:
        """transfer(l): holding kind c with g, l free, ee != l; ee' = l, in
        mode o/g for a member o of c (they have the same rows)."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        moves = bdd.false
        for c, members in enumerate(self.kinds):
            o = scene.object_names[members[0]]
            for g in scene.grasps:
                starts = {f"{x}/{g}": enc.ee_is(x) for x in scene.locations}
                starts.update({a: enc.ee_is(ELSE) for a in anchors(scene, ELSE, g)})
                holding = enc.hand_is(c) & enc.grip_is(g)
                for l in scene.locations:
                    cost = self.motion(f"{o}/{g}", starts, {f"{l}/{g}": bdd.true}, HAND)
                    moves |= (holding & ~enc.occupied(l) & ~enc.ee_is(l)
                              & enc.ee_is(l, primed=True) & cost)
        return moves & self._keep(scene.locations, grip=True, hand=True)

    def _drop(self) -> Function:
        """drop: holding kind c with g, ee = l free; loc[l]' = c, hand empty, ee' = (l, g)."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        moves = bdd.false
        for c in range(len(self.kinds)):
            for g in scene.grasps:
                for l in scene.locations:
                    moves |= (enc.hand_is(c) & enc.grip_is(g) & enc.ee_is(l) & ~enc.occupied(l)
                              & enc.loc_is(l, c, primed=True) & enc.hand_is(None, primed=True)
                              & enc.grip_is(None, primed=True) & enc.ee_is((l, g), primed=True)
                              & self._keep(self._others(l)))
        return moves & self.at_least(self.units(scene.drop_cost))

    def _slide(self) -> Function:
        """slide: ee = (l, a), a a contact, l' free; loc[l']' = loc[l],
        loc[l]' empty, ee' = (l', a) (semantics §4b)."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        moves = bdd.false
        for a in scene.contacts:
            for l in scene.locations:
                for target in scene.locations:
                    if target == l:
                        continue
                    cost = self.slide_cost(a, l, target, l)
                    if cost == bdd.false:
                        continue
                    moves |= (enc.ee_is((l, a)) & ~enc.occupied(target) & self._copy(l, target)
                              & enc.loc_is(l, None, primed=True) & enc.ee_is((target, a), primed=True)
                              & cost & self._keep(self._others(l, target)))
        return enc.grip_is(None) & moves & self._keep(grip=True, hand=True)

    # -- the human (semantics §4) -----------------------------------------------------
    def _human_relation(self) -> Function:
        """move(o, t) for an object on a location or at Else, t = Else or a
        free location the held object is not above; ee' = Else when ee was
        at the object moved.  From Else, the object may be the one ee is at
        or, if there is one, another of its kind."""
        bdd, enc, scene = self.bdd, self.enc, self.scene
        aligned_ok = {t: ~(enc.holding() & enc.ee_is(t)) for t in scene.locations}
        ee_kept = enc.ee.unchanged(bdd)
        ee_else = enc.ee_is(ELSE, primed=True)
        moves = bdd.false
        for l in scene.locations:  # the object on l
            aimed = bdd.false
            for a in scene.preimages:
                aimed |= enc.ee_is((l, a))
            ee_after = (aimed & ee_else) | (~aimed & ee_kept)
            gone = enc.occupied(l) & enc.loc_is(l, None, primed=True) & ee_after
            moves |= gone & self._keep(self._others(l))  # to Else
            for t in scene.locations:
                if t != l:
                    moves |= (gone & ~enc.occupied(t) & aligned_ok[t] & self._copy(l, t)
                              & self._keep(self._others(l, t)))
        for c in range(len(self.kinds)):  # an object of kind c at Else
            aimed = bdd.false
            for a in scene.preimages:
                aimed |= enc.ee_is((ELSE, c, a))
            ee_after = (aimed & ee_else) | ((~aimed | enc.else_count_at_least(c, 2)) & ee_kept)
            there = enc.else_count_at_least(c, 1) & ee_after
            moves |= there & self._keep(scene.locations)  # within Else
            for t in scene.locations:
                moves |= (there & ~enc.occupied(t) & aligned_ok[t] & enc.loc_is(t, c, primed=True)
                          & self._keep(self._others(t)))
        return moves & self._keep(grip=True, hand=True)
