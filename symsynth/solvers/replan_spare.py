"""The spare-places strategy σ_Z and its question "B_k^Z(start) <= T?" (issue 32).

Z is a set of spare places: locations no costmap rule names in `free` and no
goal of the task names (`solvers.rise.spare_places`).  S_Z is the scene with
every carrying motion that ends at a place of Z removed
(`solvers.rise.without_drops_at`): the same objects, places and DFA, so its
packed states are the same integers (`same_packing` checks it).  V_0 is the
no-human value of the scene, V_0^Z that of S_Z (V_0 <= V_0^Z: a plan of S_Z
is one of the scene, at the same cost).

σ_Z, memoryless over (state, DFA state, moves left h): with h >= 1, the first
action of a least-cost plan of S_Z; with h = 0, of the scene (σ's action).
What it pays at most, as `solvers.replan`'s recursion with σ_Z's plans:

    B_0^Z(p) = V_0(p),
    B_h^Z(p) = V_0^Z(p) + max(0, max over the human turns w of σ_Z's plan
                              from p and the moves m there of B_{h-1}^Z(m w) - V_0^Z(w)),

a move that wins counting -V_0^Z(w).  `SpareBound` asks it as
`replan_budget.BudgetedBound` asks σ's: the same recursion, the plans and
V_0^Z from an oracle on S_Z, V_0 (h = 0) from an oracle on the scene, whose
memo answers the replies at h = 1 (`packed.replies._settle` with bases
V_0^Z at σ_Z's turns and σ_Z's actions as codes: a repair or σ_Z's plan
followed is a plan of the scene, so the certificates bound V_0).

The rise bound R (`solvers.rise.rise_bounds`): at a state w with a place of
Z available (no object there, no held object aligned with it), every human move m has V_0(m w) <= V_0^Z(w) + R.c5 when it puts an
object from Else onto a location (class C5), and V_0(m w) <= V_0^Z(w) +
R.other for every other move (D+, wherever w is).  Two shortcuts read it:

- a reply at h = 1 whose class bound is within its budget needs no
  certificate (`_by_class`); the turn's yes is kept for the class's rise
  (not the true one, which is smaller: still a bound, so sound);
- a child at h = 1 (a move at h = 2) with a place of Z available (free, and
  not under the held object) is certified
  without its V_0^Z, plan or replies when upper + R.total <= its budget,
  upper the bound on V_0^Z(child) that answered it at h = 2
  (`_exact_children`): σ_Z's plan from the child never puts anything on
  Z, so Z stays available at every turn of it, and B_1^Z(child) <= V_0^Z(child)
  + R.total.

Both only prove yeses that hold, so `within` stays exact for σ_Z.  σ_Z needs
a bound of the costmap that σ (`replan_budget`) does not: a looser T lets
more children through the second shortcut, so `certified_upper` asks near
1.10 times the lower end first (`SPARE_FIRST`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from symsynth.game.solution import Position
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.replan import NoHumanValue, ReplanningStrategy
from symsynth.solvers.replan_budget import BudgetedBound
from symsynth.solvers.rise import Rises, without_drops_at

if TYPE_CHECKING:
    from symsynth.solvers.andor import Memo
    from symsynth.solvers.packed.tables import Tables

#: The target `certified_upper` asks first in spare mode, as a share of the lower end
SPARE_FIRST = 1.10


def same_packing(a: Tables, b: Tables) -> bool:
    """Whether two games' tables pack states and number DFA states alike."""
    same = (a.n, a.m, a.F, a.pb, a.eb, a.gb, a.qbits, a.place_names, a.frame_of, a.dfa_index) == \
        (b.n, b.m, b.F, b.pb, b.eb, b.gb, b.qbits, b.place_names, b.frame_of, b.dfa_index)
    return same and all(np.array_equal(x, y) for x, y in ((a.trans, b.trans), (a.accepting, b.accepting),
                                                            (a.atom_at, b.atom_at), (a.free_at, b.free_at)))


class SpareBound(BudgetedBound):
    """"Does σ_Z pay at most T from the start?" (module doc), for k >= 1.
    `rises`: R (`solvers.rise.Rises`: the places Z, the bounds `other`, `c5`,
    `total` in units of `resolution`); `full`: an oracle on the scene (its memo may be a
    search's); `spare`: one on S_Z (made when None).  `shortcut` and
    `by_class` turn the two shortcuts off (tests compare)."""

    name = "σ_Z"

    def __init__(self, scene: Scene, formula: ast.Formula, k: int, rises: Rises, resolution: float = 1.0,
                 full: NoHumanValue | None = None, spare: NoHumanValue | None = None, *,
                 shortcut: bool = True, by_class: bool = True):
        if k < 1:
            raise ValueError("σ_Z differs from σ only with a human move left: k >= 1")
        if spare is None:
            spare = NoHumanValue(without_drops_at(scene, rises.spares), formula, resolution)
        self.full = full or NoHumanValue(scene, formula, resolution)
        if not same_packing(self.full.t, spare.t):
            raise ValueError("internal error: the scene without drops at the spare places packs states "
                             "otherwise than the scene")
        super().__init__(scene, formula, k, resolution, spare)
        self.rises, self.shortcut, self.class_bounds = rises, shortcut, by_class
        self._values0: dict[tuple[int, int], float] = {}
        t = self.t
        self._zmask = sum(1 << t.place_of[z] for z in rises.spares)
        self._shifts = np.arange(t.n, dtype=np.int64) * t.pb
        #: children at h = 1 certified by R, left exact; replies at h = 1 answered by their class
        self.children = np.zeros(2, np.int64)
        self.by_class = 0

    @property
    def strategy(self) -> SpareStrategy:
        """σ_Z, the strategy that `within` speaks of."""
        return SpareStrategy(self.oracle, self.full)

    def _memos(self) -> list[Memo]:
        return [self.memo, self.full.memo]

    def value_at(self, x: int, q: int, h: int) -> float:
        """V_0 (the scene's) with no move left, V_0^Z with some."""
        return self._value_on(self.full, self._values0, x, q) if h == 0 else self.value(x, q)

    def _memo_at(self, h: int) -> Memo:
        return self.full.memo if h == 1 else self.memo

    def _oracle_at(self, h: int) -> NoHumanValue:
        return self.full if h == 0 else self.oracle

    # -- the shortcuts ----------------------------------------------------------------------
    def _places(self, xs: np.ndarray) -> np.ndarray:
        """Each object's place in packed states xs (one row a state)."""
        return (xs[:, None] >> self._shifts[None, :]) & ((1 << self.t.pb) - 1)

    def _spare_available(self, xs: np.ndarray) -> np.ndarray:
        """Whether some place of Z is available in each packed state of xs: no
        object there, and no held object aligned with it (`solvers.rise`)."""
        t = self.t
        at = self._places(xs)
        taken = np.bitwise_or.reduce(np.where(at < t.m, np.left_shift(1, at), 0), axis=1)
        ee = (xs >> (t.n * t.pb)) & ((1 << t.eb) - 1)
        holding = (xs >> (t.n * t.pb + t.eb)) & ((1 << t.gb) - 1) != 0
        taken |= np.where(holding & (ee >= 1) & (ee <= t.m), np.left_shift(1, np.maximum(ee - 1, 0)), 0)
        return (taken & self._zmask) != self._zmask

    def _by_class(self, keys: np.ndarray, turn: np.ndarray, plan: tuple[np.ndarray, ...],
                  s: float) -> np.ndarray | None:
        """Per reply at h = 1, V_0^Z at its turn plus its class's R when that is
        within s of it (C5: with a place of Z available at the turn), else -1."""
        r = self.rises
        if not self.class_bounds or s < min(r.other, r.c5):
            return None
        xs, _, left = plan[:3]
        shift = self.memo.hb + self.t.qbits
        before, after = self._places(xs)[turn], self._places(np.maximum(keys, 0) >> shift)
        c5 = ((before == self.t.m) & (after < self.t.m)).any(axis=1)
        fits = np.where(c5, (s >= r.c5) & self._spare_available(xs)[turn], s >= r.other) & (keys >= 0)
        if not fits.any():
            return None
        self.by_class += int(fits.sum())
        rise = np.where(c5, r.c5, r.other)
        return np.where(fits, left[turn].astype(np.int64) + rise, -1)

    def _exact_children(self, keys: np.ndarray, turn: np.ndarray, left: np.ndarray, h: int, s: float,
                        upper: np.ndarray) -> list[tuple[float, int, int, int]]:
        """At h = 2, the children a place of Z available and upper + R.total within
        their budget certify are left out (module doc); the others' rises."""
        if h == 2:
            easy = (keys >= 0) & (upper + self.rises.total <= left[turn] + s) & self.shortcut
            easy[easy] = self._spare_available(keys[easy] >> (self.memo.hb + self.t.qbits))
            self.children += (int(easy.sum()), int((keys >= 0).sum() - easy.sum()))
            keys, turn = keys[~easy], turn[~easy]
        return self._rises(keys, turn, left, h - 1)


class SpareStrategy(ReplanningStrategy):
    """σ_Z as a strategy (Position -> action), computed when asked: S_Z's plan
    with a human move left, the scene's (σ's) with none."""

    def __init__(self, spare: NoHumanValue, full: NoHumanValue):
        super().__init__(spare)
        self._full = ReplanningStrategy(full)

    def __getitem__(self, position: Position) -> str:
        return self._full[position] if position[2] == 0 else super().__getitem__(position)
