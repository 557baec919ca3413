"""A scalable family of manipulation games: put n blocks into a pattern.

    pattern_scene(n, m, k=3, seed=0)   -> Scene (validated by scene_from_data)
    pattern_data(n, m, k=3, seed=0)    -> the same scene as a dict (semantics §7 form,
                                          costmap inline as symsynth.costmap/1)
    python bench/gamefamily.py N M [--k K] [--seed S]   prints the scene as YAML

The scene (everything drawn from `random.Random(seed)`, so deterministic):

- objects `o1..on`, tags `[block, COLOUR]`, colours distinct (red, green,
  blue, ...) while there are enough of them;
- locations `l1..lm` (m >= n + 1, so a free location is always left to
  shuffle blocks through: the robot can only put an object down on a
  location of interest), Else samples `e1, e2`, grasps `top` (or the
  `grasps` given), grab = drop = 5, a human with `k` moves;
- with `colours=c` (the sorting variant), object i has colour i mod c, so
  blocks of one colour are interchangeable (game/symmetry.py) and the
  pattern asks for some block of the right colour at each target;
- the task is one pattern, `F(at(c1, l_p1) & ... & at(cn, l_pn))` with `ci`
  the colour of `oi` (its name when colours run out) and `p` a seeded
  injection of the objects into distinct locations;
- the initial placement: about a third of the objects (at least one when
  n >= 2) start at Else, the others on locations none of which is the
  object's own target, so the pattern never holds at the start.

Geometry (only used to make the costmap): the locations on a grid of
`min(m, 4)` columns and spacing 1, `li` at ((i-1) % cols, (i-1) // cols);
`e1` at (-1, -1), `e2` at (cols, -1), `home` at ((cols-1)/2, -1.5).  The
anchor `x/g` stands at the point of `x` whatever the grasp.

Costmap: every motion pair the game can ask for (semantics §5): in mode `empty`
from every anchor (home and every x/g, x in L ∪ E) to every x/g; in mode
`o/g` from every x/g to every l/g (l in L), for every object o and grasp g
(pairs with s = t are left out: they cost 0 by definition).  With d the
Euclidean distance between the two points, the straight motion costs
`base = max(1, round(10 d))`.  When the straight segment passes over other
places B (points of L ∪ E within 0.25 of the segment, strictly between its
ends; e.g. l1 -> l3 over l2 in a row), the pair gets two rules: `{free: [],
cost: base + 6 |B|}` (going around) and `{free: B, cost: base}` (straight,
when every place in B is free).  All costs are integers >= 1.
"""

from __future__ import annotations

import math
import random
import sys
from pathlib import Path
from typing import Any

COLOURS = ("red", "green", "blue", "yellow", "white", "black", "orange", "purple",
           "pink", "brown", "grey", "cyan")
GRAB = DROP = 5
DETOUR = 6          # extra cost per place the straight segment passes over
NEAR = 0.25         # a place within this distance of a segment is "in between"
MAX_COLUMNS = 4


def pattern_scene(n: int, m: int, k: int = 3, seed: int = 0, *, grasps=("top",),
                  initial: dict[str, str] | None = None, target: dict[str, str] | None = None,
                  colours: int | None = None):
    """The family's scene for n objects and m locations, validated (see the module doc).

    `initial` / `target` (object name -> place) override the drawn initial
    placement / pattern, for hand-checked tests.
    """
    from symsynth.scene import scene_from_data

    return scene_from_data(pattern_data(n, m, k, seed, grasps=grasps, initial=initial, target=target,
                                        colours=colours))


def pattern_data(n: int, m: int, k: int = 3, seed: int = 0, *, grasps=("top",),
                 initial: dict[str, str] | None = None,
                 target: dict[str, str] | None = None, colours: int | None = None) -> dict[str, Any]:
    if n < 1:
        raise ValueError(f"n must be >= 1, found {n}")
    if m < n + 1:
        raise ValueError(f"m must be >= n + 1 = {n + 1} (a free location to shuffle through), found {m}")
    if k < 0:
        raise ValueError(f"k must be >= 0, found {k}")
    grasps = list(grasps)
    rng = random.Random(f"pattern/{n}/{m}/{seed}")
    names = [f"o{i}" for i in range(1, n + 1)]
    locations = [f"l{i}" for i in range(1, m + 1)]
    samples = ["e1", "e2"]
    if colours is not None:  # the sorting variant: object i has colour i mod c
        if not 1 <= colours <= len(COLOURS):
            raise ValueError(f"colours must be in 1..{len(COLOURS)}, found {colours}")
        labels = [COLOURS[i % colours] for i in range(n)]
    else:
        labels = list(COLOURS[:n]) if n <= len(COLOURS) else names

    goal = dict(zip(names, rng.sample(locations, n)))
    if target:
        goal.update(target)
    start = _initial(rng, names, locations, goal)
    if initial:
        start.update(initial)

    objects = {}
    for o, label in zip(names, labels):
        spec: dict[str, Any] = {"tags": ["block", label] if label != o else ["block"]}
        spec["at"] = start[o]
        objects[o] = spec
    task = "F(" + " & ".join(f"at({label}, {goal[o]})" for o, label in zip(names, labels)) + ")"
    return {
        "name": (f"pattern_n{n}_m{m}_k{k}_s{seed}" if colours is None
                 else f"sort_n{n}_c{colours}_m{m}_k{k}_s{seed}"),
        "objects": objects,
        "locations": locations,
        "else_samples": samples,
        "grasps": grasps,
        "primitives": {"grab": GRAB, "drop": DROP},
        "human": {"k": k},
        "task": task,
        "costmap": costmap_data(names, locations, samples, grasps),
    }


def _initial(rng: random.Random, names: list[str], locations: list[str],
             goal: dict[str, str]) -> dict[str, str]:
    n = len(names)
    at_else = max(1, round(n / 3)) if n >= 2 else rng.randint(0, 1)
    off = set(rng.sample(names, at_else))
    on = [o for o in names if o not in off]
    for _ in range(10_000):
        spots = rng.sample(locations, len(on))
        if all(spot != goal[o] for o, spot in zip(on, spots)):
            break
    else:  # pragma: no cover - m >= n + 1 makes a derangement easy to draw
        raise RuntimeError("no initial placement found")
    start = {o: "Else" for o in off}
    start.update(zip(on, spots))
    return {o: start[o] for o in names}


def layout(locations: list[str], samples: list[str]) -> dict[str, tuple[float, float]]:
    """Points of home, the locations and the Else samples."""
    cols = min(len(locations), MAX_COLUMNS)
    points = {l: (float(i % cols), float(i // cols)) for i, l in enumerate(locations)}
    extra = [(-1.0, -1.0), (float(cols), -1.0)]
    for i, e in enumerate(samples):
        x, y = extra[i % 2]
        points[e] = (x, y - 1.0 * (i // 2))
    points["home"] = ((cols - 1) / 2, -1.5)
    return points


def between(points: dict[str, tuple[float, float]], s: str, t: str, places: list[str]) -> list[str]:
    """Places (other than s, t) whose points lie on the segment s -> t (within NEAR)."""
    (x0, y0), (x1, y1) = points[s], points[t]
    dx, dy = x1 - x0, y1 - y0
    length2 = dx * dx + dy * dy
    out = []
    if length2 == 0:
        return out
    for p in places:
        if p in (s, t):
            continue
        px, py = points[p]
        u = ((px - x0) * dx + (py - y0) * dy) / length2
        if not 0.0 < u < 1.0:
            continue
        if abs(dx * (py - y0) - dy * (px - x0)) / math.sqrt(length2) < NEAR:
            out.append(p)
    return out


def motion_rules(points, s: str, t: str, places: list[str]) -> list[dict[str, Any]]:
    """The rules of one motion between anchor points `s` and `t` (place names or home)."""
    (x0, y0), (x1, y1) = points[s], points[t]
    base = max(1, round(10 * math.hypot(x1 - x0, y1 - y0)))
    blockers = between(points, s, t, places)
    if not blockers:
        return [{"free": [], "cost": base}]
    return [{"free": [], "cost": base + DETOUR * len(blockers)},
            {"free": blockers, "cost": base}]


def costmap_data(objects: list[str], locations: list[str], samples: list[str],
                 grasps: list[str]) -> dict[str, Any]:
    """Every motion pair of semantics §5, costed from the layout (module doc)."""
    points = layout(locations, samples)
    places = locations + samples
    everywhere = [("home", "home")] + [(f"{x}/{g}", x) for x in places for g in grasps]
    motions = []

    def add(mode, s, ps, t, pt):
        if s != t:
            motions.append({"mode": mode, "from": s, "to": t,
                            "rules": motion_rules(points, ps, pt, places)})

    for g in grasps:
        for x in places:
            for s, ps in everywhere:
                add("empty", s, ps, f"{x}/{g}", x)
    for o in objects:
        for g in grasps:
            for x in places:
                for l in locations:
                    add(f"{o}/{g}", f"{x}/{g}", x, f"{l}/{g}", l)
    return {"format": "symsynth.costmap/1", "motions": motions}


def main(argv=None) -> int:
    import argparse

    import yaml

    p = argparse.ArgumentParser(description="Print a scene of the pattern family as YAML.")
    p.add_argument("n", type=int)
    p.add_argument("m", type=int)
    p.add_argument("--k", type=int, default=3)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--grasps", default="top", help="comma-separated grasp names")
    args = p.parse_args(argv)
    data = pattern_data(args.n, args.m, args.k, args.seed, grasps=args.grasps.split(","))
    from symsynth.scene import scene_from_data

    scene_from_data(data)  # validate
    yaml.safe_dump(data, sys.stdout, sort_keys=False, default_flow_style=None, width=120)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    sys.exit(main())
