"""The game of semantics §4–§6 as BDDs: variables, transition relations with cost
bits, and the substitutions that compose the task DFA with the moves.

Variables, top to bottom (each bit next to its primed copy):

    h | DFA state q (and its atoms) | grip | ee | at.o (per object) | c_0 e_0 c_1 e_1 ...

The end-effector above the objects matters: a transit's cost depends on
where the object the hand is at stands, and with `ee` read first a BDD
knows which object that is before it reads the objects.  On the benchmark
family (bench/gamefamily.py) at 4 objects x 6 locations that made the
solver 3x faster; at 8 x 12, building the relations with `ee` last did not
finish in 10 minutes, and takes 6 s with `ee` first.

`c` is an action's cost and `e` the budget left, both in integer units of
the resolution; `e` is declared later (`declare_budget`), when its width is
known, with its bits interleaved with those of `c` so that `c <= e` and
`e - c` stay linear in size.

Robot relations, one per action family, over (v, v', c):

    T_fam(v, v', c) = guard /\\ effect /\\ frame /\\ U(v, c)

where U is *upward closed* in c: it holds for every c at least the action's
cost.  That turns semantics §5 into Boolean structure: the max over anchor pairs
becomes a conjunction and the min over rules a disjunction,

    U(v, c) = /\\_(s,t) [s in S(v) /\\ t in T(v) => \\/_rules (free_o(F)(v) /\\ c >= cost)]

and an action of infinite cost has U = false (it is not available).  The
fixpoint only ever asks "is there a c <= e with X(e - c)?", and X is upward
closed in e, so the least c is what counts.

The relations are not restricted to well-formed states: from a well-formed
state they lead to well-formed ones only, and conjoining the invariant (an
all-different constraint) made the transit relation at 8 x 12 grow from
0.2 to 3.8 million nodes.  The human relation
H(v, v') is semantics §4's `move(o, t)`; it does not mention the counter `h`:
the fixpoint (`solvers.bdd.fixpoint`) solves one value of h at a time, and a
human move leads from layer h to the final layer h - 1.  The DFA reads ρ(v'): its transition function
delta_b(q, x) becomes D_b(q, v') = delta_b(q, x := P_x(v')).
"""

from __future__ import annotations

import os
from collections.abc import Iterable

from symsynth.automata import SymbolicDFA
from symsynth.automata.shared import dfa_into
from symsynth.automata.bdd import Function, new_manager
from symsynth.game.abstraction import anchors, costmap_of, quantize
from symsynth.scene.propositions import interpret_all
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND, HOME, Scene
from symsynth.solvers.bdd.bitvec import Domain, constant, less_equal, less_than, subtract
from symsynth.solvers.bdd.encoding import StateEncoding

#: The robot's action families: v1's four, and `slide` in scenes with
#: contacts (semantics §4b); `Arena.robot` holds those the scene has.
FAMILIES = ("transit", "grab", "transfer", "drop", "slide")


class Arena:
    """One game (scene, task, k, resolution) encoded in one BDD manager."""

    def __init__(self, scene: Scene, formula: ast.Formula, k: int, resolution: float):
        self.scene = scene
        self.k = k
        self.resolution = resolution
        self.costmap = costmap_of(scene)
        self.bdd = bdd = new_manager(reordering=False, memory=_cache_memory())
        self.props = interpret_all(formula, scene)
        self.h = Domain.declare(bdd, "#h", k + 1)
        self.dfa: SymbolicDFA = dfa_into(formula, bdd)  # compiled once per task, not once per game
        self.enc = self._declare_state()
        self.max_units = max(self._all_units(), default=0)
        self.c = Domain.declare(bdd, "#c", self.max_units + 1, primed=False)
        self.e: Domain | None = None
        self._free: dict[tuple[str, str], Function] = {}
        self._at_least: dict[int, Function] = {}

        self.state_bits = self.enc.bits()
        self.next_bits = self.enc.bits(primed=True)
        #: Acc(q): the task is done
        self.accepting = self.dfa.accepting
        # D_b(q, v') = delta_b(q, x := P_x(v'))
        letter_next = {key: self.enc.proposition(p, primed=True) for key, p in self.props.items()}
        self.dfa_next = {b: bdd.let(letter_next, d) if letter_next else d
                         for b, d in self.dfa.delta.items()}
        self.robot = self._robot_relations()
        self.human = self._human_relation()

    # -- the encoding and the relations (`bdd.classes.ClassArena` has its own) ----
    def _declare_state(self) -> StateEncoding:
        return StateEncoding.declare(self.bdd, self.scene)

    def _robot_relations(self) -> dict[str, Function]:
        builders = (_transit, _grab, _transfer, _drop, _slide)
        return {family: build(self) for family, build in zip(FAMILIES, builders)
                if family != "slide" or self.scene.contacts}

    def _human_relation(self) -> Function:
        return _human(self)

    # -- the budget ------------------------------------------------------------
    def declare_budget(self, width: int) -> Domain:
        """Budget bits e_0..e_{width-1}, e_i just below c_i (the rest at the bottom)."""
        bdd = self.bdd
        bits = tuple(f"#e_{i}" for i in range(width))
        for i, b in enumerate(bits):
            if i < len(self.c.bits):
                bdd.insert_var(b, bdd.level_of_var(self.c.bits[i]) + 1)
            else:
                bdd.declare(b)
        self.e = Domain("#e", 1 << width, bits)
        return self.e

    def budget(self) -> Domain:
        """The budget's domain e (`declare_budget` first)."""
        if self.e is None:
            raise ValueError("the arena has no budget bits: declare_budget() first")
        return self.e

    def cost_vector(self) -> list[Function]:
        """c, zero-extended to the width of e."""
        bdd, width = self.bdd, len(self.budget().bits)
        return self.c.vector(bdd) + constant(bdd, 0, width - len(self.c.bits))

    # -- substitutions -----------------------------------------------------------
    def _next_state(self) -> dict[str, Function]:
        """v := v', q := D(q, v'): the state a move leads to, and the DFA reading it."""
        sub = {b: self.bdd.var(p) for b, p in zip(self.state_bits, self.next_bits)}
        sub.update(self.dfa_next)
        return sub

    def robot_substitution(self, with_costs: bool) -> dict[str, Function]:
        """v := v', q := D(q, v'), and with costs e := e - c."""
        bdd = self.bdd
        sub = self._next_state()
        if with_costs:
            e = self.budget()
            sub.update(zip(e.bits, subtract(bdd, e.vector(bdd), self.cost_vector())))
        return sub

    def move_substitution(self) -> dict[str, Function]:
        """v := v', q := D(q, v'): after a human move, within a layer of h."""
        return self._next_state()

    def affordable(self) -> Function:
        """c <= e."""
        return less_equal(self.bdd, self.cost_vector(), self.budget().vector(self.bdd))

    # -- costs ---------------------------------------------------------------------
    def units(self, cost: float) -> int:
        return quantize(cost, self.resolution)

    def _all_units(self) -> Iterable[int]:
        yield self.units(self.scene.grab_cost)
        yield self.units(self.scene.drop_cost)
        for rule in self.costmap.all_rules():
            yield self.units(rule.cost)

    def at_least(self, units: int) -> Function:
        """c >= units."""
        if units not in self._at_least:
            self._at_least[units] = ~less_than(self.bdd, self.c.vector(self.bdd), units)
        return self._at_least[units]

    def free_for(self, place: str, obj: str) -> Function:
        """`place` in L ∪ E counts as free for a motion serving `obj` (semantics §5)."""
        key = (place, obj)
        if key not in self._free:
            where = place if place in self.scene.locations else ELSE
            result = self.bdd.true
            for other in self.scene.object_names:
                if other != obj:
                    result &= ~self.enc.at_is(other, where)
            self._free[key] = result
        return self._free[key]

    def step_cost(self, mode: str, start: str, goal: str, obj: str) -> Function:
        """cost(mode, s, t, v, o) <= c, as a BDD over (v, c)."""
        if start == goal:
            return self.bdd.true
        return self._satisfied(self.costmap.rules(mode, start, goal), obj)

    def slide_cost(self, contact: str, start: str, goal: str, obj: str) -> Function:
        """slide(a, l, l', v, o) <= c (semantics §4b), as a BDD over (v, c):
        false when no slide rule is satisfied."""
        return self._satisfied(self.costmap.slide_rules(contact, start, goal), obj)

    def _satisfied(self, rules, obj: str) -> Function:
        """The least cost of a satisfied rule <= c: some rule's places free
        for `obj`, and c at least its cost (false for no rules)."""
        result = self.bdd.false
        for rule in rules:
            condition = self.at_least(self.units(rule.cost))
            for place in rule.free:
                condition &= self.free_for(place, obj)
            result |= condition
        return result

    def motion(self, mode: str, starts: dict[str, Function], goals: dict[str, Function],
               obj: str) -> Function:
        """motion(mode, S(v), T(v), o) <= c, given `s -> [s in S(v)]` and
        `t -> [t in T(v)]` over every candidate anchor; false when S(v) or
        T(v) is empty."""
        bdd = self.bdd
        some_start = bdd.false
        for cond in starts.values():
            some_start |= cond
        some_goal = bdd.false
        for cond in goals.values():
            some_goal |= cond
        result = some_start & some_goal
        for s, in_s in starts.items():
            for t, in_t in goals.items():
                # s in S(v) /\ t in T(v) => cost(mode, s, t, v, o) <= c
                result &= ~(in_s & in_t) | self.step_cost(mode, s, t, obj)
        return result


def _cache_memory() -> int:
    """What CUDD may grow its computed table to: a quarter of the machine's
    memory, at most 4 GiB.  The fixpoint repeats the same compositions and
    products; with the 16 MiB that suits a DFA compilation the table kept
    evicting them (benchmark family 5 x 7: 398 s, against 169 s with 4 GiB)."""
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # not POSIX: assume a small machine
        physical = 2**33
    return min(2**32, physical // 4)


# -- robot families (semantics §4) ------------------------------------------------------

def _keep(arena: Arena, objects: Iterable[str] = (), grip: bool = False, ee: bool = False) -> Function:
    """Frame condition: the named parts of v' equal those of v."""
    bdd = arena.bdd
    result = bdd.true
    for o in objects:
        result &= arena.enc.at[o].unchanged(bdd)
    if grip:
        result &= arena.enc.grip.unchanged(bdd)
    if ee:
        result &= arena.enc.ee.unchanged(bdd)
    return result


def _empty_starts(arena: Arena) -> dict[str, Function]:
    """s -> [s in S(v)] for an empty hand: from ee = Else every anchor (and
    home) but the absent ones (semantics §5); from ee = (o', a') the
    anchors of o' with a' (a grasp or a contact)."""
    enc, scene = arena.enc, arena.scene
    anywhere = enc.ee_is(ELSE)
    present = set(scene.present_anchors)
    starts = {HOME: anywhere}
    for x in scene.locations + scene.else_samples:
        where = x if x in scene.locations else ELSE
        for a in scene.preimages:
            cond = anywhere if f"{x}/{a}" in present else arena.bdd.false
            for o in scene.object_names:
                cond |= enc.ee_is((o, a)) & enc.at_is(o, where)
            starts[f"{x}/{a}"] = cond
    return starts


def _goals(arena: Arena, obj: str, grasp: str) -> dict[str, Function]:
    """t -> [t in anchors(at[obj], grasp)]."""
    enc, scene = arena.enc, arena.scene
    goals = {}
    for x in scene.locations:
        goals[f"{x}/{grasp}"] = enc.at_is(obj, x)
    for anchor in anchors(scene, ELSE, grasp):
        goals[anchor] = enc.at_is(obj, ELSE)
    return goals


def _transit(arena: Arena) -> Function:
    """transit(o, a), a a grasp or a contact: hand empty, ee != (o, a); ee' = (o, a)."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    starts = _empty_starts(arena)
    moves = bdd.false
    for o in scene.object_names:
        for g in scene.preimages:
            cost = arena.motion(EMPTY, starts, _goals(arena, o, g), o)
            moves |= ~enc.ee_is((o, g)) & enc.ee_is((o, g), primed=True) & cost
    return enc.grip_is(None) & moves & _keep(arena, scene.object_names, grip=True)


def _grab(arena: Arena) -> Function:
    """grab: hand empty, ee = (o, g); at[o]' = Hand, grip' = g, ee' = at[o]."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    moves = bdd.false
    for o in scene.object_names:
        others = [p for p in scene.object_names if p != o]
        ee_follows = bdd.false
        for x in scene.locations + (ELSE,):
            ee_follows |= enc.at_is(o, x) & enc.ee_is(x, primed=True)
        for g in scene.grasps:
            moves |= (enc.ee_is((o, g)) & enc.at_is(o, HAND, primed=True)
                      & enc.grip_is(g, primed=True) & ee_follows & _keep(arena, others))
    return enc.grip_is(None) & moves & arena.at_least(arena.units(scene.grab_cost))


def _transfer(arena: Arena) -> Function:
    """transfer(l): holding o with g, l free, ee != l; ee' = l."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    moves = bdd.false
    for o in scene.object_names:
        for g in scene.grasps:
            # S(v) while holding with g: l/g when ee = l, every e/g when ee = Else
            starts = {f"{x}/{g}": enc.ee_is(x) for x in scene.locations}
            starts.update({a: enc.ee_is(ELSE) for a in anchors(scene, ELSE, g)})
            holding = enc.at_is(o, HAND) & enc.grip_is(g)
            for l in scene.locations:
                cost = arena.motion(f"{o}/{g}", starts, {f"{l}/{g}": bdd.true}, o)
                moves |= (holding & ~enc.occupied(l) & ~enc.ee_is(l)
                          & enc.ee_is(l, primed=True) & cost)
    return moves & _keep(arena, scene.object_names, grip=True)


def _drop(arena: Arena) -> Function:
    """drop: holding o with g, ee = l free; at[o]' = l, grip' = none, ee' = (o, g)."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    moves = bdd.false
    for o in scene.object_names:
        others = [p for p in scene.object_names if p != o]
        for g in scene.grasps:
            for l in scene.locations:
                moves |= (enc.at_is(o, HAND) & enc.grip_is(g) & enc.ee_is(l) & ~enc.occupied(l)
                          & enc.at_is(o, l, primed=True) & enc.grip_is(None, primed=True)
                          & enc.ee_is((o, g), primed=True) & _keep(arena, others))
    return moves & arena.at_least(arena.units(scene.drop_cost))


def _slide(arena: Arena) -> Function:
    """slide(o, a, l'): hand empty, ee = (o, a) with a a contact, at[o] = l in
    L, l' in L free; at[o]' = l', ee' = (o, a) (semantics §4b)."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    moves = bdd.false
    for o in scene.object_names:
        others = [p for p in scene.object_names if p != o]
        for a in scene.contacts:
            for l in scene.locations:
                for target in scene.locations:
                    if target == l:
                        continue
                    cost = arena.slide_cost(a, l, target, o)
                    if cost == bdd.false:
                        continue
                    moves |= (enc.ee_is((o, a)) & enc.at_is(o, l) & ~enc.occupied(target)
                              & enc.at_is(o, target, primed=True) & cost & _keep(arena, others))
    return enc.grip_is(None) & moves & _keep(arena, grip=True, ee=True)


# -- the human (semantics §4) -----------------------------------------------------------

def _human(arena: Arena) -> Function:
    """move(o, t): at[o] != Hand; t = Else, or t in L free and not where the
    held object is aligned; at[o]' = t; ee' = Else if ee was (o, a)."""
    bdd, enc, scene = arena.bdd, arena.enc, arena.scene
    aligned_ok = {l: ~(enc.holding() & enc.ee_is(l)) for l in scene.locations}
    moves = bdd.false
    for o in scene.object_names:
        others = [p for p in scene.object_names if p != o]
        targets = enc.at_is(o, ELSE, primed=True)
        for l in scene.locations:
            targets |= ~enc.occupied(l) & aligned_ok[l] & enc.at_is(o, l, primed=True)
        aimed = bdd.false  # ee = (o, a) for some grasp or contact a
        for a in scene.preimages:
            aimed |= enc.ee_is((o, a))
        ee_after = (aimed & enc.ee_is(ELSE, primed=True)) | (~aimed & enc.ee.unchanged(bdd))
        moves |= (~enc.at_is(o, HAND) & targets & ee_after
                  & _keep(arena, others, grip=True))
    return moves
