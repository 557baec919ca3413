"""The compiled solver (`--solver compiled`): the explicit solver's algorithm
with its core in machine code (numba), on positions packed into integers.

Same game, same value as `solvers.explicit` (Dijkstra for min-cost
reachability games over the positions the start reaches); what changes is
how a position and its moves are represented:

- a position is one 64-bit integer: each object's place (a location, Else or
  the hand) in a few bits, the end-effector (Else, a location, or an
  object's grasp or contact), the grip, the DFA state, the human's moves
  left and whose turn it is;
- the costmap becomes integer tables: per (mode, from anchor, to anchor) the
  rules' `free` sets as bit masks over L ∪ E with their costs in units, the
  same for slides; "the places that count as free" for a move is a mask
  computed from the packed state, and a rule is satisfied when its mask is
  inside it;
- the task's DFA becomes a table `(q, letter) -> q'` over the letters of its
  atoms (a letter is a bit mask of the atoms that hold), built from the
  symbolic DFA before the search;
- interchangeable objects (`game.symmetry`) are canonicalized in the kernel
  with the same order as `Symmetry.canonical` (places and frames ranked by
  name), so the Python side maps a canonical answer back to real objects
  exactly as it does for the explicit solver.

Positions, edges and values live in numpy arrays; the exploration (an
open-addressing hash table from packed position to index) and Dijkstra's algorithm (a binary
heap on arrays) are `numba.njit` functions, compiled on first use and cached
on disk.  The moves are generated in the kernel from docs/game-semantics.md
§4-§5 as `game/abstraction.py` writes them; the tests hold the two to the
same value on every generated scene, and the strategy is followed through
every human behaviour in the real game.

Scenes the packing cannot hold (more than 62 bits per position, more than
16 task atoms) raise `TooLarge` (an `InputError`) naming the limit; `--solver explicit`
solves them.
"""

from __future__ import annotations

import math
import time
from collections.abc import Hashable, Iterator, Mapping

import numpy as np
from numba import njit

from symsynth.errors import InputError
from symsynth.game.abstraction import (State, action_name, costmap_of, initial_state, legal_human_moves,
                                       legal_robot_moves, quantize)
from symsynth.game.graph import PASS
from symsynth.game.solution import (Position, Solution, Step, check_parameters, task_formula, verdict,
                                    won_at_start)
from symsynth.game.symmetry import Symmetry
from symsynth.automata import compile_ltlf
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND, HOME, Scene
from symsynth.scene.propositions import interpret_all

INF = np.int64(1 << 60)
MAX_ATOMS = 16


class TooLarge(InputError):
    """The game does not fit the compiled solver's packing or tables."""


KIND_TRANSIT, KIND_GRAB, KIND_TRANSFER, KIND_DROP, KIND_SLIDE, KIND_PASS, KIND_MOVE = range(7)


def solve_compiled(scene: Scene, formula: str | ast.Formula | None = None, *,
                   k: int | None = None, budget: float | None = None,
                   resolution: float = 1.0, symmetric: bool = True) -> Solution:
    """E_p, a strategy and plays, as `solve_explicit` computes them."""
    k = check_parameters(scene, k, resolution)
    clock = time.perf_counter()
    formula = task_formula(scene, formula)
    symmetry = Symmetry.of(scene, formula) if symmetric else None
    tables = Tables(scene, formula, resolution, symmetry, k)
    _check_width(tables, k)
    seconds = {"tables": time.perf_counter() - clock}
    v0 = initial_state(scene)
    q0 = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v0))
    if tables.accepting[q0]:
        return won_at_start(scene, k, resolution, budget, seconds | {"explore": 0.0, "solve": 0.0})

    clock = time.perf_counter()
    start = tables.key(tables.canon(tables.pack(v0)), q0, k, robot=False)
    keys, offsets, targets, units, codes = _explore(start, *tables.kernel_args())
    seconds["explore"] = time.perf_counter() - clock

    clock = time.perf_counter()
    if len(targets) >= 1 << 31 or len(keys) >= 1 << 31:
        raise TooLarge(f"the compiled solver holds fewer than 2^31 moves; this game has {len(targets)}")
    value, choice = _dijkstra(keys, offsets, targets, units)
    graph = Graph(tables, keys, offsets, targets, units, codes, value, choice)
    top = int(value[1])
    result = None if top >= INF else top
    realizable = verdict(result, resolution, budget)
    if result is None:
        principal, counter = (), graph.counter_play()
        strategy: Mapping = {}
    else:
        principal = graph.principal_play()
        counter = principal if realizable is False else None
        strategy = CompiledStrategy(graph)
    seconds["solve"] = time.perf_counter() - clock
    solution = Solution(None if result is None else result * resolution, result, resolution, budget,
                        realizable, k, len(keys) - 1, seconds, strategy, principal, counter,
                        scene.object_names, {"edges": int(offsets[-1])})
    return solution if symmetry is None else symmetry.realize(solution)


# -- tables ------------------------------------------------------------------------------

def _bits(count: int) -> int:
    return max(1, (count - 1).bit_length())


class Tables:
    """The scene, costmap, task and symmetry as integer arrays, and the packing."""

    def __init__(self, scene: Scene, formula: ast.Formula, resolution: float, symmetry: Symmetry | None,
                 k: int):
        self.scene, self.resolution, self.k = scene, resolution, k
        names, L, E, F = scene.object_names, scene.locations, scene.else_samples, scene.preimages
        n, m = len(names), len(L)
        self.n, self.m, self.F = n, m, len(F)
        self.place_names = list(L) + [ELSE, HAND]
        self.place_of = {p: i for i, p in enumerate(self.place_names)}
        self.frame_of = {f: i for i, f in enumerate(F)}
        # packing: at fields, then ee, then grip
        self.pb = _bits(m + 2)
        self.ee_count = 1 + m + n * len(F)
        self.eb = _bits(self.ee_count)
        self.gb = _bits(len(F) + 1)
        self.vbits = n * self.pb + self.eb + self.gb

        # anchors and rules
        anchors = [HOME] + [f"{x}/{a}" for x in list(L) + list(E) for a in F]
        aidx = {a: i for i, a in enumerate(anchors)}
        A = len(anchors)
        self.anchor_at = np.full((m + 1, len(F), max(1, len(E))), -1, np.int64)  # place (L or ELSE), frame
        self.anchor_count = np.zeros((m + 1, len(F)), np.int64)
        for f, a in enumerate(F):
            for l in range(m):
                self.anchor_at[l, f, 0] = aidx[f"{L[l]}/{a}"]
                self.anchor_count[l, f] = 1
            for j, e in enumerate(E):
                self.anchor_at[m, f, j] = aidx[f"{e}/{a}"]
            self.anchor_count[m, f] = len(E)
        self.home_starts = np.array([aidx[a] for a in scene.anchors], np.int64)
        free_bit = {x: i for i, x in enumerate(list(L) + list(E))}
        self.samples_mask = np.int64(sum(1 << free_bit[e] for e in E))
        modes = {EMPTY: 0}
        for i, o in enumerate(names):
            for f, a in enumerate(F):
                modes[f"{o}/{a}"] = 1 + i * len(F) + f
        self.rule_start = np.zeros((len(modes), A, A), np.int64)
        self.rule_count = np.zeros((len(modes), A, A), np.int64)
        free_list, unit_list = [], []
        costmap = costmap_of(scene)
        for (mode, s, t), rules in costmap.motions.items():
            if mode not in modes or s not in aidx or t not in aidx:
                continue
            mi, si, ti = modes[mode], aidx[s], aidx[t]
            self.rule_start[mi, si, ti] = len(free_list)
            self.rule_count[mi, si, ti] = len(rules)
            for r in rules:
                free_list.append(sum(1 << free_bit[x] for x in r.free if x in free_bit))
                unit_list.append(quantize(r.cost, resolution) if math.isfinite(r.cost) else INF)
        self.slide_start = np.zeros((max(1, len(F)), m, m), np.int64)
        self.slide_count = np.zeros((max(1, len(F)), m, m), np.int64)
        for (a, s, t), rules in costmap.slides.items():
            if a not in self.frame_of or s not in self.place_of or t not in self.place_of:
                continue
            fi, si, ti = self.frame_of[a], self.place_of[s], self.place_of[t]
            if si >= m or ti >= m:
                continue
            self.slide_start[fi, si, ti] = len(free_list)
            self.slide_count[fi, si, ti] = len(rules)
            for r in rules:
                free_list.append(sum(1 << free_bit[x] for x in r.free if x in free_bit))
                unit_list.append(quantize(r.cost, resolution) if math.isfinite(r.cost) else INF)
        self.rule_free = np.array(free_list or [0], np.int64)
        self.rule_units = np.array(unit_list or [0], np.int64)
        self.is_grasp = np.array([a in scene.grasps for a in F] or [False], np.bool_)
        self.grab_units = quantize(scene.grab_cost, resolution) if math.isfinite(scene.grab_cost) else INF
        self.drop_units = quantize(scene.drop_cost, resolution) if math.isfinite(scene.drop_cost) else INF

        # atoms and the DFA table
        props = interpret_all(formula, scene)
        self.atom_keys = list(props)
        if len(self.atom_keys) > MAX_ATOMS:
            raise TooLarge(f"the compiled solver takes tasks of at most {MAX_ATOMS} atoms, "
                             f"this one has {len(self.atom_keys)}; use --solver explicit")
        kinds = {"at": 0, "holding": 1, "occupied": 2, "free": 3}
        self.atom_kind = np.array([kinds[p.kind] for p in props.values()] or [0], np.int64)
        self.atom_mask = np.array([sum(1 << i for i, spec in enumerate(scene.objects)
                                       if p.tag is not None and p.tag in spec.tags)
                                   for p in props.values()] or [0], np.int64)
        self.atom_place = np.array([self.place_of[HAND if p.kind == "holding" else p.location]
                                    for p in props.values()] or [0], np.int64)
        self.dfa = compile_ltlf(formula)
        self._dfa_table()
        self.qbits = _bits(len(self.dfa_states))

        # symmetry: classes, and the ranks that order places and frames as Symmetry does
        self.symmetry = symmetry
        classes = symmetry.classes if symmetry is not None else ()
        self.class_members = np.array([i for c in classes for i in c] or [0], np.int64)
        self.class_offsets = np.array([0] + list(np.cumsum([len(c) for c in classes])), np.int64)
        order = sorted(self.place_names)
        self.place_rank = np.array([order.index(p) for p in self.place_names], np.int64)
        self.rank_place = np.array([self.place_of[p] for p in order], np.int64)

    def _dfa_table(self) -> None:
        """Every DFA state the initial one reaches over any letter of the task's atoms."""
        letters = 1 << len(self.atom_keys)
        words = [frozenset(k for j, k in enumerate(self.atom_keys) if bits >> j & 1) for bits in range(letters)]
        states, index = [self.dfa.initial], {self.dfa.initial: 0}
        rows = []
        for q in states:  # grows while iterated
            row = []
            for word in words:
                q2 = self.dfa.step(q, word)
                if q2 not in index:
                    index[q2] = len(states)
                    states.append(q2)
                row.append(index[q2])
            rows.append(row)
        self.dfa_states, self.dfa_index = states, index
        self.trans = np.array(rows, np.int64)
        self.accepting = np.array([self.dfa.is_accepting(q) for q in states], np.bool_)

    # -- packing (Python side) -----------------------------------------------------
    def pack(self, v: State) -> int:
        x = 0
        for i, place in enumerate(v.at):
            x |= self.place_of[place] << (i * self.pb)
        if isinstance(v.ee, tuple):
            o, a = v.ee
            ee = 1 + self.m + self.scene.object_names.index(o) * self.F + self.frame_of[a]
        elif v.ee == ELSE:
            ee = 0
        else:
            ee = 1 + self.place_of[v.ee]
        x |= ee << (self.n * self.pb)
        grip = 0 if v.grip is None else 1 + self.frame_of[v.grip]
        return x | grip << (self.n * self.pb + self.eb)

    def unpack(self, x: int) -> State:
        pmask = (1 << self.pb) - 1
        at = tuple(self.place_names[(x >> (i * self.pb)) & pmask] for i in range(self.n))
        ee = (x >> (self.n * self.pb)) & ((1 << self.eb) - 1)
        grip = (x >> (self.n * self.pb + self.eb)) & ((1 << self.gb) - 1)
        if ee == 0:
            eev: object = ELSE
        elif ee <= self.m:
            eev = self.place_names[ee - 1]
        else:
            o, f = divmod(ee - 1 - self.m, self.F)
            eev = (self.scene.object_names[o], self.scene.preimages[f])
        return State(at, None if grip == 0 else self.scene.preimages[grip - 1], eev)

    def canon(self, x: int) -> int:
        return int(_canon(np.int64(x), self.n, self.m, self.F, self.pb, self.eb, self.class_members,
                          self.class_offsets, self.place_rank, self.rank_place))

    def step(self, q: int, x: int) -> int:
        return int(self.trans[q, _letter(np.int64(x), self.n, self.pb, self.atom_kind, self.atom_mask,
                                          self.atom_place, len(self.atom_keys))])

    def key(self, x: int, q: int, h: int, robot: bool) -> int:
        return ((x << self.qbits | q) * (self.k + 1) + h) * 2 + int(robot)

    def kernel_args(self) -> tuple:
        return (self.n, self.m, self.F, self.pb, self.eb, self.gb, self.qbits, self.k,
                self.anchor_at, self.anchor_count, self.home_starts, self.samples_mask,
                self.rule_start, self.rule_count, self.rule_free, self.rule_units,
                self.slide_start, self.slide_count, self.is_grasp, np.int64(self.grab_units),
                np.int64(self.drop_units), self.atom_kind, self.atom_mask, self.atom_place,
                len(self.atom_keys), self.trans, self.accepting, self.class_members,
                self.class_offsets, self.place_rank, self.rank_place)

    def action(self, code: int) -> str:
        """The name of the move an edge's code stands for."""
        rest, loc = divmod(int(code), self.m + 2)
        rest, frame = divmod(rest, self.F + 1)
        kind, obj = divmod(rest, self.n + 1)
        names, F = self.scene.object_names, self.scene.preimages
        if kind == KIND_TRANSIT:
            return action_name("transit", names[obj], F[frame])
        if kind == KIND_GRAB:
            return action_name("grab", names[obj])
        if kind == KIND_TRANSFER:
            return action_name("transfer", self.place_names[loc])
        if kind == KIND_DROP:
            return action_name("drop", names[obj], self.place_names[loc])
        if kind == KIND_SLIDE:
            return action_name("slide", names[obj], F[frame], self.place_names[loc])
        if kind == KIND_PASS:
            return PASS
        return action_name("move", names[obj], self.place_names[loc])


def _check_width(tables: Tables, k: int) -> None:
    bits = tables.vbits + tables.qbits + (k + 1).bit_length() + 1
    if bits > 62:
        raise TooLarge(f"the compiled solver packs a position into 62 bits; this game needs {bits} "
                         "(objects, places, DFA states, k); use --solver explicit")


# -- the graph, read back ------------------------------------------------------------------

class Graph:
    """The explored positions with their values, for strategies and plays."""

    def __init__(self, tables, keys, offsets, targets, units, codes, value, choice):
        self.tables, self.keys, self.offsets = tables, keys, offsets
        self.targets, self.units, self.codes = targets, units, codes
        self.value, self.choice = value, choice
        self.sorted = np.argsort(keys[1:], kind="stable") + 1
        self.sorted_keys = keys[self.sorted]

    def index(self, key: int) -> int | None:
        j = int(np.searchsorted(self.sorted_keys, key))
        if j < len(self.sorted_keys) and self.sorted_keys[j] == key:
            return int(self.sorted[j])
        return None

    def position(self, i: int) -> Position:
        t = self.tables
        key = int(self.keys[i]) >> 1
        key, h = divmod(key, t.k + 1)
        q = key & ((1 << t.qbits) - 1)
        return (t.unpack(key >> t.qbits), t.dfa_states[q], h)

    def edges(self, i: int) -> range:
        return range(int(self.offsets[i]), int(self.offsets[i + 1]))

    def _step(self, i: int, e: int, who: str) -> tuple[Step, int]:
        t = self.tables
        v = self.position(i)[0]
        name = t.action(self.codes[e])
        if name == PASS:
            return Step(who, PASS, 0.0, v), int(self.targets[e])
        legal = legal_robot_moves if who == "robot" else legal_human_moves
        after = next(mv.after for mv in legal(t.scene, v) if mv.action == name)
        cost = int(self.units[e]) * t.resolution if who == "robot" else 0.0
        return Step(who, name, cost, after), int(self.targets[e])

    def principal_play(self) -> tuple[Step, ...]:
        play, i = [], 1
        while i != 0:
            robot = int(self.keys[i]) & 1
            if robot:
                step, i = self._step(i, int(self.choice[i]), "robot")
            else:  # the reply of largest value, the pass (first) on ties
                e = max(self.edges(i), key=lambda x: int(self.value[self.targets[x]]))
                step, i = self._step(i, e, "human")
            if step.action != PASS:
                play.append(step)
        return tuple(play)

    def counter_play(self) -> tuple[Step, ...]:
        play, i, seen = [], 1, set()
        while i not in seen:
            seen.add(i)
            robot = int(self.keys[i]) & 1
            edges = list(self.edges(i))
            if robot:
                if not edges:
                    break
                e = min(edges, key=lambda x: int(self.units[x]))
                step, i = self._step(i, e, "robot")
            else:
                e = next(x for x in edges if self.value[self.targets[x]] >= INF)
                step, i = self._step(i, e, "human")
            if step.action != PASS:
                play.append(step)
            if i == 0:
                raise RuntimeError("internal error: the counter play reached a win")
        return tuple(play)


class CompiledStrategy(Mapping):
    """The robot's action at explored robot-turn positions of finite value."""

    def __init__(self, graph: Graph):
        self._graph = graph

    def __getitem__(self, position: Position) -> str:
        g, t = self._graph, self._graph.tables
        v, q, h = position
        qi = t.dfa_index.get(q)
        i = None if qi is None else g.index(t.key(t.pack(v), qi, h, robot=True))
        if i is None or g.value[i] >= INF:
            raise KeyError(position)
        return t.action(g.codes[int(g.choice[i])])

    def __iter__(self) -> Iterator[Position]:
        g = self._graph
        return iter([g.position(i) for i in range(1, len(g.keys))
                     if int(g.keys[i]) & 1 and g.value[i] < INF])

    def __len__(self) -> int:
        g = self._graph
        return int(sum(1 for i in range(1, len(g.keys)) if int(g.keys[i]) & 1 and g.value[i] < INF))


# -- kernels ---------------------------------------------------------------------------------

@njit(cache=True)
def _letter(x, n, pb, atom_kind, atom_mask, atom_place, atoms):
    pmask = (1 << pb) - 1
    bits = 0
    for j in range(atoms):
        kind = atom_kind[j]
        holds = False
        if kind == 0 or kind == 1:  # at(tag, place), holding(tag) (the hand is a place)
            for i in range(n):
                if atom_mask[j] >> i & 1 and ((x >> (i * pb)) & pmask) == atom_place[j]:
                    holds = True
                    break
        else:
            for i in range(n):
                if ((x >> (i * pb)) & pmask) == atom_place[j]:
                    holds = True
                    break
            if kind == 3:
                holds = not holds
        if holds:
            bits |= 1 << j
    return bits


@njit(cache=True)
def _canon(x, n, m, F, pb, eb, class_members, class_offsets, place_rank, rank_place):
    """The canonical state of x's orbit: in each class, the members' (place,
    frame aimed at) sorted by rank and handed out in member order."""
    classes = len(class_offsets) - 1
    if classes == 0:
        return x
    pmask = (1 << pb) - 1
    eshift = n * pb
    ee = (x >> eshift) & ((1 << eb) - 1)
    holder, frame = -1, -1
    if ee > m:
        holder = (ee - 1 - m) // F
        frame = (ee - 1 - m) % F
    new_ee = ee
    out = x
    desc = np.empty(n, np.int64)
    for c in range(classes):
        lo, hi = class_offsets[c], class_offsets[c + 1]
        size = hi - lo
        for j in range(size):
            i = class_members[lo + j]
            d = place_rank[(x >> (i * pb)) & pmask] * (F + 1)
            if i == holder:
                d += 1 + frame
            desc[j] = d
        for a in range(1, size):  # insertion sort
            key = desc[a]
            b = a - 1
            while b >= 0 and desc[b] > key:
                desc[b + 1] = desc[b]
                b -= 1
            desc[b + 1] = key
        for j in range(size):
            i = class_members[lo + j]
            place = rank_place[desc[j] // (F + 1)]
            out = (out & ~(pmask << (i * pb))) | (place << (i * pb))
            f = desc[j] % (F + 1)
            if f > 0:
                new_ee = 1 + m + i * F + (f - 1)
    return (out & ~(((1 << eb) - 1) << eshift)) | (new_ee << eshift)


@njit(cache=True)
def _free_for(at, n, m, i, samples_mask):
    """The places that count as free for a move serving object i (a mask over L ∪ E)."""
    occupied = 0
    else_other = False
    for j in range(n):
        if j != i:
            if at[j] < m:
                occupied |= 1 << at[j]
            elif at[j] == m:
                else_other = True
    free = ((1 << m) - 1) & ~occupied
    if not else_other:
        free |= samples_mask
    return free


@njit(cache=True)
def _rule_min(start, count, free, rule_free, rule_units):
    best = INF
    for r in range(start, start + count):
        if (rule_free[r] & ~free) == 0 and rule_units[r] < best:
            best = rule_units[r]
    return best


@njit(cache=True)
def _motion(mode, S, slen, T, tlen, free, rule_start, rule_count, rule_free, rule_units):
    """max over s in S[:slen], t in T[:tlen] of the cheapest satisfied rule (0 when s = t)."""
    if slen == 0 or tlen == 0:
        return INF
    worst = 0
    for a in range(slen):
        s = S[a]
        for b in range(tlen):
            t = T[b]
            if s == t:
                continue
            c = _rule_min(rule_start[mode, s, t], rule_count[mode, s, t], free, rule_free, rule_units)
            if c > worst:
                worst = c
    return worst


@njit(cache=True)
def _code(kind, obj, frame, loc, n, F, m):
    return ((kind * (n + 1) + obj) * (F + 1) + frame) * (m + 2) + loc


@njit(cache=True)
def _slot(key, bits):
    return np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(64 - bits))


@njit(cache=True)
def _find(table, bits, key):
    """The index stored with `key` in the hash table, -1 if absent (the key
    sits next to its index: one cache line per probe)."""
    mask = (1 << bits) - 1
    a = _slot(key, bits)
    while True:
        k = table[a, 0]
        if k == key:
            return table[a, 1]
        if k < 0:
            return -1
        a = (a + 1) & mask


@njit(cache=True)
def _insert(table, bits, key, index):
    mask = (1 << bits) - 1
    a = _slot(key, bits)
    while table[a, 0] >= 0:
        a = (a + 1) & mask
    table[a, 0] = key
    table[a, 1] = index


@njit(cache=True)
def _grow(a, size):
    b = np.empty(size, a.dtype)
    b[:len(a)] = a
    return b


@njit(cache=True)
def _explore(start, n, m, F, pb, eb, gb, qbits, k, anchor_at, anchor_count, home_starts, samples_mask,
             rule_start, rule_count, rule_free, rule_units, slide_start, slide_count, is_grasp,
             grab_units, drop_units, atom_kind, atom_mask, atom_place, atoms, trans, accepting,
             class_members, class_offsets, place_rank, rank_place):
    """Breadth-first from `start` (index 1; WIN is 0): packed keys and the
    edges of each position in CSR form (targets, units, action codes)."""
    pmask = (1 << pb) - 1
    eshift = n * pb
    emask = (1 << eb) - 1
    gshift = eshift + eb
    qmask = (1 << qbits) - 1
    keys = np.empty(1 << 16, np.int64)
    offsets = np.zeros((1 << 16) + 1, np.int64)
    targets = np.empty(1 << 18, np.int32)
    units = np.empty(1 << 18, np.int32)
    codes = np.empty(1 << 18, np.int32)
    bits = 17
    table = np.full((1 << bits, 2), -1, np.int64)  # open addressing: (key, index), -1 empty
    keys[0] = -1
    keys[1] = start
    _insert(table, bits, start, 1)
    count = 2
    ne = 0
    at = np.empty(n, np.int64)
    S = np.empty(len(home_starts) + anchor_at.shape[2], np.int64)
    T = np.empty(anchor_at.shape[2], np.int64)
    # moves of one position: (after state, units, code)
    mv_after = np.empty(4 * (n * (F + m + 2) + m + 2), np.int64)
    mv_units = np.empty(len(mv_after), np.int64)
    mv_code = np.empty(len(mv_after), np.int64)
    i = 1
    while i < count:
        key = keys[i]
        robot = key & 1
        rest = key >> 1
        h = rest % (k + 1)
        rest //= (k + 1)
        q = rest & qmask
        x = rest >> qbits
        for j in range(n):
            at[j] = (x >> (j * pb)) & pmask
        ee = (x >> eshift) & emask
        grip = (x >> gshift) & ((1 << gb) - 1)
        occupied = 0
        held = -1
        for j in range(n):
            if at[j] < m:
                occupied |= 1 << at[j]
            elif at[j] == m + 1:
                held = j
        nm = 0
        if robot:
            # the anchors v may stand for
            if grip != 0 or ee > m:
                if grip != 0:
                    place = m if ee == 0 else ee - 1
                    f = grip - 1
                else:
                    place = at[(ee - 1 - m) // F]
                    f = (ee - 1 - m) % F
                slen = anchor_count[place, f]
                for a in range(slen):
                    S[a] = anchor_at[place, f, a]
            else:
                slen = len(home_starts)
                for a in range(slen):
                    S[a] = home_starts[a]
            if held < 0:
                for o in range(n):
                    free = _free_for(at, n, m, o, samples_mask)
                    for f in range(F):
                        aim = 1 + m + o * F + f
                        if ee == aim:
                            continue
                        tlen = anchor_count[at[o], f]
                        for a in range(tlen):
                            T[a] = anchor_at[at[o], f, a]
                        c = _motion(0, S, slen, T, tlen, free, rule_start, rule_count, rule_free, rule_units)
                        if c < INF:
                            mv_after[nm] = (x & ~(emask << eshift)) | (aim << eshift)
                            mv_units[nm] = c
                            mv_code[nm] = _code(0, o, f, 0, n, F, m)
                            nm += 1
                if ee > m:
                    o = (ee - 1 - m) // F
                    f = (ee - 1 - m) % F
                    if is_grasp[f]:
                        if grab_units < INF:
                            y = (x & ~(pmask << (o * pb))) | ((m + 1) << (o * pb))
                            spot = 1 + at[o] if at[o] < m else 0
                            y = (y & ~(emask << eshift)) | (spot << eshift)
                            y |= (1 + f) << gshift
                            mv_after[nm] = y
                            mv_units[nm] = grab_units
                            mv_code[nm] = _code(1, o, f, 0, n, F, m)
                            nm += 1
                    elif at[o] < m:
                        free = _free_for(at, n, m, o, samples_mask)
                        for l in range(m):
                            if occupied >> l & 1:
                                continue
                            c = _rule_min(slide_start[f, at[o], l], slide_count[f, at[o], l], free,
                                          rule_free, rule_units)
                            if c < INF:
                                mv_after[nm] = (x & ~(pmask << (o * pb))) | (l << (o * pb))
                                mv_units[nm] = c
                                mv_code[nm] = _code(4, o, f, l, n, F, m)
                                nm += 1
            else:
                o = held
                g = grip - 1
                free = _free_for(at, n, m, o, samples_mask)
                mode = 1 + o * F + g
                for l in range(m):
                    if occupied >> l & 1 or ee == 1 + l:
                        continue
                    T[0] = anchor_at[l, g, 0]
                    c = _motion(mode, S, slen, T, 1, free, rule_start, rule_count, rule_free, rule_units)
                    if c < INF:
                        mv_after[nm] = (x & ~(emask << eshift)) | ((1 + l) << eshift)
                        mv_units[nm] = c
                        mv_code[nm] = _code(2, o, g, l, n, F, m)
                        nm += 1
                if 1 <= ee <= m and not (occupied >> (ee - 1) & 1) and drop_units < INF:
                    y = (x & ~(pmask << (o * pb))) | ((ee - 1) << (o * pb))
                    y &= ~(((1 << gb) - 1) << gshift)
                    y = (y & ~(emask << eshift)) | ((1 + m + o * F + g) << eshift)
                    mv_after[nm] = y
                    mv_units[nm] = drop_units
                    mv_code[nm] = _code(3, o, g, ee - 1, n, F, m)
                    nm += 1
        else:
            mv_after[0] = x
            mv_units[0] = 0
            mv_code[0] = _code(5, 0, 0, 0, n, F, m)
            nm = 1
            if h > 0:
                aligned = ee - 1 if grip != 0 and 1 <= ee <= m else -1
                for o in range(n):
                    if at[o] == m + 1:
                        continue
                    aimed = ee > m and (ee - 1 - m) // F == o
                    for t in range(m + 1):
                        if t < m and (occupied >> t & 1 or t == aligned):
                            continue
                        y = (x & ~(pmask << (o * pb))) | (t << (o * pb))
                        if aimed:
                            y &= ~(emask << eshift)
                        mv_after[nm] = y
                        mv_units[nm] = 0
                        mv_code[nm] = _code(6, o, 0, t, n, F, m)
                        nm += 1
        if ne + nm > len(targets):
            size = 2 * (ne + nm)
            targets = _grow(targets, size)
            units = _grow(units, size)
            codes = _grow(codes, size)
        for e in range(nm):
            w = mv_after[e]
            if not robot and e == 0:  # the pass: the robot's turn at the same position
                succ = ((x << qbits | q) * (k + 1) + h) * 2 + 1
            else:
                w = _canon(w, n, m, F, pb, eb, class_members, class_offsets, place_rank, rank_place)
                q2 = trans[q, _letter(w, n, pb, atom_kind, atom_mask, atom_place, atoms)]
                if accepting[q2]:
                    succ = -1
                elif robot:
                    succ = ((w << qbits | q2) * (k + 1) + h) * 2
                else:
                    succ = ((w << qbits | q2) * (k + 1) + h - 1) * 2 + 1
            if succ < 0:
                j = 0
            else:
                j = _find(table, bits, succ)
                if j < 0:
                    j = count
                    if count == len(keys):
                        keys = _grow(keys, 2 * count)
                        offsets = _grow(offsets, 2 * count + 1)
                    keys[count] = succ
                    count += 1
                    if 2 * count > len(table):
                        bits += 1
                        table = np.full((1 << bits, 2), -1, np.int64)
                        for r in range(1, count):
                            _insert(table, bits, keys[r], r)
                    else:
                        _insert(table, bits, succ, j)
            targets[ne] = j
            units[ne] = mv_units[e]
            codes[ne] = mv_code[e]
            ne += 1
        offsets[i + 1] = ne
        i += 1
    offsets[1] = 0
    return keys[:count].copy(), offsets[:count + 1].copy(), targets[:ne].copy(), units[:ne].copy(), codes[:ne].copy()


@njit(cache=True)
def _dijkstra(keys, offsets, targets, units):
    """Values (INF: never settled) and, at robot positions, the chosen edge.

    Dijkstra's algorithm for min-cost reachability games (solvers/explicit.py)
    with a bucket queue (Dial's): edge costs are small integers, so the
    positions waiting to settle are kept in a ring of max-cost + 1 buckets."""
    N = len(keys)
    E = len(targets)
    indeg = np.zeros(N + 1, np.int64)
    for e in range(E):
        indeg[targets[e] + 1] += 1
    for j in range(N):
        indeg[j + 1] += indeg[j]
    pred_edge = np.empty(E, np.int64)  # edges into each position, grouped by target
    fill = indeg[:N].copy()
    for e in range(E):
        t = targets[e]
        pred_edge[fill[t]] = e
        fill[t] += 1
    source = np.empty(E, np.int32)
    for i in range(N):
        for e in range(offsets[i], offsets[i + 1]):
            source[e] = i
    waiting = np.empty(N, np.int64)
    for i in range(N):
        waiting[i] = offsets[i + 1] - offsets[i]
    best = np.full(N, INF, np.int64)
    best_edge = np.full(N, -1, np.int64)
    value = np.full(N, INF, np.int64)
    choice = np.full(N, -1, np.int64)
    C = 1
    for e in range(E):
        if units[e] + 1 > C:
            C = units[e] + 1
    head = np.full(C, -1, np.int64)
    entry_node = np.empty(N + 1024, np.int64)
    entry_dist = np.empty(N + 1024, np.int64)
    entry_next = np.empty(N + 1024, np.int64)
    used = 0
    pending = 0
    # (0, WIN)
    entry_node[0] = 0
    entry_dist[0] = 0
    entry_next[0] = -1
    head[0] = 0
    used = 1
    pending = 1
    d = 0
    while pending > 0:
        b = d % C
        x = head[b]
        if x < 0:
            d += 1
            continue
        head[b] = entry_next[x]
        pending -= 1
        j = entry_node[x]
        if value[j] < INF or entry_dist[x] != d:
            continue  # settled already, or a stale entry
        value[j] = d
        if j != 0 and keys[j] & 1:
            choice[j] = best_edge[j]
        for p in range(indeg[j], indeg[j + 1]):
            e = pred_edge[p]
            i = source[e]
            if value[i] < INF:
                continue
            nd = -1
            if keys[i] & 1:
                cand = d + units[e]
                if cand < best[i]:
                    best[i] = cand
                    best_edge[i] = e
                    nd = cand
            else:
                waiting[i] -= 1
                if waiting[i] == 0:
                    nd = d
            if nd >= 0:
                if used == len(entry_node):
                    entry_node = _grow(entry_node, 2 * used)
                    entry_dist = _grow(entry_dist, 2 * used)
                    entry_next = _grow(entry_next, 2 * used)
                entry_node[used] = i
                entry_dist[used] = nd
                entry_next[used] = head[nd % C]
                head[nd % C] = used
                used += 1
                pending += 1
    return value, choice
