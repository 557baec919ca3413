"""C5^Z: a bound on V_0(w') - V_0^Z(w) for the human moves of class C5, an object o taken from
Else onto a location t (w' the state after the move), at states w where a spare place z is
available (`solvers.rise`: no object at z, no held object aligned with z).  V_0 is the
no-human value of the scene S, V_0^Z that of S_Z (no carrying motion ends at a place of Z).
The style and the facts (M), (W), (H) are those of D+'s proof (bench/results/game-notes.md,
"The proof"); U, Lo and path as in `solvers.rise_costs`; G, D the grab and drop costs; X/a
the anchors of place X with grasp a, E/a those of Else; A every present anchor (the starts
of an empty hand at Else).  Costs are in the packed search's units, where the same argument
holds (that game has the same moves with every cost rounded up).

**Z stays available (K).**  Along a plan of S_Z from a state where z is available, z stays
so: no transfer ends at z (S_Z has no carrying motion there), so the hand is never aligned
with z unless it grabbed there, and nothing stands at z to be grabbed; a drop lands where
the hand is aligned.

**Fetching o from z instead of Else (F).**  Let u be a state with o at Else, z available, π
an optimal S_Z plan from u (when there is none the bound holds trivially), and u^z the state
u with o at z instead.
- (F1) u not aimed at o: V_0(u^z) <= V_0^Z(u) + fetch, where fetch is the largest over the
  start sets S of the transits towards o that π can make (A only when u's hand is empty at
  Else: `fetch_any`; else the anchors of another object at y in (L - z) ∪ Else) and the
  grasps a, of U(S, z/a) - min_a' Lo(S, E/a') + after_grab(a), and after_grab(a) is the
  largest over l in L - Z of U(o/a: z/a -> l/a) - Lo(o/a: E/a -> l/a).
  Proof.  By (W) and the task, π grabs o, so it transits to o first.  Before its first
  transit to o, every action of π is legal in the u^z-world and costs the same: the two
  worlds differ only at z and at Else, which no rule names; π never transfers to z nor drops
  there (K); ee is the same and not aimed at o.  A *visit* of π to o is a maximal run of
  transits to o (grasps a_1..a_k) from starts S; it ends with a grab or with a transit to
  another object's anchors T.
  - Ends with a transit to T: we leave the visit out (one transit S -> T, or none when T is
    where we are aimed) or make it to o at z; that costs at most min(U(S, T), U(S, z/a_1) +
    U(z/a_1, z/a_k) + U(z/a_k, T)), π paid at least Lo(S, E/a_1) + Lo(E/a_k, T).  The
    largest difference (`skip`) is checked to be <= 0 (else no bound: `c5_bound` gives inf),
    so visits without a grab cost us nothing more, and the worlds are related as before.
  - Ends with a grab: we transit S -> z/a_k, grab, and make π's next action, a transfer to
    some l (holding at Else only transfers; l not in Z), from z/a_k: l is free in both
    worlds, and after it the two states are equal.  The difference is the term above.
- (F2) u aimed at (o, a0) (o at Else), our world aimed at (o, g) at z:
  V_0(ours) <= V_0^Z(u) + Ψ(g), Ψ(g) the larger of: π's first visit ends with a grab:
  U(z/g, z/a) + after_grab(a); it ends with a transit to T: U(z/g, T) - Lo(E/a, T) + fetch
  (then F1 from a state aimed at another object).
- (Θ) u not aimed at o with hand empty and starts S, our world u^z but aimed at (o, g) at z.
  By π's first action: a transit to another object's anchors T: we go there from z/g,
  U(z/g, T) - Lo(S, T) + fetch (`away`); a transit to o: the visit ends with a grab
  (U(z/g, z/a) + after_grab(a) - min_a' Lo(S, E/a')) or with a transit to T (U(z/g, T) -
  min_a' Lo(S, E/a') - min_a Lo(E/a, T) + fetch) (`to_o`); a grab of the object aimed at:
  we first go back to S, U(z/g, S) + fetch (`back`, which fits every first action).

**The cases.**  The human puts o (at Else in w) on t (free in w, not aligned with a held
object).  The relocation (t not in Z): from the hand's starts S to o at t with a grasp g
the robot chooses, grab, carry to z, drop: reloc(S, g) = U(S, t/g) + G + U(o/g: t/g -> z/g) + D
(z is free and not where the hand is), leaving the hand aimed at (o, g) at z.  Each case
below is an inequality between the states u (o at Else) and u' (the same with o at t), so a
case can end in another: where π's first action is a choice, the bound is the largest over
π's choices of the least over the plans that fit it.
- t in Z (the relocation is nothing; z := t, available in w since the move was legal): u'
  = u^t, so F1 gives `fetch_any`; when w was aimed at o (the move sets ee to Else), transit
  to (o, g) at t and F2: min_g U(A, t/g) + Ψ(g).
- E1 hand empty at Else: reloc(A, g) + the least of fetch_any (by (M), our state costs at
  most u^z, whose hand is at Else, and F1) and the largest of Θ's away and to_o (π's first
  action from Else is a transit).
- E4 aimed at o (the move sets ee to Else): reloc(A, g) + Ψ(g).
- E2 aimed at another object o' at y (y in (L - z - t) ∪ Else, anchors S): after reloc(S, g),
  per π's first action: a transit (to o or not): the least of `back` and Θ's term; a grab
  of o': the least of `back` and following it (grab too; then o' is held where it stood,
  case H1 with e = y or H2, from π's state after its grab).
- H1 holding o_h at e in L (e is neither z nor t): drop at e, reloc(e/g_h, g), transit back
  to (o_h, g_h) at e, grab: that is u^z, then F1: D + reloc + U(z/g, e/g_h) + G + fetch.
- H2 holding o_h at Else: by (H) π carries o_h to its first drop l_d (not in Z), paying at
  least max_e path(e/g_h, l_d/g_h) and D.
  - l_d != t: carry o_h there directly and drop (l_d is free in our world too); that is π's
    state after its drop, with o at t, aimed at o_h at l_d: U(E/g_h, l_d/g_h) - paid + E2.
  - l_d = t (swap): carry o_h to a free f in L - t - z, drop, relocate o from t to z,
    transit back to o_h, grab, carry it to t: five motions at their U, two grabs and two
    drops, minus paid, + fetch (π's state after its drop with o at z).  When k <= n - 2 other
    objects stand on L - t - z, the robot has at least the (k + 1)-th cheapest f; when all n - 2
    do, no object but o is at Else, then or later (no robot action puts one there), so π's
    transits to o start at a location's anchors: fetch over those starts only (`fetch_on_L`).
C5^Z is the largest case over the objects (one or two of each set with the same carrying
rules), grasps, spare places z and places named; a grasp the robot chooses is a least."""

from __future__ import annotations

import itertools

from symsynth.scene.model import EMPTY
from symsynth.solvers.rise_costs import INF, Costs, less


class _Fetch:
    """The building blocks of the proof for one object o (kind) and one spare place z."""

    def __init__(self, tb: Costs, o: str, z: str, spares):
        self.tb, self.o, self.z = tb, o, z
        sc = tb.scene
        self.outside = [l for l in tb.L if l not in spares]  # where a plan of S_Z carries to
        others = [y for y in tb.L if y != z]
        self.targets = [tb.at(y, a) for y in others for a in sc.preimages] + [tb.Else(a) for a in sc.preimages]
        self.starts = [tb.A] + self.targets
        self.after_grab = {a: self._after_grab(a) for a in sc.grasps}
        self.skip = self._skip()
        self.fetch_any = max(self._fetch_from(S) for S in self.starts)  # Φ
        self.fetch = max(self._fetch_from(S) for S in self.targets)  # Φ': the hand not at Else
        on_L = [tb.at(y, a) for y in others for a in sc.preimages]
        self.fetch_on_L = max((self._fetch_from(S) for S in on_L), default=-INF)  # no other object at Else

    def _fetch_from(self, S) -> float:
        tb = self.tb
        return max(less(tb.U(EMPTY, S, tb.at(self.z, a)), self._to_else(S)) + self.after_grab[a]
                   for a in tb.scene.grasps)

    def _to_else(self, S) -> float:
        """The least the plan's first transit towards o at Else can cost from S."""
        return min(self.tb.Lo(EMPTY, S, self.tb.Else(a)) for a in self.tb.scene.preimages)

    def _after_grab(self, a: str) -> float:
        """Φ_T: the first transfer after the grab, from z instead of from Else."""
        tb, mo = self.tb, f"{self.o}/{a}"
        return max((less(tb.U(mo, tb.at(self.z, a), tb.at(l, a)), tb.Lo(mo, tb.Else(a), tb.at(l, a)))
                    for l in self.outside), default=-INF)

    def _skip(self) -> float:
        """The most a visit of the plan to o at Else that ends without a grab costs us more when
        we leave it out (or make it to o at z instead, whichever is cheaper)."""
        tb, pre = self.tb, self.tb.scene.preimages
        worst = -INF
        for S, T in itertools.product(self.starts, self.targets):
            direct = tb.U(EMPTY, S, T)
            for a, a2 in itertools.product(pre, pre):
                Za, Za2 = tb.at(self.z, a), tb.at(self.z, a2)
                ours = min(direct, tb.U(EMPTY, S, Za) + tb.U(EMPTY, Za, Za2) + tb.U(EMPTY, Za2, T))
                worst = max(worst, less(ours, tb.Lo(EMPTY, S, tb.Else(a)) + tb.Lo(EMPTY, tb.Else(a2), T)))
        return worst

    def back(self, g: str, S) -> float:
        """From (o, g) at z back to the anchors S, then the plan with o fetched from z."""
        return self.tb.U(EMPTY, self.tb.at(self.z, g), S) + self.fetch

    def away(self, g: str, S) -> float:
        """We are aimed at (o, g) at z, the plan's hand empty with starts S, and its first action
        a transit to another object (anchors T): we make it from z."""
        tb, Zg = self.tb, self.tb.at(self.z, g)
        return max(less(tb.U(EMPTY, Zg, T), tb.Lo(EMPTY, S, T)) for T in self.targets) + self.fetch

    def to_o(self, g: str, S) -> float:
        """The same, the plan's first action a transit to o at Else: it grabs o at the end of
        its visit (then we grab at z), or leaves to some T (then we go there from z)."""
        tb, Zg, first = self.tb, self.tb.at(self.z, g), self._to_else(S)
        grab = max(less(tb.U(EMPTY, Zg, tb.at(self.z, a)) + self.after_grab[a], first) for a in tb.scene.grasps)
        leave = max(less(tb.U(EMPTY, Zg, T), first + min(tb.Lo(EMPTY, tb.Else(a), T) for a in tb.scene.preimages))
                    for T in self.targets) + self.fetch
        return max(grab, leave)

    def aimed_at_o(self, g: str) -> float:
        """Ψ(g): we are aimed at (o, g) at z, the plan at o at Else."""
        tb, Zg = self.tb, self.tb.at(self.z, g)
        grab = max(tb.U(EMPTY, Zg, tb.at(self.z, a)) + self.after_grab[a] for a in tb.scene.grasps)
        away = max(less(tb.U(EMPTY, Zg, T), tb.Lo(EMPTY, tb.Else(a), T))
                   for T in self.targets for a in tb.scene.preimages) + self.fetch
        return max(grab, away)


def c5_cases(tb: Costs, spares) -> dict[str, tuple[float, tuple]]:
    """Every hand case's bound and where it is attained; "skip" is the condition the proof
    needs (<= 0)."""
    out: dict[str, tuple[float, tuple]] = {}

    def note(name, value, where):
        if value > out.get(name, (-INF,))[0]:
            out[name] = (value, where)

    objects = tb.kinds()
    for o, z in itertools.product(objects, spares):
        fz = _Fetch(tb, o, z, spares)
        note("skip", fz.skip, (o, z))
        note("fetch", fz.fetch_any, (o, z))
        for t in tb.L:
            if t not in spares:
                _moved(_Repair(tb, fz, t), note, objects)
        # t in Z: o stands on a spare place already (z = t)
        note("on Z, hand as it was", fz.fetch_any, (o, z))
        note("on Z, was aimed at o", min(tb.U(EMPTY, tb.A, tb.at(z, g)) + fz.aimed_at_o(g)
                                         for g in tb.scene.grasps), (o, z))
    return out


class _Repair:
    """The relocation of o from t (not in Z) to z, and the plans around it."""

    def __init__(self, tb: Costs, fz: _Fetch, t: str):
        self.tb, self.fz, self.o, self.z, self.t = tb, fz, fz.o, fz.z, t

    def reloc(self, S, g: str) -> float:
        """Transit from S to o at t, grab, carry to z, drop."""
        tb, o = self.tb, self.o
        return (tb.U(EMPTY, S, tb.at(self.t, g)) + tb.grab + tb.U(f"{o}/{g}", tb.at(self.t, g), tb.at(self.z, g))
                + tb.drop)

    def best(self, S, after) -> float:
        """The least over the relocation's grasp g of reloc + after(g)."""
        return min(self.reloc(S, g) + after(g) for g in self.tb.scene.grasps)


def _moved(rp: _Repair, note, objects) -> None:
    """o put on t, not a spare place: relocate it to z first (module doc, cases E and H)."""
    tb, fz, o, z, t = rp.tb, rp.fz, rp.o, rp.z, rp.t
    sc, G, D, A = tb.scene, tb.grab, tb.drop, tb.A
    where = (o, z, t)
    # via (M), or following the plan's first action (a transit from A, to o or not)
    e1 = rp.best(A, lambda g: min(fz.fetch_any, max(fz.away(g, A), fz.to_o(g, A))))
    note("E1 empty at Else", e1, where)
    note("E4 was aimed at o", rp.best(A, fz.aimed_at_o), where)
    held = {}
    for oh, gh in itertools.product(objects, sc.grasps):
        if oh == o:
            continue
        for e in tb.L:
            if e not in (z, t):
                Ye = tb.at(e, gh)
                held[oh, gh, e] = D + rp.best(Ye, lambda g: tb.U(EMPTY, tb.at(z, g), Ye) + G) + fz.fetch
                note("H1 holding at a location", held[oh, gh, e], where + (oh, e))
    aimed = {}
    for (oh, gh, y), h1 in held.items():
        aimed[oh, gh, y] = _aimed(rp, tb.at(y, gh), h1)
        note("E2 aimed at another", aimed[oh, gh, y], where + (oh, y))
    for oh, gh in itertools.product(objects, sc.grasps):
        if oh == o:
            continue
        mh, Eh = f"{oh}/{gh}", tb.Else(gh)
        h2 = -INF
        for ld in fz.outside:
            if ld != t:
                Ld = tb.at(ld, gh)
                paid = max(tb.path(mh, e, Ld[0]) for e in Eh)
                h2 = max(h2, less(tb.U(mh, Eh, Ld), paid) + aimed[oh, gh, ld])
        note("H2 holding at Else", h2, where + (oh,))
        swap = _swap(rp, oh, gh)
        note("H2 swap", swap[0], swap[1])
        note("E2 aimed at another", _aimed(rp, Eh, max(h2, swap[0])), where + (oh, "Else"))


def _aimed(rp: _Repair, S, follow: float) -> float:
    """Hand empty, aimed at another object o' (anchors S): by the plan's first action, the
    least of the plans that fit it.  `follow`: the bound when the plan grabs o' first and we
    grab it too (then o' is held where it stood: H1 or H2)."""
    fz = rp.fz
    back = rp.best(S, lambda g: fz.back(g, S))
    grab = min(follow, back)
    away = min(back, rp.best(S, lambda g: fz.away(g, S)))
    to_o = min(back, rp.best(S, lambda g: fz.to_o(g, S)))
    return max(grab, away, to_o)


def _swap(rp: _Repair, oh, gh) -> tuple[float, tuple]:
    """Holding oh at Else, the plan's drop at t: park oh at f, carry o from t to z, carry oh
    from f to t; k others on L may take the k cheapest places f (module doc)."""
    tb, o, z, t = rp.tb, rp.o, rp.z, rp.t
    G, D = tb.grab, tb.drop
    mh, Eh, Th = f"{oh}/{gh}", tb.Else(gh), tb.at(t, gh)
    paid = max(tb.path(mh, e, Th[0]) for e in Eh)
    plans = []
    for f in tb.L:
        if f in (t, z):
            continue
        F = tb.at(f, gh)
        plans.append((tb.U(mh, Eh, F) + D + rp.best(F, lambda g: tb.U(EMPTY, tb.at(z, g), F)) + G
                      + tb.U(mh, F, Th), f))
    plans.sort()
    others = len(tb.scene.objects) - 2
    where = (o, z, t, oh)
    if len(plans) <= others:
        return INF, where
    # k others on L leave the robot the (k + 1)-th cheapest f; all n - 2 of them on L leave no
    # object at Else but o, so the plan's later transits to o start at a location (fetch_on_L)
    worst = max((less(plans[k][0], paid) + (rp.fz.fetch_on_L if k == others else rp.fz.fetch), k)
                for k in range(others + 1))
    return worst[0], where + ("park at", plans[worst[1]][1])


def c5_bound(tb: Costs, spares) -> tuple[float, dict]:
    """(C5^Z, the cases): inf when the proof's condition on visits fails."""
    found = c5_cases(tb, spares)
    if found["skip"][0] > 0:
        return INF, found
    return max(v for name, (v, _) in found.items() if name not in ("skip", "fetch")), found
