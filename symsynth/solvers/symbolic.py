"""The symbolic solver: semantics §6's value by the cost-bounded attractor on BDDs.

1. Encode the game (`solvers.bdd.arena`): state bits, the task DFA in the same
   manager, robot relations with cost bits, the human relation; with
   interchangeable objects, on orbits (`solvers.bdd.classes`), the moves
   and the strategy still those of real states (`_ClassQueries`).
2. Qualitative attractor (costs ignored), one layer of h at a time, until
   the initial position is won; its ranks bound the robot actions of some
   winning strategy (`Attractor.action_bound`: the initial position's rank
   in layer k plus every round of the layers below), so E_p <= bound *
   c_max and the budget needs bit_length(bound * c_max) bits.  When the
   initial position is never won, E_p is infinite.
3. The cost-bounded attractor over (position, budget); E_p is the least e
   with X(v0, q0, k, e).
4. The strategy, read off the iterates: at a robot position p = (v, q, h)
   of value val(p), let i be the first iterate of layer h with
   R_i(p, val(p)); play an action leading into X_{i-1} with budget
   val(p) - c.  If the human passes, the robot position p' has
   (p', val(p) - c) in R_{i-1} of the same layer, so val(p') <= val(p) - c,
   and when c = 0 and the value stays, p' was won by round i-1; if the
   human moves, p' is in layer h - 1 with val(p') <= val(p) - c.  So
   (h, val, i) decreases lexicographically along every play: the strategy
   wins, and the costs it pays add up to at most val(p).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager

from tqdm import tqdm

from symsynth.automata.bdd import Function, cofactor, peak_nodes
from symsynth.game.abstraction import (State, in_costmap_units, initial_state, legal_human_moves,
                                       letter, robot_moves)
from symsynth.game.graph import PASS
from symsynth.game.solution import Position, Solution, Step, check_parameters, task_formula, verdict
from symsynth.game.symmetry import Symmetry, interchangeable
from symsynth.logic import ast
from symsynth.scene.model import ELSE, HAND, Scene
from symsynth.solvers.bdd.arena import Arena
from symsynth.solvers.bdd.classes import ClassArena
from symsynth.solvers.bdd.fixpoint import Attractor, attractor, reachable

Q = tuple[bool, ...]


def solve_symbolic(scene: Scene, formula: str | ast.Formula | None = None, *,
                   k: int | None = None, budget: float | None = None,
                   resolution: float = 1.0, symmetric: bool = True,
                   reachable_only: bool = False) -> Solution:
    """E_p, a strategy and plays for `formula` (default: the scene's task)
    against a human with `k` moves (default: the scene's k).  With
    `symmetric` and interchangeable objects in the scene (`game.symmetry`),
    on the class encoding (`bdd.classes`); else each object's place in bits.
    With `reachable_only`, the attractors solve only the positions a play
    from the start can reach (`bdd.fixpoint.reachable`): the strategy and
    the values are those of every other solver there, and undefined (the
    strategy raises KeyError) elsewhere."""
    k = check_parameters(scene, k, resolution)
    formula = task_formula(scene, formula)
    clock = time.perf_counter()
    arena, game, stats = _encoded(scene, formula, k, resolution, symmetric)
    seconds = {"encode": time.perf_counter() - clock}

    v0 = initial_state(scene)
    q0 = game.read(game.dfa_initial, v0)
    start = (v0, q0, k)
    if game.accepting(q0):
        return _solution(arena, 0, budget, seconds, stats, None, (), None)

    within = _reachable(arena, game, v0, q0, seconds, stats) if reachable_only else None
    clock = time.perf_counter()
    with _rounds("qualitative attractor") as bar:
        qualitative = attractor(arena, with_costs=False, progress=bar, within=within,
                                stop=lambda x: game.contains(x, start))
    seconds["qualitative"] = time.perf_counter() - clock
    stats["qualitative_iterations"] = sum(qualitative.rounds)
    if qualitative.converged:  # the initial position was never won
        game.attractor = qualitative
        counter: tuple[Step, ...] | None = _counter_play(game, start)
        stats["peak_nodes"] = peak_nodes(arena.bdd)
        return _solution(arena, None, budget, seconds, stats, None, (), counter)

    width = (qualitative.action_bound * arena.max_units).bit_length()
    del qualitative
    game.attractor = _quantitative(arena, width, within, seconds, stats)
    units = game.value_human(start)

    clock = time.perf_counter()
    strategy = Strategy(game)
    principal = _principal_play(game, start)
    seconds["plays"] = time.perf_counter() - clock
    counter = principal if verdict(units, resolution, budget) is False else None
    return _solution(arena, units, budget, seconds, stats, strategy, principal, counter)


def _reachable(arena: Arena, game: _Queries, v0: State, q0: Q, seconds: dict[str, float],
               stats: dict[str, object]) -> list[Function]:
    """The positions a play from (v0, q0) can reach (`fixpoint.reachable`),
    counted into `stats`."""
    clock = time.perf_counter()
    within = reachable(arena, arena.bdd.cube(game._values(v0, q0)))
    seconds["reachable"] = time.perf_counter() - clock
    nvars = len(arena.state_bits) + len(arena.dfa.bits)
    stats["reachable_positions"] = sum(int(arena.bdd.count(u, nvars=nvars)) for u in within)
    return within


def _quantitative(arena: Arena, width: int, within: list[Function] | None, seconds: dict[str, float],
                  stats: dict[str, object]) -> Attractor:
    """The cost-bounded attractor on budgets of `width` bits."""
    arena.declare_budget(width)
    stats["budget_bits"] = width
    clock = time.perf_counter()
    with _rounds("cost-bounded attractor") as bar:
        quantitative = attractor(arena, with_costs=True, progress=bar, within=within)
    seconds["attractor"] = time.perf_counter() - clock
    stats["iterations"] = sum(quantitative.rounds)
    stats.update({f"seconds_{key}": value for key, value in quantitative.seconds.items()})
    stats["peak_nodes"] = peak_nodes(arena.bdd)
    return quantitative


def _encoded(scene: Scene, formula: ast.Formula, k: int, resolution: float,
             symmetric: bool) -> tuple[Arena, _Queries, dict[str, object]]:
    """The arena (the class encoding when `symmetric` finds interchangeable
    objects, else each object's place in bits), its queries and its sizes."""
    classes = interchangeable(scene, formula) if symmetric else ()
    arena: Arena
    game: _Queries
    if classes:
        arena = ClassArena(scene, formula, k, resolution, classes)
        game = _ClassQueries(arena)
    else:
        arena = Arena(scene, formula, k, resolution)
        game = _Queries(arena)
    stats: dict[str, object] = {"encoding": "classes" if classes else "objects",
                                "state_bits": len(arena.state_bits), "dfa_bits": len(arena.dfa.bits),
                                "cost_bits": len(arena.c.bits), "max_units": arena.max_units}
    if classes:
        stats["interchangeable"] = Symmetry(scene, classes).describe()
    return arena, game, stats


@contextmanager
def _rounds(what: str) -> Iterator[Callable[[int], None]]:
    """A progress bar of fixpoint rounds, shown only on a terminal and only
    when the work takes more than a second."""
    with tqdm(desc=what, unit=" rounds", delay=1.0, leave=False, disable=None) as bar:
        yield lambda rounds: bar.update(rounds - bar.n)


def _solution(arena: Arena, units: int | None, budget: float | None, seconds: dict,
              stats: dict, strategy: Mapping | None, principal: tuple[Step, ...],
              counter: tuple[Step, ...] | None) -> Solution:
    r = arena.resolution
    return Solution(None if units is None else in_costmap_units(units, r), units, r, budget,
                    verdict(units, r, budget), arena.k, _count_positions(arena), seconds,
                    strategy if strategy is not None else {}, principal, counter,
                    arena.scene.object_names, stats)


def _count_positions(arena: Arena) -> int:
    """Robot-turn positions (v, q, h) the encoding represents: well-formed
    states x reachable DFA states x 0..k."""
    bdd = arena.bdd
    space = arena.enc.well_formed() & arena.dfa.reachable & arena.h.invariant(bdd)
    nvars = len(arena.state_bits) + len(arena.dfa.bits) + len(arena.h.bits)
    return int(bdd.count(space, nvars=nvars))


class _Queries:
    """Questions about single positions, answered from the BDDs."""

    def __init__(self, arena: Arena):
        self.arena = arena
        self.bdd = arena.bdd
        self.dfa_initial: Q = arena.dfa.initial
        self.attractor: Attractor | None = None

    def _attractor(self) -> Attractor:
        """The attractor the questions are answered from (set by the solver)."""
        if self.attractor is None:
            raise ValueError("no attractor computed yet")
        return self.attractor

    # -- the DFA on explicit states ----------------------------------------------
    def read(self, q: Q, v: State) -> Q:
        """The DFA state after reading ρ(v) from q."""
        return self.arena.dfa.step(q, letter(self.arena.scene, self.arena.props, v))

    def accepting(self, q: Q) -> bool:
        return self.arena.dfa.is_accepting(q)

    # -- membership and values ------------------------------------------------------
    def _values(self, v: State | None, q: Q | None = None, h: int | None = None,
                e: int | None = None) -> dict[str, bool]:
        arena = self.arena
        values = arena.enc.assignment(v) if v is not None else {}
        if q is not None:
            values.update(zip(arena.dfa.bits, q))
        if h is not None:
            values.update(arena.h.assignment(h))
        if e is not None:
            values.update(arena.budget().assignment(e))
        return values

    def _holds(self, u: Function, values: dict[str, bool]) -> bool:
        return cofactor(self.bdd, values, u) == self.bdd.true

    def restrict(self, u: Function, position: Position) -> Function:
        v, q, h = position
        values = self._values(v, q, h)
        return cofactor(self.bdd, values, u)

    def contains(self, u: Function, position: Position) -> bool:
        """Some budget puts `position` in `u`."""
        return self.restrict(u, position) != self.bdd.false

    def value_robot(self, position: Position) -> int | None:
        """val(p) of a robot-turn position, in units; None when infinite."""
        return self._least_budget(self._attractor().robot_win, position)

    def value_human(self, position: Position) -> int | None:
        v, q, h = position
        if self.accepting(q):
            return 0
        return self._least_budget(self._attractor().win, position)

    def _least_budget(self, u: Function, position: Position) -> int | None:
        restricted = self.restrict(u, position)
        if self.arena.e is None:  # qualitative only
            return None if restricted == self.bdd.false else 0
        return self.arena.e.least(self.bdd, restricted)

    def rank(self, position: Position, budget: int) -> int:
        """The first iterate (0-based) that wins `position` with `budget`."""
        v, q, h = position
        values = self._values(v, q, h, budget)
        layers = self._attractor().layers
        lo, hi = 0, len(layers) - 1  # layers grow: binary search the first member
        while lo < hi:
            mid = (lo + hi) // 2
            if self._holds(layers[mid], values):
                hi = mid
            else:
                lo = mid + 1
        return lo

    # -- moves on explicit states ---------------------------------------------------
    def robot_moves(self, v: State) -> list[tuple[str, State, int]]:
        """(action, next state, units) for every robot action from v, by name."""
        arena, bdd = self.arena, self.bdd
        values = arena.enc.assignment(v)
        moves = []
        for relation in arena.robot.values():
            options = cofactor(bdd, values, relation)  # over (v', c)
            targets = bdd.exist(set(arena.c.bits), options)
            for bits in bdd.pick_iter(targets, care_vars=set(arena.next_bits)):
                w = arena.enc.decode(bits, primed=True)
                # the relation is upward closed in c: the action's cost is its least c
                cost = arena.c.least(bdd, cofactor(bdd, arena.enc.assignment(w, primed=True), options))
                if cost is None:  # w was picked from the options: some cost leads there
                    raise ValueError(f"no cost for the robot move from {v} to {w}")
                moves.append((action_between(arena.scene, v, w), w, cost))
        return sorted(moves, key=lambda m: m[0])

    def human_moves(self, v: State) -> list[tuple[str, State]]:
        arena, bdd = self.arena, self.bdd
        options = cofactor(bdd, arena.enc.assignment(v), arena.human)
        targets = (arena.enc.decode(bits, primed=True)
                   for bits in bdd.pick_iter(options, care_vars=set(arena.next_bits)))
        return sorted(((_move_name(arena.scene, v, w), w) for w in targets), key=lambda m: m[0])

    def choose(self, position: Position) -> tuple[str, State, int, int] | None:
        """The strategy at a robot position: (action, next state, units, budget
        left after it), or None where the robot cannot win."""
        value = self.value_robot(position)
        if value is None:
            return None
        i = self.rank(position, value)
        v, q, h = position
        target = self._attractor().wins[i]  # the human-turn set R_{i+1} was computed from
        for action, w, units in self.robot_moves(v):
            if units <= value and self._holds(target, self._values(w, self.read(q, w), h,
                                                                     value - units)):
                return action, w, units, value - units
        raise RuntimeError(f"internal error: no action of value {value} at {position}")


class _ClassQueries(_Queries):
    """Questions about real positions on the class encoding: the BDDs are
    read at a position's orbit (`ClassEncoding.assignment`), the moves are
    the real state's own (`game.abstraction`), so the strategy names the
    real object standing where the action acts: an action leads into an
    iterate exactly when its orbit does."""

    def robot_moves(self, v: State) -> list[tuple[str, State, int]]:
        units = self.arena.units
        return sorted(((action, after, units(cost)) for action, after, cost in robot_moves(self.arena.scene, v)),
                      key=lambda m: m[0])

    def human_moves(self, v: State) -> list[tuple[str, State]]:
        return sorted(((m.action, m.after) for m in legal_human_moves(self.arena.scene, v)),
                      key=lambda m: m[0])


class Strategy(Mapping):
    """The robot's action at robot-turn positions (v, q, h), computed on
    demand from the attractor's iterates and then cached.

    Looking up a position of infinite value raises KeyError.  The mapping is
    lazy: iterating lists the positions decided so far; the positions a
    play can reach are `game.strategy.reachable_positions`.
    """

    def __init__(self, game: _Queries):
        self._game = game
        self._cache: dict[Position, str | None] = {}

    def __getitem__(self, position: Position) -> str:
        if position not in self._cache:
            choice = self._game.choose(position)
            self._cache[position] = None if choice is None else choice[0]
        action = self._cache[position]
        if action is None:
            raise KeyError(position)
        return action

    def __iter__(self) -> Iterator[Position]:
        return (p for p, action in list(self._cache.items()) if action is not None)

    def __len__(self) -> int:
        return sum(action is not None for action in self._cache.values())


def _principal_play(game: _Queries, start: Position) -> tuple[Step, ...]:
    """The strategy against the human's worst replies (the largest value; a
    pass on ties, then the first move by name), from the start to the win."""
    r = game.arena.resolution
    play: list[Step] = []
    v, q, h = start
    while True:
        # the human's turn at (v, q, h): pass, or move to a robot position
        options = [(game.value_robot((v, q, h)), PASS, v, q, h)]
        if h > 0:
            for name, u in game.human_moves(v):
                q2 = game.read(q, u)
                worth = 0 if game.accepting(q2) else game.value_robot((u, q2, h - 1))
                options.append((worth, name, u, q2, h - 1))
        _, name, v, q, h = max(options, key=lambda o: math.inf if o[0] is None else o[0])  # None: infinite
        if name != PASS:
            play.append(Step("human", name, 0.0, v))
            if game.accepting(q):
                return tuple(play)
        chosen = game.choose((v, q, h))
        if chosen is None:  # every position of the play is won (its value is finite)
            raise ValueError(f"the strategy has no action at {(v, q, h)}")
        action, w, cost, _ = chosen
        play.append(Step("robot", action, in_costmap_units(cost, r), w))
        v, q = w, game.read(q, w)
        if game.accepting(q):
            return tuple(play)


def _counter_play(game: _Queries, start: Position) -> tuple[Step, ...]:
    """A play where the robot never wins (the initial position is lost): the
    human keeps to lost robot positions (passing when that does), the robot
    takes its cheapest action; it ends where the robot has no action or the
    play comes back to a robot position already visited."""
    r = game.arena.resolution
    play: list[Step] = []
    v, q, h = start
    seen = set()
    while True:
        if game.value_robot((v, q, h)) is not None:  # passing would let the robot win
            for name, u in game.human_moves(v) if h > 0 else []:
                q2 = game.read(q, u)
                if not game.accepting(q2) and game.value_robot((u, q2, h - 1)) is None:
                    play.append(Step("human", name, 0.0, u))
                    v, q, h = u, q2, h - 1
                    break
        if (v, q, h) in seen:
            return tuple(play)
        seen.add((v, q, h))
        moves = game.robot_moves(v)
        if not moves:
            return tuple(play)
        action, w, units = min(moves, key=lambda m: m[2])
        play.append(Step("robot", action, in_costmap_units(units, r), w))
        v, q = w, game.read(q, w)


# -- names of moves --------------------------------------------------------------

def action_between(scene: Scene, v: State, w: State) -> str:
    """The robot action that leads from v to w (semantics §4's names)."""
    if v.grip is None:
        if w.grip is not None:
            return f"grab({scene.object_names[w.at.index(HAND)]})"
        if not isinstance(w.ee, tuple):  # an empty hand moves to an object
            raise ValueError(f"no robot action leads from {v} to {w}")
        o, a = w.ee
        if w.at != v.at:  # the hand stays at the contact, the object moves
            return f"slide({o},{a},{w.at[scene.object_names.index(o)]})"
        return f"transit({o},{a})"
    if w.grip is not None:
        return f"transfer({w.ee})"
    i = v.at.index(HAND)
    return f"drop({scene.object_names[i]},{w.at[i]})"


def _move_name(scene: Scene, v: State, w: State) -> str:
    """The human move from v to w.  A move within Else changes no `at`: it
    is the object the end-effector was aimed at, if any, else the first
    object at Else (the states are the same whichever moved)."""
    changed = [i for i, (a, b) in enumerate(zip(v.at, w.at)) if a != b]
    if changed:
        i = changed[0]
    elif isinstance(v.ee, tuple) and w.ee == ELSE:
        i = scene.object_names.index(v.ee[0])
    else:
        i = v.at.index(ELSE)
    return f"move({scene.object_names[i]},{w.at[i]})"
