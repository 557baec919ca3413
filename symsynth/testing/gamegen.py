"""Seeded random scenes for the game solvers: abstract scenes, conditional
costmaps and tasks, built through `scene_from_data` so they are validated.

`random_scene(seed)` draws 1–3 objects with shared tags, 2–4 locations,
0–2 Else samples, 1–2 grasps, a human with k in 0..2 and a task from a few
patterns.  The costmap covers the motions the game can ask for (transit:
any anchor to any x/g; transfer with o/g: x/g to l/g), but each goal anchor
is dropped for a mode now and then, single pairs go missing, and rules
carry random `free` conditions, so some scenes are unrealizable.

`positive=True` makes every action cost at least one unit (costs 1–9,
grab and drop 1–5, and never exactly one Else sample, which would make a
transit between two objects in Else cost 0): then every play that stays
within a cost bound B has at most B robot actions, which is what a
budget-bounded brute force needs.
"""

from __future__ import annotations

import random
from typing import Any

from symsynth.scene import Scene, scene_from_data

TAGS = ("block", "red", "blue")


def random_scene(seed: int, *, positive: bool = False, contacts: bool = False, zeros: float = 0.0) -> Scene:
    """`contacts=True` adds 1-2 contacts (semantics §4b), motions to and from
    their anchors and random slide rules, drawn from a second generator so
    that the rest of the scene is the one `contacts=False` draws.  `zeros`:
    the share of motion rules whose cost is then set to 0 (a third
    generator), for games where waiting on zero-cost moves pays (§9)."""
    rng = random.Random(seed)
    low = 1 if positive else 0
    locations = [f"l{i}" for i in range(1, rng.randint(2, 4) + 1)]
    samples = [f"e{i}" for i in range(1, rng.choice([0, 2, 2, 2] if positive else [0, 1, 2, 2]) + 1)]
    grasps = ["top", "side"][:rng.randint(1, 2)]
    names = [f"o{i}" for i in range(1, rng.randint(1, 3) + 1)]
    spots = rng.sample(locations + ["Else"] * len(names), len(names))
    objects = {o: {"tags": rng.sample(TAGS, rng.randint(0, 2)), "at": at}
               for o, at in zip(names, spots)}
    data: dict[str, Any] = {
        "name": f"random{seed}",
        "objects": objects,
        "locations": locations,
        "else_samples": samples,
        "grasps": grasps,
        "primitives": {"grab": rng.randint(low, 5), "drop": rng.randint(low, 5)},
        "human": {"k": rng.randint(0, 2)},
        "task": _task(rng, objects, locations),
        "costmap": _costmap(rng, names, locations, samples, grasps, low),
    }
    if contacts:
        _add_contacts(random.Random(f"contacts {seed}"), data, low)
    if zeros:
        draw = random.Random(f"zeros {seed}")
        for motion in data["costmap"]["motions"]:
            for rule in motion["rules"]:
                if draw.random() < zeros:
                    rule["cost"] = 0
    return scene_from_data(data)


def _add_contacts(rng: random.Random, data: dict, low: int) -> None:
    """Contacts, the transits that reach them or start from them, and slide
    rules between locations (some missing, some conditional)."""
    contacts = ["push", "pull"][:rng.randint(1, 2)]
    locations, grasps = data["locations"], data["grasps"]
    places = locations + data["else_samples"]
    at_contact = [f"{x}/{a}" for x in places for a in contacts]
    every = ["home"] + [f"{x}/{g}" for x in places for g in grasps] + at_contact
    pairs = [(s, t) for t in at_contact for s in every] + [(s, f"{x}/{g}") for s in at_contact
                                                          for x in places for g in grasps]
    motions = data["costmap"]["motions"]
    for s, t in pairs:
        if s != t and rng.random() < 0.9:
            rules = [{"free": _some(rng, places), "cost": rng.randint(low, 9)} for _ in range(rng.randint(1, 2))]
            if rng.random() < 0.9:
                rules[-1]["free"] = []
            motions.append({"mode": "empty", "from": s, "to": t, "rules": rules})
    slides = []
    for a in contacts:
        for l in locations:
            for m in locations:
                if l != m and rng.random() < 0.6:
                    rules = [{"free": _some(rng, places), "cost": rng.randint(low, 9)}
                             for _ in range(rng.randint(1, 2))]
                    slides.append({"contact": a, "from": l, "to": m, "rules": rules})
    data["contacts"] = contacts
    data["costmap"]["slides"] = slides


def _task(rng: random.Random, objects: dict, locations: list[str]) -> str:
    tags = sorted({t for o, spec in objects.items() for t in [o, *spec["tags"]]})
    x, y = rng.choice(tags), rng.choice(tags)
    l, m = rng.sample(locations, 2)
    anywhere = rng.choice(locations + ["Else"])
    patterns = [
        f"F(at({x}, {l}))",
        f"F(at({x}, {anywhere}))",
        f"F(at({x}, {l}) & at({y}, {m}))",
        f"F(at({x}, {l})) & G(!at({y}, {m}))",
        f"F(at({x}, {l})) & G(occupied({m}) -> at({y}, {m}))",
        f"F(holding({x}))",
        f"F(occupied({l}) & free({m}))",
        f"F(at({x}, {l}) & F(at({y}, {m})))",
    ]
    return rng.choice(patterns)


def _costmap(rng: random.Random, names: list[str], locations: list[str], samples: list[str],
             grasps: list[str], low: int) -> dict:
    places = locations + samples
    every = ["home"] + [f"{x}/{g}" for x in places for g in grasps]
    pairs = [("empty", s, f"{x}/{g}") for x in places for g in grasps for s in every]
    pairs += [(f"{o}/{g}", f"{x}/{g}", f"{l}/{g}")
              for o in names for g in grasps for x in places for l in locations]
    goals = sorted({(mode, t) for mode, _, t in pairs})
    dropped = {goal for goal in goals if rng.random() < 0.1}
    motions = []
    for mode, s, t in pairs:
        if s == t or (mode, t) in dropped or rng.random() < 0.003:
            continue
        rules = [{"free": _some(rng, places), "cost": rng.randint(low, 9)}
                 for _ in range(rng.randint(1, 3))]
        if rng.random() < 0.97:
            rules[-1]["free"] = []  # usually one unconditional fallback
        motions.append({"mode": mode, "from": s, "to": t, "rules": rules})
    return {"format": "symsynth.costmap/1", "motions": motions}


def _some(rng: random.Random, places: list[str]) -> list[str]:
    return [x for x in places if rng.random() < 0.25]


def alike_scene(seed: int, *, contacts: bool = False) -> Scene:
    """A random scene whose objects come in kinds: 2-4 objects of 1-2 kinds
    (tags `block` and `red` or `blue`), the costmap rows of mode `o/g` the
    same for every object of a kind (drawn once per kind, with the same
    missing pairs and conditions), the task over the kinds' tags -- now and
    then over one object's own name, which sets it apart from its kind."""
    rng = random.Random(f"alike {seed}")
    locations = [f"l{i}" for i in range(1, rng.randint(2, 4) + 1)]
    samples = [f"e{i}" for i in range(1, rng.choice([0, 1, 2, 2]) + 1)]
    grasps = ["top", "side"][:rng.randint(1, 2)]
    n = rng.randint(2, min(4, len(locations) + 1))
    names = [f"o{i}" for i in range(1, n + 1)]
    kinds = {o: rng.choice(["red", "blue"][:rng.randint(1, 2)]) for o in names}
    spots = rng.sample(locations + ["Else"] * n, n)
    objects = {o: {"tags": ["block", kinds[o]], "at": at} for o, at in zip(names, spots)}
    costmap = _costmap(rng, sorted(set(kinds.values())), locations, samples, grasps, 0)
    motions = []
    for entry in costmap["motions"]:
        kind, slash, g = entry["mode"].partition("/")
        if not slash:
            motions.append(entry)
            continue
        motions += [dict(entry, mode=f"{o}/{g}") for o in names if kinds[o] == kind]
    costmap["motions"] = motions
    tags = ["block", *sorted(set(kinds.values()))] + ([rng.choice(names)] if rng.random() < 0.2 else [])
    data = {
        "name": f"alike{seed}",
        "objects": objects,
        "locations": locations,
        "else_samples": samples,
        "grasps": grasps,
        "primitives": {"grab": rng.randint(0, 5), "drop": rng.randint(0, 5)},
        "human": {"k": rng.randint(0, 2)},
        "task": _task(rng, {t: {"tags": []} for t in tags}, locations),
        "costmap": costmap,
    }
    if contacts:
        _add_contacts(random.Random(f"contacts alike {seed}"), data, 0)
    return scene_from_data(data)
