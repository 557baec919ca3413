"""Interchangeable objects: positions that differ only by which of two alike
objects stands where have the same value.

Two objects are *interchangeable* in a game when swapping them everywhere
changes nothing the game reads (docs/game-semantics.md §2–§5):

- the task cannot tell them apart: for every tag an `at` or `holding` atom
  of the task names, both carry it or neither does (so an atom that names
  one of them by its own name separates it from the others);
- the costmap cannot: for every grasp `g`, the rules of mode `o/g` are the
  rules of mode `o'/g`, pair by pair (same `free` sets and costs; the
  evidence paths may differ).  Everything else the game reads (transits to
  `x/g`, grab and drop, slides, the human's moves, `occupied`/`free`) does
  not depend on which object it is;
- in a physical scene, also the same shape: a strategy acts on the real
  object, and the simulator moves its body.

Then a permutation `π` of each class's members maps the game onto itself:
a state `v`, its moves, their costs and their letters map to `π(v)`'s, so
`val(v, q, h) = val(π(v), q, h)`.  The solvers therefore search *canonical*
positions only: in each class, the members' places (with the grasp or
contact the hand is at, if it is at one of them) sorted and handed out in
the order of the members' indices.  The number of positions shrinks by up to
the product of the classes' factorials.

What leaves a solver still names real objects: `realize` maps a solution
on canonical positions back -- its strategy answers at any real position
(canonicalize, look the action up, and take the real move that does to the
real object what the canonical move does to its canonical stand-in), and its
plays are replayed from the real initial state.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Hashable, Iterator, Mapping

from symsynth.errors import InputError
from symsynth.game.abstraction import Move, State, initial_state, legal_human_moves, legal_robot_moves
from symsynth.game.solution import Position, Solution, Step
from symsynth.logic import ast
from symsynth.scene.model import Scene


def interchangeable(scene: Scene, formula: ast.Formula) -> tuple[tuple[int, ...], ...]:
    """The classes of interchangeable objects with at least two members, each
    as object indices in increasing order: the scene's declared classes
    (`interchangeable:`, each checked: a declaration the game can tell apart
    is refused, never trusted), else the classes found (module doc)."""
    if scene.declared_classes is None:
        return detected(scene, formula)
    index = {o: i for i, o in enumerate(scene.object_names)}
    keys = _keys(scene, formula)
    wheres = scene.declared_where or tuple(f"interchangeable.{i}" for i in range(len(scene.declared_classes)))
    for members, where in zip(scene.declared_classes, wheres):
        first = members[0]
        for other in members[1:]:
            if keys[other] != keys[first]:
                raise InputError(f"{where}: {first} and {other} are not interchangeable: "
                                 f"{_apart(keys[first], keys[other], first, other)}; solving them as one "
                                 "would give another game's value")
    return tuple(tuple(sorted(index[o] for o in members)) for members in scene.declared_classes)


def detected(scene: Scene, formula: ast.Formula) -> tuple[tuple[int, ...], ...]:
    """The classes of objects the game cannot tell apart (module doc)."""
    keys = _keys(scene, formula)
    groups: dict[Hashable, list[int]] = {}
    for i, name in enumerate(scene.object_names):
        groups.setdefault(keys[name], []).append(i)
    return tuple(tuple(members) for members in groups.values() if len(members) > 1)


def _keys(scene: Scene, formula: ast.Formula) -> dict[str, tuple]:
    """Object -> what the game reads of it: (the task's tags it carries, its
    costmap rows of mode o/g, its shape).  Equal keys: interchangeable."""
    tags = sorted({a.args[0] for a in ast.atoms(formula) if a.name in ("at", "holding") and a.args})
    names = scene.object_names
    modes = {f"{o}/{g}": (o, g) for o in names for g in scene.grasps}
    rows: dict[str, set] = {o: set() for o in names}
    if scene.costmap is not None:
        for (mode, s, t), rules in scene.costmap.motions.items():
            if mode in modes:
                o, g = modes[mode]
                rows[o].add((g, s, t, frozenset(rules)))
    shapes = _shapes(scene)
    return {spec.name: (tuple((t, t in spec.tags) for t in tags), frozenset(rows[spec.name]),
                        shapes.get(spec.name)) for spec in scene.objects}


def _apart(a: tuple, b: tuple, first: str, other: str) -> str:
    """What tells two objects apart, from their `_keys`."""
    for (tag, has_a), (_, has_b) in zip(a[0], b[0]):
        if has_a != has_b:
            return f"the task names {tag!r}, which {first if has_a else other} carries and " \
                   f"{other if has_a else first} does not"
    if a[1] != b[1]:
        differ = sorted({(g, s, t) for g, s, t, _ in a[1] ^ b[1]})
        g, s, t = differ[0]
        return (f"the costmap's motions holding them differ (mode {first}/{g} against {other}/{g}, "
                f"{s} -> {t}{f', and {len(differ) - 1} more' if len(differ) > 1 else ''})")
    return f"their shapes differ ({a[2]} against {b[2]})"


def _shapes(scene: Scene) -> dict[str, str]:
    """Object name -> its shape, written out (physical scenes; none in abstract ones)."""
    if scene.geometry is None:
        return {}
    return {name: repr(shape) for name, shape in scene.geometry.shapes.items()}


class Symmetry:
    """Canonical positions for the classes of interchangeable objects of a scene."""

    def __init__(self, scene: Scene, classes: tuple[tuple[int, ...], ...]):
        self.scene = scene
        self.classes = classes
        self.names = scene.object_names
        self._index = {o: i for i, o in enumerate(self.names)}
        self._cache: dict[State, tuple[State, tuple[int, ...]]] = {}

    @classmethod
    def of(cls, scene: Scene, formula: ast.Formula) -> Symmetry | None:
        """The scene's symmetry for `formula`, None when all objects are distinct."""
        classes = interchangeable(scene, formula)
        return cls(scene, classes) if classes else None

    def describe(self) -> str:
        """`{w1, w2}, {r1, r2, r3}`: the classes by name."""
        return ", ".join("{" + ", ".join(self.names[i] for i in c) + "}" for c in self.classes)

    def reduction(self) -> int:
        """The product of the classes' factorials: the most positions one canonical one stands for."""
        product = 1
        for c in self.classes:
            for j in range(2, len(c) + 1):
                product *= j
        return product

    def canon(self, v: State) -> State:
        """The canonical state of `v`'s orbit."""
        return self.canonical(v)[0]

    def canonical(self, v: State) -> tuple[State, tuple[int, ...]]:
        """(canonical state, π) with `π[i]` the index object `i` of `v` stands as."""
        hit = self._cache.get(v)
        if hit is not None:
            return hit
        at = list(v.at)
        perm = list(range(len(at)))
        ee = v.ee
        holder = self._index[ee[0]] if isinstance(ee, tuple) else -1
        new_ee = ee
        for members in self.classes:
            order = sorted(members, key=lambda i: (v.at[i], ee[1] if i == holder else ""))
            for j, i in zip(members, order):
                at[j] = v.at[i]
                perm[i] = j
                if i == holder:
                    new_ee = (self.names[j], ee[1])
        result = (State(tuple(at), v.grip, new_ee), tuple(perm))
        if len(self._cache) < 1 << 20:
            self._cache[v] = result
        return result

    def real_move(self, v: State, action: str, robot: bool) -> Move:
        """The move of the real state `v` that the canonical action `action`
        (named at `canon(v)`) stands for."""
        c, perm = self.canonical(v)
        legal = legal_robot_moves if robot else legal_human_moves
        if c == v:
            return next(m for m in legal(self.scene, v) if m.action == action)
        m = next(m for m in legal(self.scene, c) if m.action == action)
        real = perm.index(m.serves)
        return next(x for x in legal(self.scene, v)
                    if x.kind == m.kind and x.serves == real and x.grasp == m.grasp
                    and x.location == m.location)

    def realize(self, solution: Solution) -> Solution:
        """`solution`, found on canonical positions, in real objects: its
        strategy answers at every real position, its plays start from the
        scene's initial state."""
        v0 = initial_state(self.scene)
        principal = self._replay(v0, solution.principal_play)
        counter = solution.counter_play
        if counter is solution.principal_play:
            counter = principal
        elif counter is not None:
            counter = self._replay(v0, counter)
        stats = dict(solution.stats) | {"interchangeable": self.describe()}
        return dataclasses.replace(solution, strategy=RealStrategy(self, solution.strategy),
                                   principal_play=principal, counter_play=counter, stats=stats)

    def _replay(self, v: State, play: tuple[Step, ...]) -> tuple[Step, ...]:
        out = []
        for step in play:
            move = self.real_move(v, step.action, step.who == "robot")
            assert self.canon(move.after) == self.canon(step.state), "a canonical play left its orbit"
            out.append(Step(step.who, move.action, step.cost, move.after))
            v = move.after
        return tuple(out)


class RealStrategy(Mapping):
    """A strategy on canonical positions, answering at real ones."""

    def __init__(self, symmetry: Symmetry, canonical: Mapping[Position, str]):
        self._symmetry = symmetry
        self._canonical = canonical

    def __getitem__(self, position: Position) -> str:
        v, q, h = position
        action = self._canonical[(self._symmetry.canon(v), q, h)]
        return self._symmetry.real_move(v, action, robot=True).action

    def __iter__(self) -> Iterator[Position]:
        return iter(self._canonical)  # canonical positions are real ones too

    def __len__(self) -> int:
        return len(self._canonical)
