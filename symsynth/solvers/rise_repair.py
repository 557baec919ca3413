"""D+: a bound on V_0(m w) - V_0(w) for every state w and every human move m but those of
class C5 (an object taken from Else onto a location), from the costmap alone.  The cases'
repair plans and their proof are in bench/results/game-notes.md ("A repair bound D+ from the
costmap", "The proof"); `solvers.rise` states the setting they need.

A case's bound is a sum of U's for the repair plan's motions, grab and drop, minus Lo's (or
least paths over Lo's) for what the plan it replaces pays and no longer needs, maximised over
the objects (one per class of identical carrying rules), grasps and places it names.

Case names (x = where the moved object o was, t = where the human put it):
  C1  x in L, t = Else, hand aimed at o                 restore o, then the plan itself
  C2  x in L, t = Else, any other hand                  the plan, o fetched where the plan met it
  C3  x = Else, t = Else, hand aimed at o               aim again
  C4a x, t in L, hand empty at Else or aimed at o       restore o
  C4b x, t in L, hand aimed at another object at y      restore o, aim again at y
  C4c x, t in L, holding at a location e                put down at e, restore o, pick up again
  C4d x, t in L, holding at Else                        the plan to its drop, then C4b
  C4d swap  the same, the plan dropping at t            park the held object, restore o, carry on

C4d swap (`swap_bound`) takes every motion at its U and lets the robot park at the (n - 1)-th
cheapest place f (other objects can take the n - 2 cheaper ones).  That is at least what the
game notes' exact-occupancy maximum gives (each motion's cost for a given occupancy is at most
its U, and among the places the others leave free the robot's best costs at most the
(n - 1)-th cheapest), and equal to it in the pattern family (153 at 8 x 12), at a fraction of
its time (it tried every set of n - 2 places: the whole script 3.1 s at 8 x 12, now 0.7 s)."""

from __future__ import annotations

import itertools

from symsynth.scene.model import ELSE, EMPTY
from symsynth.solvers.rise_costs import INF, Costs, less

SOUND = ("C1", "C2", "C3", "C4a", "C4b", "C4c", "C4d", "C4d swap")


def d_plus(costs: Costs) -> tuple[float, dict[str, tuple[float, tuple]]]:
    """(D+, every case's bound and the instance (object, grasp, places) that attains it)."""
    found = cases(costs)
    return max((found[c][0] for c in SOUND if c in found), default=-INF), found


def cases(tb: Costs) -> dict[str, tuple[float, tuple]]:
    """Every case's bound and where it is attained."""
    out: dict[str, tuple[float, tuple]] = {}

    def note(name, value, where):
        if value > out.get(name, (-INF,))[0]:
            out[name] = (value, where)

    objects = tb.kinds()
    for o, g in itertools.product(objects, tb.scene.grasps):
        mo, Eg = f"{o}/{g}", tb.Else(g)
        for x in tb.L:
            fetch_back = tb.grab + tb.U(mo, Eg, tb.at(x, g)) + tb.drop  # grab at Else, carry to x, drop
            note("C1", tb.U(EMPTY, tb.A, Eg) + fetch_back, (o, g, x))
            _c2(tb, note, o, g, x, fetch_back)
            for t in tb.L:
                if t != x:
                    _c4(tb, note, o, g, x, t, objects)
        note("C3", tb.U(EMPTY, tb.A, Eg), (o, g))
    return out


def _c2(tb: Costs, note, o, g, x, fetch_back) -> None:
    """x in L, t = Else, not aimed at o: the plan runs unchanged until it first aims at o (then
    from Else instead of x, and o carried back to x: P2), or to its end without touching o
    (then o fetched from Else: P1; the plan's last action is a drop, so it ends aimed at a
    location)."""
    sc, Eg, X = tb.scene, tb.Else(g), tb.at(x, g)
    for l, g2 in itertools.product(tb.L, sc.grasps):
        if l != x:
            note("C2", tb.U(EMPTY, tb.at(l, g2), Eg) + fetch_back, (o, g, x, "P1 after", l))
    starts = [("Else", tb.A)] + [(y, tb.at(y, a)) for y in tb.L + [ELSE] if y != x for a in sc.preimages]
    for y, S in starts:
        note("C2", less(tb.U(EMPTY, S, Eg), tb.Lo(EMPTY, S, X)) + fetch_back, (o, g, x, "P2 from", y))


def _c4(tb: Costs, note, o, g, x, t, objects) -> None:
    """x, t in L: restore o from t to x, with what the hand must do around it."""
    sc, G, D = tb.scene, tb.grab, tb.drop
    X, Tt = tb.at(x, g), tb.at(t, g)
    back = G + tb.U(f"{o}/{g}", Tt, X) + D  # grab at t, carry to x, drop
    note("C4a", tb.U(EMPTY, tb.A, Tt) + back, (o, g, x, t))
    for y, a in itertools.product(tb.L + [ELSE], sc.preimages):
        if y in (x, t):
            continue
        Y = tb.at(y, a)
        if y != ELSE:  # aim again at y afterwards
            note("C4b", tb.U(EMPTY, Y, Tt) + back + tb.U(EMPTY, X, Y), (o, g, x, t, "aimed at", y))
            continue
        # aimed at o' at Else: the plan either grabs o' next (then it holds o' at Else: C4d,
        # counted there) or transits from Y to some T: restore o first, then transit from x to T
        targets = [tb.at(l, a2) for l in tb.L if l != t for a2 in sc.preimages]
        targets += [tb.Else(a2) for a2 in sc.preimages]
        away = max(less(tb.U(EMPTY, X, T), tb.Lo(EMPTY, Y, T)) for T in targets)
        note("C4b", tb.U(EMPTY, Y, Tt) + back + away, (o, g, x, t, "aimed at Else, plan transits"))
    for oh, gh in itertools.product(objects, sc.grasps):
        if oh == o:
            continue
        for e in tb.L:
            if e in (x, t):
                continue
            Ye = tb.at(e, gh)
            note("C4c", D + tb.U(EMPTY, Ye, Tt) + back + tb.U(EMPTY, X, Ye) + G, (o, g, x, t, oh, "at", e))
        _c4d(tb, note, o, g, x, t, oh, gh, back)


def _c4d(tb: Costs, note, o, g, x, t, oh, gh, back) -> None:
    """Holding oh at Else: carry it to the plan's next drop ld and drop there, then C4b aimed
    at oh at ld; when ld = t, put oh down at a free f, restore o, and carry oh on to t."""
    mh, Eh = f"{oh}/{gh}", tb.Else(gh)
    X, Tt = tb.at(x, g), tb.at(t, g)
    for ld in tb.L:
        if ld in (x, t):
            continue
        Ld = tb.at(ld, gh)
        paid = max(tb.path(mh, e, Ld[0]) for e in Eh)
        value = less(tb.U(mh, Eh, Ld), paid) + tb.U(EMPTY, Ld, Tt) + back + tb.U(EMPTY, X, Ld)
        note("C4d", value, (o, g, x, t, oh, "drop at", ld))
    bound, (others, f) = swap_bound(tb, f"{o}/{g}", mh, g, gh, x, t)
    note("C4d swap", bound, (o, g, x, t, oh, "others on", others, "via", f))


def swap_bound(tb: Costs, mo, mh, g, gh, x, t) -> tuple[float, tuple]:
    """C4d-swap for o (mode mo) moved from x to t while oh (mode mh) is held at Else: (bound,
    (the places the other objects take, the parking place f)).  Park oh at f, restore o from t
    to x, carry oh from f on to t: five motions at their U.  At most n - 2 other objects stand
    on L besides o, on places other than x and t; they may take the n - 2 places where the
    plan is cheapest, so the robot is left the (n - 1)-th cheapest."""
    G, D = tb.grab, tb.drop
    Eh, X, Tt, Th = tb.Else(gh), tb.at(x, g), tb.at(t, g), tb.at(t, gh)
    paid = max(tb.path(mh, e, Th[0]) for e in Eh)
    plans = sorted((tb.U(mh, Eh, F) + D + tb.U(EMPTY, F, Tt) + G + tb.U(mo, Tt, X) + D + tb.U(EMPTY, X, F) + G
                    + tb.U(mh, F, Th), f)
                   for f in tb.L if f not in (x, t) for F in [tb.at(f, gh)])
    taken = max(0, len(tb.scene.objects) - 2)
    if len(plans) <= taken:
        return INF, (tuple(f for _, f in plans), None)
    cost, f = plans[taken]
    others = sorted((p for _, p in plans[:taken]), key=tb.L.index)
    return less(cost, paid), (tuple(others), f)
