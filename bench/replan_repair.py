"""A bound D+ on the rise of the no-human value V_0 over one human move, from the costmap
alone (no position enumerated): the repair argument of bench/results/game-notes.md ("A
repair bound D+ from the costmap"), where each case's plan and its proof are written out.
The cases are computed by symsynth/solvers/rise_repair.py (the solver's rise bound); this
script prints them, with the conditional C5 beside them.

    python bench/replan_repair.py N M [SEED ...]     D+ and its cases on pattern_scene(N, M, 3, SEED),
                                                     then the spare places' bounds (solvers.rise)

Per motion pair (mode, s, t): U = the least cost of a rule with no condition (F empty: holds
in every state; inf when there is none), L = the least cost of any rule (no state pays
less); 0 when s = t.  A case's bound is a sum of U's for the repair plan's motions, grab and
drop, minus L's (or shortest paths over L's) for what p's own plan pays and no longer needs.
Every case is a maximum over the objects (one per set of objects with the same carrying
rules), grasps and places it names; C4d's swap with each motion at its U and the (n - 1)-th
cheapest parking place (the other objects may take the cheaper ones; the exact-occupancy
maximum over sets of n - 2 places gave the same 146 at 6 x 8 and 153 at 8 x 12).  Scenes with
contacts (slides), and costmaps where an Else sample is a condition of a rule, are refused (the postponing cases assume an object at Else blocks nothing).

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
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.scene.model import ELSE, EMPTY  # noqa: E402
from symsynth.solvers.rise import rise_bounds, spare_places  # noqa: E402
from symsynth.solvers.rise_costs import Costs  # noqa: E402
from symsynth.solvers.rise_repair import SOUND, cases  # noqa: E402
from symsynth.solvers.rise_repair import swap_bound as swap_worst  # noqa: E402,F401 (replan_repair_check)


class Tables(Costs):
    """The costs of `solvers.rise_costs` at resolution 1, refusing the scenes the proof does
    not cover."""

    def __init__(self, scene):
        if scene.contacts:
            raise ValueError("scenes with contacts (slides) are not covered by this bound")
        super().__init__(scene)
        if any(r.free & set(scene.else_samples) for r in self.cm.all_rules()):
            raise ValueError("a rule asks for an Else sample to be free: C2's postponing does not hold")


def _c5(tb, note, o, g, t, mo):
    """x = Else, t in L: NOT a sound bound.  What p's plan pays more when it fetches o from t
    instead of from Else, assuming its part before that neither uses t nor meets a rule that
    asks t to be free (the notes say why that cannot be assumed)."""
    sc = tb.scene
    Eg, Tt = tb.Else(g), tb.at(t, g)
    carry = max(tb.U(mo, Tt, tb.at(l, g)) - tb.Lo(mo, Eg, tb.at(l, g)) for l in tb.L if l != t)
    starts = [("Else", tb.A)] + [(y, tb.at(y, a)) for y in tb.L + [ELSE] if y != t for a in sc.preimages]
    for y, S in starts:
        note("C5 (conditional)", tb.U(EMPTY, S, Tt) - tb.Lo(EMPTY, S, Eg) + max(0, carry), (o, g, t, "from", y))
    note("C5 (conditional)", tb.U(EMPTY, tb.A, Tt) + max(0, carry), (o, g, t, "was aimed at o"))


def d_plus(scene) -> tuple[float, dict]:
    """(D+, every case's bound and where it is attained): D+ is the largest sound case, with
    the conditional C5 beside them."""
    tb = Tables(scene)
    found = cases(tb)

    def note(name, value, where):
        if name not in found or value > found[name][0]:
            found[name] = (value, where)

    for o, g in itertools.product(tb.kinds(), scene.grasps):
        for t in tb.L:
            _c5(tb, note, o, g, t, f"{o}/{g}")
    return max(found[c][0] for c in SOUND if c in found), found


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    n, m = int(argv[0]), int(argv[1])
    for seed in [int(s) for s in argv[2:]] or [0]:
        scene = pattern_scene(n, m, 3, seed)
        clock = time.perf_counter()
        bound, found = d_plus(scene)
        seconds = time.perf_counter() - clock
        print(f"{n} x {m} seed {seed}: D+ = {bound}")
        for name in sorted(found):
            value, where = found[name]
            print(f"  {name:18} {value:6}  {where}")
        _spares(scene, seconds)
    return 0


def _spares(scene, seconds) -> None:
    """The bound C5^Z of symsynth/solvers/rise_c5.py, when the scene has spare places."""
    clock = time.perf_counter()
    formula = task_formula(scene, None)
    spares = spare_places(scene, formula)
    rises = rise_bounds(scene, formula)
    seconds += time.perf_counter() - clock
    if rises is None:
        print(f"  no spare place (spare_places: {spares}); {seconds:.2f} s")
        return
    print(f"  spare places {', '.join(spares)}: C5^Z = {rises.c5}, R = {rises.total}; {seconds:.2f} s")
    for name, value in rises.classes:
        print(f"    {name:36} {value:4}")


if __name__ == "__main__":
    sys.exit(main())
