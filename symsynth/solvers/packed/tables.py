"""The compiled solver's game as integer tables (`Tables`), and a position
packed into one 64-bit integer.

- a position: each object's place (a location, Else or the hand) in a few
  bits, the end-effector (Else, a location, or an object's grasp or
  contact), the grip; a node's key adds the DFA state below (the layer
  says h);
- the costmap: per (mode, from anchor, to anchor) the rules' `free` sets as
  bit masks over L ∪ E with their costs in units, cheapest first, the same
  for slides;
- the task's DFA: a table `(q, letter) -> q'` over the letters of its atoms
  (a letter is a bit mask of the atoms that hold), and the letter as n
  table reads;
- interchangeable objects (`game.symmetry`): the classes and the ranks
  that order places as `Symmetry.canonical` does.

What the packing cannot hold raises `TooLarge`, naming the limit.
"""

from __future__ import annotations

import math

import numpy as np

from symsynth.automata.shared import dfa_of
from symsynth.game.abstraction import State, action_name, costmap_of, quantize
from symsynth.game.graph import PASS
from symsynth.game.solution import OutOfReach
from symsynth.game.symmetry import Symmetry
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND, HOME, Scene
from symsynth.scene.propositions import interpret_all
from symsynth.solvers.packed.kernels import (INF, KIND_DROP, KIND_GRAB, KIND_PASS, KIND_SLIDE, KIND_TRANSFER,
                                             KIND_TRANSIT, _canon, _code, _letter)

MAX_ATOMS = 16
#: The moves of this many nodes are generated at once, in parallel, before their new targets
#: are added in order (two buffers of BATCH x the most moves a node has, 8 bytes a move)
BATCH = 8192
#: The human's moves are kept (4 bytes each) while there are at most this many (2 GiB); a
#: larger game drops them and generates them again when solving (twice their exploring work:
#: sorting 8 x 12, 332 M human moves, solves in 10 s CPU with them kept, 23 s without)
HUMAN_MOVES_KEPT = 1 << 29
#: The most units one move may cost: the kernels add costs in 64-bit integers
#: with INF = 2^60, so sums of up to 2^20 moves stay exact below INF.
MAX_MOVE_UNITS = 1 << 40
#: The most locations and Else samples: the free places are a mask in a signed 64-bit integer
MAX_PLACES = 62


class TooLarge(OutOfReach):
    """The game does not fit the compiled solver's packing or tables."""


def _bits(count: int) -> int:
    return max(1, (count - 1).bit_length())


class Tables:
    """The scene, costmap, task and symmetry as integer arrays, and the packing."""

    def __init__(self, scene: Scene, formula: ast.Formula, resolution: float, symmetry: Symmetry | None,
                 k: int):
        """Every table the kernels read, for `formula` against a human with
        `k` moves on `scene` at `resolution`, reduced by `symmetry` (None:
        not reduced); `TooLarge` when the scene does not fit: more than
        `MAX_PLACES` locations and Else samples, a move beyond
        `MAX_MOVE_UNITS`, more than `MAX_ATOMS` task atoms."""
        self.scene, self.resolution, self.k = scene, resolution, k
        names, L, F = scene.object_names, scene.locations, scene.preimages
        places = len(L) + len(scene.else_samples)
        if places > MAX_PLACES:
            raise TooLarge(f"the compiled solver keeps the free places in a 64-bit mask, at most {MAX_PLACES} "
                           f"locations and Else samples; this scene has {places}; use --solver explicit")
        self.n, self.m, self.F = len(names), len(L), len(F)
        self.place_names = list(L) + [ELSE, HAND]
        self.place_of = {p: i for i, p in enumerate(self.place_names)}
        self.frame_of = {f: i for i, f in enumerate(F)}
        # packing: at fields, then ee, then grip
        self.pb = _bits(self.m + 2)
        self.ee_count = 1 + self.m + self.n * len(F)
        self.eb = _bits(self.ee_count)
        self.gb = _bits(len(F) + 1)
        self.vbits = self.n * self.pb + self.eb + self.gb
        self._anchors()
        self._rules()
        self._atoms(formula)
        self.dfa = dfa_of(formula)
        self._dfa_table()
        self.qbits = _bits(len(self.dfa_states))
        self._symmetry(symmetry)

    def _anchors(self) -> None:
        """Anchors by index (home, then x/a for x in L ∪ E), the anchors at each
        (place, frame), the start set at home, and the free-place bits."""
        scene, L, E, F, m = self.scene, self.scene.locations, self.scene.else_samples, self.scene.preimages, self.m
        self.anchors = [HOME] + [f"{x}/{a}" for x in list(L) + list(E) for a in F]
        self.aidx = aidx = {a: i for i, a in enumerate(self.anchors)}
        self.anchor_at = np.full((m + 1, len(F), max(1, len(E))), -1, np.int64)  # place (L or ELSE), frame
        self.anchor_count = np.zeros((m + 1, len(F)), np.int64)
        for f, a in enumerate(F):
            for l in range(m):
                self.anchor_at[l, f, 0] = aidx[f"{L[l]}/{a}"]
                self.anchor_count[l, f] = 1
            for j, e in enumerate(E):
                self.anchor_at[m, f, j] = aidx[f"{e}/{a}"]
            self.anchor_count[m, f] = len(E)
        self.home_starts = np.array([aidx[a] for a in scene.present_anchors], np.int64)  # semantics §5
        self.free_bit = {x: i for i, x in enumerate(list(L) + list(E))}
        self.samples_mask = np.int64(sum(1 << self.free_bit[e] for e in E))

    def _rules(self) -> None:
        """The costmap's motion and slide rules as masks and units (`_add_rules`),
        indexed by cell; grab and drop in units; the bits of a robot move's code."""
        scene, m, n, F, A = self.scene, self.m, self.n, self.scene.preimages, len(self.anchors)
        modes = {EMPTY: 0}
        for i, o in enumerate(scene.object_names):
            for f, a in enumerate(F):
                modes[f"{o}/{a}"] = 1 + i * len(F) + f
        self.rule_start = np.zeros((len(modes), A, A), np.int64)
        self.rule_count = np.zeros((len(modes), A, A), np.int64)
        free_list: list[int] = []  # each rule's free places, as bits
        unit_list: list[int | np.int64] = []  # each rule's cost in units (INF: none)
        costmap = costmap_of(scene)
        aidx = self.aidx
        for (mode, s, t), rules in costmap.motions.items():
            if mode not in modes or s not in aidx or t not in aidx:
                continue
            mi, si, ti = modes[mode], aidx[s], aidx[t]
            self.rule_start[mi, si, ti] = len(free_list)
            self.rule_count[mi, si, ti] = len(rules)
            self._add_rules(rules, free_list, unit_list)
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
            self._add_rules(rules, free_list, unit_list)
        self.rule_free = np.array(free_list or [0], np.int64)
        self.rule_units = np.array(unit_list or [0], np.int64)
        self.is_grasp = np.array([a in scene.grasps for a in F] or [False], np.bool_)
        self.grab_units = self._units(scene.grab_cost, "grab")
        self.drop_units = self._units(scene.drop_cost, "drop")
        # a robot move is stored as its target (32 bits) and units << code_bits | code (32 bits)
        self.code_bits = (_code(KIND_SLIDE, n, len(F), m + 1, n, len(F), m)).bit_length()
        units = [int(u) for u in (*unit_list, self.grab_units, self.drop_units) if u < INF]
        self.max_units = max(units, default=0)
        if self.max_units >= 1 << (31 - self.code_bits):
            raise TooLarge(f"the compiled solver stores a robot move's cost in {31 - self.code_bits} bits "
                           f"(below {1 << (31 - self.code_bits)} units of resolution {self.resolution}); this "
                           f"scene has a move of {self.max_units} units; use a coarser --resolution or "
                           "--solver explicit")

    def _units(self, cost: float, what: str) -> int:
        """A cost in units (INF: no such action); `TooLarge` past `MAX_MOVE_UNITS`."""
        if not math.isfinite(cost):
            return int(INF)
        units = quantize(cost, resolution=self.resolution)
        if units > MAX_MOVE_UNITS:
            raise TooLarge(f"a move ({what}) costs {units} units of resolution {self.resolution:g}; the "
                           "compiled solver adds costs in 64-bit integers and takes at most 2^40 units a "
                           "move; use --solver explicit (or a coarser --resolution)")
        return units

    def _atoms(self, formula: ast.Formula) -> None:
        """The task's atoms: the letter of a packed state as n table reads (the
        at/holding/occupied atoms object i makes true at place p, and the free
        atoms an object at p makes false)."""
        scene, n, m = self.scene, self.n, self.m
        props = interpret_all(formula, scene)
        self.atom_keys = list(props)
        if len(self.atom_keys) > MAX_ATOMS:
            raise TooLarge(f"the compiled solver takes tasks of at most {MAX_ATOMS} atoms, "
                           f"this one has {len(self.atom_keys)}; use --solver explicit")
        self.atom_at = np.zeros((n, m + 2), np.int64)
        self.free_at = np.zeros(m + 2, np.int64)
        for j, p in enumerate(props.values()):
            place = self.place_of[p.place]
            if p.kind == "free":
                self.free_at[place] |= 1 << j
            for i, spec in enumerate(scene.objects):
                if p.kind == "occupied" or (p.kind in ("at", "holding") and p.tag is not None
                                            and p.tag in spec.tags):
                    self.atom_at[i, place] |= 1 << j
        self.free_all = np.int64(sum(1 << j for j, p in enumerate(props.values()) if p.kind == "free"))

    def _symmetry(self, symmetry: Symmetry | None) -> None:
        """Classes of interchangeable objects, and the ranks that order places
        and frames as `Symmetry.canonical` does."""
        self.symmetry = symmetry
        classes = symmetry.classes if symmetry is not None else ()
        self.class_members = np.array([i for c in classes for i in c] or [0], np.int64)
        self.class_offsets = np.array([0] + list(np.cumsum([len(c) for c in classes])), np.int64)
        order = sorted(self.place_names)
        self.place_rank = np.array([order.index(p) for p in self.place_names], np.int64)
        self.rank_place = np.array([self.place_of[p] for p in order], np.int64)

    def _add_rules(self, rules, free_list, unit_list) -> None:
        """A (mode, from, to) cell's rules as masks and units, cheapest first (the
        kernel takes the first satisfied one)."""
        cells = [(quantize(r.cost, resolution=self.resolution) if math.isfinite(r.cost) else INF,
                  sum(1 << self.free_bit[x] for x in r.free if x in self.free_bit)) for r in rules]
        for units, free in sorted(cells, key=lambda cell: cell[0]):
            if units != INF and units > MAX_MOVE_UNITS:
                raise TooLarge(f"a move costs {units} units of resolution {self.resolution:g}; the compiled "
                               f"solver adds costs in 64-bit integers and takes at most 2^40 units a move; "
                               "use --solver explicit (or a coarser --resolution)")
            free_list.append(free)
            unit_list.append(units)

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
        eev: str | tuple[str, str]
        if ee == 0:
            eev = ELSE
        elif ee <= self.m:
            eev = self.place_names[ee - 1]
        else:
            o, f = divmod(ee - 1 - self.m, self.F)
            eev = (self.scene.object_names[o], self.scene.preimages[f])
        return State(at, None if grip == 0 else self.scene.preimages[grip - 1], eev)

    def canon(self, x: int) -> int:
        return int(_canon(np.int64(x), self.n, self.m, self.F, self.pb, self.eb, self.class_members,
                          self.class_offsets, self.place_rank, self.rank_place, np.empty(self.n, np.int64)))

    def step(self, q: int, x: int) -> int:
        return int(self.trans[q, _letter(np.int64(x), self.n, self.pb, self.atom_at, self.free_at,
                                          self.free_all)])

    def key(self, x: int, q: int) -> int:
        """A node's key: the packed state and the DFA state (the layer says h)."""
        return x << self.qbits | q

    def kernel_args(self, human_cap: int = HUMAN_MOVES_KEPT, batch: int = BATCH) -> tuple:
        """What `packed.explore.explore` reads after the start's key."""
        return (self.n, self.m, self.F, self.pb, self.eb, self.gb, self.qbits, self.k,
                self.anchor_at, self.anchor_count, self.home_starts, self.samples_mask,
                self.rule_start, self.rule_count, self.rule_free, self.rule_units,
                self.slide_start, self.slide_count, self.is_grasp, np.int64(self.grab_units),
                np.int64(self.drop_units), self.atom_at, self.free_at, self.free_all,
                self.trans, self.accepting, self.class_members,
                self.class_offsets, self.place_rank, self.rank_place, self.code_bits, human_cap, batch)

    def human_args(self) -> tuple:
        """What `_solve` needs to generate the human's moves again."""
        return (self.code_bits, self.n, self.m, self.F, self.pb, self.eb, self.gb, self.qbits,
                self.atom_at, self.free_at, self.free_all, self.trans, self.accepting,
                self.class_members, self.class_offsets, self.place_rank, self.rank_place)

    def units(self, move: int) -> int:
        """The cost in units of a robot move stored as `r_move`."""
        return int(move) >> self.code_bits

    def code(self, move: int) -> int:
        """The action code of a robot move stored as `r_move`."""
        return int(move) & ((1 << self.code_bits) - 1)

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


def check_width(tables: Tables, k: int) -> None:
    """`TooLarge` unless a node's key (position, DFA state, h) fits 62 bits and
    a node's moves can be counted in 16."""
    bits = tables.vbits + tables.qbits + (k + 1).bit_length() + 1
    if bits > 62:
        raise TooLarge(f"the compiled solver packs a position into 62 bits; this game needs {bits} "
                       "(objects, places, DFA states, k); use --solver explicit")
    moves = 4 * (tables.n * (tables.F + tables.m + 2) + tables.m + 2)  # the kernels' bound per node
    if moves >= 1 << 15:
        raise TooLarge(f"the compiled solver stores a chosen move in 16 bits, fewer than {1 << 15} "
                       f"moves per position; this scene may have up to {moves}; use --solver explicit")


