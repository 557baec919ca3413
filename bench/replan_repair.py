"""A bound D+ on the rise of the no-human value V_0 over one human move, from the costmap
alone (no position enumerated): the repair argument of bench/results/game-notes.md ("A
repair bound D+ from the costmap"), where each case's plan and its proof are written out.

    python bench/replan_repair.py N M [SEED ...]     D+ and its cases on pattern_scene(N, M, 3, SEED)

Per motion pair (mode, s, t): U = the least cost of a rule with no condition (F empty: holds
in every state; inf when there is none), L = the least cost of any rule (no state pays
less); 0 when s = t.  A case's bound is a sum of U's for the repair plan's motions, grab and
drop, minus L's (or shortest paths over L's) for what p's own plan pays and no longer needs.
Every case is a maximum over the objects (one per set of objects with the same carrying
rules), grasps and places it names; C4d's swap also over the sets of n - 2 places the other
objects can stand on, with each motion costed exactly for that occupancy.  Scenes with contacts (slides), and costmaps where an Else sample is a condition of a
rule, are refused (the postponing cases assume an object at Else blocks nothing).

Case names (x = where the moved object o was, t = where the human put it):
  C1  x in L, t = Else, hand aimed at o                 restore o, then p itself
  C2  x in L, t = Else, any other hand                  p's plan, o fetched where the plan met it
  C3  x = Else, t = Else, hand aimed at o               aim again
  C4a x, t in L, hand empty at Else or aimed at o       restore o
  C4b x, t in L, hand aimed at another object at y      restore o, aim again at y
  C4c x, t in L, holding at a location e                put down at e, restore o, pick up again
  C4d x, t in L, holding at Else                        p's plan to its drop, then C4b
  C4d swap  the same, p's plan dropping at t             park the held object, restore o, carry on
  C5  x = Else, t in L                                  NOT BOUNDED: conditional (see the notes)
"""

from __future__ import annotations

import itertools
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.abstraction import anchors, costmap_of  # noqa: E402
from symsynth.scene.model import ELSE, EMPTY  # noqa: E402

INF = math.inf


class Tables:
    """U, L and shortest L-paths of one scene's costmap, with the scene's places."""

    def __init__(self, scene):
        if scene.contacts:
            raise ValueError("scenes with contacts (slides) are not covered by this bound")
        self.scene, self.cm = scene, costmap_of(scene)
        self.E = set(scene.else_samples)
        if any(r.free & self.E for r in self.cm.all_rules()):
            raise ValueError("a rule asks for an Else sample to be free: C2's postponing does not hold")
        self.L = list(scene.locations)
        self.A = tuple(scene.present_anchors)
        self.grab, self.drop = scene.grab_cost, scene.drop_cost
        self._paths: dict[str, dict] = {}
        self._memo: dict = {}
        self._names: dict = {}

    def U(self, mode, S, T):
        """The most a motion from S to T can cost, in any state."""
        return max(self._pair(mode, s, t, upper=True) for s in S for t in T)

    def Lo(self, mode, S, T):
        """The least a motion from S to T can cost: max over s, t of the least rule."""
        return max(self._pair(mode, s, t, upper=False) for s in S for t in T)

    def _pair(self, mode, s, t, upper):
        if s == t:
            return 0
        rules = self.cm.rules(mode, s, t)
        costs = [r.cost for r in rules if not upper or not r.free]
        return min(costs, default=INF)

    def C(self, mode, S, T, occupied):
        """A motion's cost when exactly `occupied` (locations) hold other objects."""
        return max(self._given(mode, s, t, frozenset(occupied)) for s in S for t in T)

    def _given(self, mode, s, t, occupied):
        if s == t:
            return 0
        key = (mode, s, t, occupied & self._named(mode, s, t))
        if key not in self._memo:
            self._memo[key] = min((r.cost for r in self.cm.rules(mode, s, t) if not r.free & occupied),
                                  default=INF)
        return self._memo[key]

    def _named(self, mode, s, t):
        """The places some rule of the pair asks to be free."""
        key = (mode, s, t)
        if key not in self._names:
            self._names[key] = frozenset().union(*(r.free for r in self.cm.rules(mode, s, t)))
        return self._names[key]

    def kinds(self):
        """One object per set of objects whose carrying modes have the same rules (two of a
        set when it is the only one: the cases need two objects), so that the cases need not
        repeat the same numbers for every object."""
        seen = {}
        for o in self.scene.object_names:
            sig = tuple((s, t, tuple(sorted((tuple(sorted(x.free)), x.cost) for x in r)), mode.split("/")[1])
                        for (mode, s, t), r in sorted(self.cm.motions.items()) if mode.split("/")[0] == o)
            seen.setdefault(sig, []).append(o)
        kept = [os[0] for os in seen.values()]
        if len(kept) == 1 and len(seen[next(iter(seen))]) > 1:
            kept.append(seen[next(iter(seen))][1])
        return kept

    def path(self, mode, s, t):
        """The least sum of least rules over transfers from anchor s to anchor t."""
        if mode not in self._paths:
            nodes = sorted({a for a in self.A if a != "home"})
            d = {(a, b): self._pair(mode, a, b, upper=False) for a in nodes for b in nodes}
            for k, i, j in itertools.product(nodes, nodes, nodes):
                if d[i, k] + d[k, j] < d[i, j]:
                    d[i, j] = d[i, k] + d[k, j]
            self._paths[mode] = d
        return self._paths[mode][s, t]

    def at(self, place, g):
        return anchors(self.scene, place, g)


def cases(tb: Tables) -> dict[str, tuple[float, tuple]]:
    """Every case's bound and the instance (object, grasp, places) that attains it."""
    out: dict[str, tuple[float, tuple]] = {}

    def note(name, value, where):
        if value > out.get(name, (-INF,))[0]:
            out[name] = (value, where)

    sc, L, A, G, D = tb.scene, tb.L, tb.A, tb.grab, tb.drop
    grasps = sc.grasps
    objects = tb.kinds()
    for o, g in itertools.product(objects, grasps):
        mo = f"{o}/{g}"
        Eg = tb.at(ELSE, g)
        for x in L:
            X = tb.at(x, g)
            fetch_back = G + tb.U(mo, Eg, X) + D  # grab at Else, carry to x, drop
            note("C1", tb.U(EMPTY, A, Eg) + fetch_back, (o, g, x))
            _c2(tb, note, o, g, x, X, Eg, mo, fetch_back)
            for t in L:
                if t != x:
                    _c4(tb, note, o, g, x, t, mo, objects)
        note("C3", tb.U(EMPTY, A, Eg), (o, g))
        for t in L:
            _c5(tb, note, o, g, t, mo)
    return out


def _c2(tb, note, o, g, x, X, Eg, mo, fetch_back):
    """x in L, t = Else, not aimed at o: p's plan runs unchanged until it first aims at o (then
    from Else instead of x, and o carried back to x: P2), or to its end without touching o
    (then o fetched from Else: P1; the plan's last action is a drop, so it ends aimed at a
    location)."""
    sc = tb.scene
    for l, g2 in itertools.product(tb.L, sc.grasps):
        if l != x:
            note("C2", tb.U(EMPTY, tb.at(l, g2), Eg) + fetch_back, (o, g, x, "P1 after", l))
    starts = [("Else", tb.A)] + [(y, tb.at(y, a)) for y in tb.L + [ELSE] if y != x for a in sc.preimages]
    for y, S in starts:
        note("C2", tb.U(EMPTY, S, Eg) - tb.Lo(EMPTY, S, X) + fetch_back, (o, g, x, "P2 from", y))


def _c4(tb, note, o, g, x, t, mo, objects):
    """x, t in L: restore o from t to x, with what the hand must do around it."""
    sc, G, D = tb.scene, tb.grab, tb.drop
    X, Tt = tb.at(x, g), tb.at(t, g)
    back = G + tb.U(mo, Tt, X) + D  # grab at t, carry to x, drop
    note("C4a", tb.U(EMPTY, tb.A, Tt) + back, (o, g, x, t))
    for y, a in itertools.product(tb.L + [ELSE], sc.preimages):
        if y in (x, t):
            continue
        Y = tb.at(y, a)
        if y != ELSE:  # aim again at y afterwards
            note("C4b", tb.U(EMPTY, Y, Tt) + back + tb.U(EMPTY, X, Y), (o, g, x, t, "aimed at", y))
            continue
        # aimed at o' at Else: p's plan either grabs o' next (then it holds o' at Else: C4d,
        # counted there) or transits from Y to some T: restore o first, then transit from x to T
        targets = [tb.at(l, a2) for l in tb.L if l != t for a2 in sc.preimages]
        targets += [tb.at(ELSE, a2) for a2 in sc.preimages]
        away = max(tb.U(EMPTY, X, T) - tb.Lo(EMPTY, Y, T) for T in targets)
        note("C4b", tb.U(EMPTY, Y, Tt) + back + away, (o, g, x, t, "aimed at Else, plan transits"))
    for oh, gh in itertools.product(objects, sc.grasps):
        if oh == o:
            continue
        mh = f"{oh}/{gh}"
        for e in tb.L:
            if e in (x, t):
                continue
            Ye = tb.at(e, gh)
            note("C4c", D + tb.U(EMPTY, Ye, Tt) + back + tb.U(EMPTY, X, Ye) + G, (o, g, x, t, oh, "at", e))
        _c4d(tb, note, o, g, x, t, mo, oh, gh, mh, back)


def _c4d(tb, note, o, g, x, t, mo, oh, gh, mh, back):
    """Holding oh at Else: carry it to p's next drop ld and drop there, then C4b aimed at oh
    at ld; when ld = t, put oh down at a free f, restore o, and carry oh on to t (`swap_worst`)."""
    Eh = tb.at(ELSE, gh)
    X, Tt = tb.at(x, g), tb.at(t, g)
    for ld in tb.L:
        if ld in (x, t):
            continue
        Ld = tb.at(ld, gh)
        paid = max(tb.path(mh, e, Ld[0]) for e in Eh)
        value = tb.U(mh, Eh, Ld) - paid + tb.U(EMPTY, Ld, Tt) + back + tb.U(EMPTY, X, Ld)
        note("C4d", value, (o, g, x, t, oh, "drop at", ld))
    bound, (others, f) = swap_worst(tb, mo, mh, g, gh, x, t)
    note("C4d swap", bound, (o, g, x, t, oh, "others on", others, "via", f))


def swap_worst(tb, mo, mh, g, gh, x, t):
    """C4d-swap for o (mode mo) moved from x to t while oh (mode mh) is held at Else: (bound,
    (the other objects' places, the parking place f)).  At most n - 2 other objects stand on
    L, on places S other than x and t; more of them only raise the costs and take parking
    places away, so every S of size n - 2 is tried, each motion costed exactly for S, and the
    robot parks oh at the best free f."""
    G, D = tb.grab, tb.drop
    Eh, X, Tt, T_h = tb.at(ELSE, gh), tb.at(x, g), tb.at(t, g), tb.at(t, gh)
    paid = max(tb.path(mh, e, T_h[0]) for e in Eh)
    rest = [l for l in tb.L if l not in (x, t)]
    worst = (-INF, (None, None))
    for S in itertools.combinations(rest, min(len(tb.scene.objects) - 2, len(rest))):
        occ = set(S)
        best = min(((tb.C(mh, Eh, tb.at(f, gh), occ | {t}) + D + tb.C(EMPTY, tb.at(f, gh), Tt, occ | {f})
                     + G + tb.C(mo, Tt, X, occ | {f}) + D + tb.C(EMPTY, X, tb.at(f, gh), occ | {x}) + G
                     + tb.C(mh, tb.at(f, gh), T_h, occ | {x}), f) for f in rest if f not in occ),
                   default=(INF, None))
        if best[0] > worst[0]:
            worst = (best[0], (S, best[1]))
    return worst[0] - paid, worst[1]


def _c5(tb, note, o, g, t, mo):
    """x = Else, t in L: NOT a sound bound.  What p's plan pays more when it fetches o from t
    instead of from Else, assuming its part before that neither uses t nor meets a rule that
    asks t to be free (the notes say why that cannot be assumed)."""
    sc = tb.scene
    Eg, Tt = tb.at(ELSE, g), tb.at(t, g)
    carry = max(tb.U(mo, Tt, tb.at(l, g)) - tb.Lo(mo, Eg, tb.at(l, g)) for l in tb.L if l != t)
    starts = [("Else", tb.A)] + [(y, tb.at(y, a)) for y in tb.L + [ELSE] if y != t for a in sc.preimages]
    for y, S in starts:
        note("C5 (conditional)", tb.U(EMPTY, S, Tt) - tb.Lo(EMPTY, S, Eg) + max(0, carry), (o, g, t, "from", y))
    note("C5 (conditional)", tb.U(EMPTY, tb.A, Tt) + max(0, carry), (o, g, t, "was aimed at o"))


SOUND = ("C1", "C2", "C3", "C4a", "C4b", "C4c", "C4d", "C4d swap")


def d_plus(scene) -> tuple[float, dict]:
    """(D+, every case's bound and where it is attained): D+ is the largest sound case."""
    found = cases(Tables(scene))
    return max(found[c][0] for c in SOUND if c in found), found


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    n, m = int(argv[0]), int(argv[1])
    for seed in [int(s) for s in argv[2:]] or [0]:
        bound, found = d_plus(pattern_scene(n, m, 3, seed))
        print(f"{n} x {m} seed {seed}: D+ = {bound}")
        for name in sorted(found):
            value, where = found[name]
            print(f"  {name:18} {value:6}  {where}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
