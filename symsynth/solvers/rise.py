"""A proven bound R on how much one human move can raise the no-human value, for the replanning
strategy σ_Z that keeps spare places free (issue 32).

- `spare_places(scene, formula)`: the places Z no rule of any mode names in `free` and no goal
  of the task names; () when the setting below does not hold.
- `without_drops_at(scene, places)`: S_Z, the scene whose carrying motions never end at a place
  of Z (its no-human value V_0^Z >= V_0; its packed states are S's).
- `rise_bounds(scene, formula)`: `Rises` (in the packed search's integer units), None when there
  is no spare place.  For every state w in which some z of Z is *available* (no object stands
  at z, and the hand does not hold an object aligned with z: not (holding and ee = z)) and every
  legal human move m at w:
  - m not of class C5 (C5: an object taken from Else onto a location):
    V_0(m w) <= V_0(w) + other <= V_0^Z(w) + other (`other` = D+, `solvers.rise_repair`);
  - m of class C5: V_0(m w) <= V_0^Z(w) + c5 (`solvers.rise_c5`).
  A least-cost plan of S_Z from a state where z is available keeps z available (it never
  carries anything onto z, and nothing stands at z to be grabbed), so at every human turn of
  σ_Z's plan from such a state the bound applies again.
  S_Z may have no plan where S has one (V_0^Z infinite): when the places left besides Z leave
  no room to shuffle (3 x 5 seed 3: two spare places, three objects on the other three).

Setting (both proofs need it): the task is F(φ), φ a conjunction of at(X, l) atoms, each tag X
naming one object, every object named once, the goals l distinct locations; the scene has no
contacts and at least one Else sample; no costmap rule names an Else sample (an object at Else
blocks nothing).  Then V_0
is a function of the state alone (acceptance depends only on which object stands where)."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable

from symsynth.automata.normal import split_conjuncts
from symsynth.game.abstraction import Move, State, costmap_of
from symsynth.logic import ast
from symsynth.scene.model import ELSE, EMPTY, HAND, Scene
from symsynth.scene.propositions import interpret
from symsynth.solvers.rise_c5 import c5_bound
from symsynth.solvers.rise_costs import Costs
from symsynth.solvers.rise_repair import d_plus


@dataclasses.dataclass(frozen=True)
class Rises:
    """The rise bounds of one scene and task, in units of the resolution they were asked at."""

    spares: tuple[str, ...]  # Z
    other: int  # D+: every human move but C5
    c5: int  # C5^Z: an object from Else onto a location, relative to V_0^Z(w)
    #: (class of `move_class`, its bound): what `other` and `c5` are the largest of; a class
    #: of C5_CLASSES bounds V_0(m w) - V_0^Z(w), any other V_0(m w) - V_0(w)
    classes: tuple[tuple[str, int], ...] = ()

    @property
    def total(self) -> int:
        """R = max(other, c5): a bound for every human move at a state with a spare available."""
        return max(self.other, self.c5)

    def of(self, name: str) -> int:
        """The bound of one class of moves (`move_class`)."""
        return dict(self.classes)[name]


#: the classes of human moves (`move_class`) and the proof's cases that cover each
CLASSES = {
    "L->Else, aimed at o": ("C1",), "L->Else": ("C2",), "Else->Else, aimed at o": ("C3",),
    "L->L, hand at Else or aimed at o": ("C4a",), "L->L, aimed at another": ("C4b", "C4d", "C4d swap"),
    "L->L, holding at L": ("C4c",), "L->L, holding at Else": ("C4d", "C4d swap"),
    "Else->Z, aimed at o": ("on Z, was aimed at o",), "Else->Z": ("on Z, hand as it was",),
    "Else->L, hand at Else": ("E1 empty at Else",), "Else->L, aimed at o": ("E4 was aimed at o",),
    "Else->L, aimed at another": ("E2 aimed at another",), "Else->L, holding at L": ("H1 holding at a location",),
    "Else->L, holding at Else": ("H2 holding at Else", "H2 swap"),
}
C5_CLASSES = tuple(c for c in CLASSES if c.startswith("Else->") and not c.startswith("Else->Else"))


def move_class(scene: Scene, spares: tuple[str, ...], w: State, move: Move) -> str | None:
    """The class of the human move `move` at `w` (a key of CLASSES), None for a move that
    changes nothing the value reads (an object moved within Else, the hand not aimed at it)."""
    x, t = w.at[move.serves], move.location
    held = HAND in w.at
    if held:
        hand = "holding at Else" if w.ee == ELSE else "holding at L"
    elif w.ee == ELSE:
        hand = "hand at Else"
    else:
        hand = "aimed at o" if w.ee[0] == move.obj else "aimed at another"
    if x == ELSE and t == ELSE:
        return "Else->Else, aimed at o" if hand == "aimed at o" else None
    if x == ELSE:
        if t in spares:
            return "Else->Z, aimed at o" if hand == "aimed at o" else "Else->Z"
        return f"Else->L, {hand}"
    if t == ELSE:
        return "L->Else, aimed at o" if hand == "aimed at o" else "L->Else"
    if hand in ("hand at Else", "aimed at o"):
        return "L->L, hand at Else or aimed at o"
    return f"L->L, {hand}"


def goals(scene: Scene, formula: ast.Formula) -> dict[str, str] | None:
    """object -> goal location when the task is the setting's F(φ) (module doc), else None."""
    if not isinstance(formula, ast.Eventually):
        return None
    found: dict[str, str] = {}
    for part in split_conjuncts(formula.arg):
        p = interpret(part, scene) if isinstance(part, ast.Atom) else None
        if p is None or p.kind != "at" or p.location not in scene.locations:
            return None
        named = scene.tagged(p.named_tag)
        if len(named) != 1 or named[0] in found:
            return None
        found[named[0]] = p.location
    if set(found) != set(scene.object_names) or len(set(found.values())) != len(found):
        return None
    return found


def spare_places(scene: Scene, formula: ast.Formula) -> tuple[str, ...]:
    """Z: the locations no rule of any mode names in `free` and no goal is; () when the
    setting (module doc) does not hold."""
    if scene.contacts or scene.costmap is None or not scene.else_samples:
        return ()
    task = goals(scene, formula)
    if task is None:
        return ()
    named = frozenset().union(*(r.free for r in costmap_of(scene).all_rules()))
    if named & set(scene.else_samples):
        return ()
    return tuple(l for l in scene.locations if l not in named and l not in task.values())


def without_drops_at(scene: Scene, places: Iterable[str]) -> Scene:
    """S_Z: `scene` with every carrying motion (mode other than `empty`) that ends at an anchor
    of a place of `places` removed (a missing pair is an unavailable action)."""
    cm = costmap_of(scene)
    ends = {f"{z}/{g}" for z in places for g in scene.grasps}
    motions = {key: r for key, r in cm.motions.items() if key[0] == EMPTY or key[2] not in ends}
    return dataclasses.replace(scene, costmap=dataclasses.replace(cm, motions=motions))


def available_spares(rises: Rises, v: State) -> tuple[str, ...]:
    """The places of Z available in `v`: no object there, and no held object aligned with it."""
    held = v.ee if HAND in v.at else None
    return tuple(z for z in rises.spares if z not in v.at and z != held)


def rise_bounds(scene: Scene, formula: ast.Formula, resolution: float = 1.0) -> Rises | None:
    """The rise bounds (module doc) in units of `resolution`; None when there is no spare
    place (or the setting does not hold) or a bound is not finite."""
    spares = spare_places(scene, formula)
    if not spares:
        return None
    costs = Costs(scene, resolution)
    other, repairs = d_plus(costs)
    c5, relocations = c5_bound(costs, spares)
    if not (math.isfinite(other) and math.isfinite(c5)):
        return None
    found = repairs | relocations
    worst = {name: max(found.get(c, (-math.inf,))[0] for c in cases) for name, cases in CLASSES.items()}
    classes = tuple((name, int(value) if value > -math.inf else 0) for name, value in worst.items())
    return Rises(spares, int(other), int(c5), classes)
