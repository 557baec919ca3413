"""The physical form of a scene file: robot, obstacles, shapes and poses.

A scene file is physical when it has a `robot` key.  Then `locations`,
`else_samples` and `grasps` are mappings from names to poses instead of
lists of names, objects carry a shape, and `costs`, `obstacles`, `else` and
`planner` are allowed.  This module holds the JSON Schema of those parts and
turns validated data into `Geometry`; `load.py` reports the problems.

```yaml
robot:                 # all keys optional; the default is the Franka Panda
  urdf: franka_panda/panda.urdf   # relative to the scene file, else to pybullet_data
  base: {xyz: [0, 0, 0], rpy: [0, 0, 0]}
  home: [0, -0.785, 0, -2.356, 0, 1.571, 0.785]
  ee_link: panda_hand
  fixed: {panda_finger_joint1: 0.04, panda_finger_joint2: 0.04}
  opening: 0.08        # widest object across the fingers the hand closes on (grab);
                       # unchecked when left out (scenes/arch.yaml leaves it out: its bridge
                       # is 14 cm across the fingers, as the paper's abstraction allows)
obstacles:
  table: {box: [1.2, 1.6, 0.05], xyz: [0.3, 0, -0.05], physics: {friction: 0.5}}
objects:
  w1: {tags: [block, white], box: [0.04, 0.04, 0.08], at: table1,
       physics: {mass: 0.05, friction: 0.5}}   # optional: the physical world's material
locations:
  table1: {xyz: [0.45, 0.25, 0]}
else:                  # Else samples: explicit, or drawn in a region
  samples: 4
  region: {min: [0.3, -0.4], max: [0.7, 0.4]}
grasps:
  top: {xyz: [0, 0, 0.1634], rpy: [3.14159265, 0, 0], approach: 0.05}
contacts:              # optional: poses for displacement primitives (push, pull, plugins)
  behind: {primitive: push, xyz: [-0.16, 0, 0.12], rpy: [0, 2.356, 0], approach: 0.05}
# A grasp or contact may say where it has no anchor (`absent_at: [PLACE, ...]`, e.g. a top
# grasp under a low shelf board): semantics §5's absent anchors, recorded in the costmap.
costs: {per_radian: 1, grab: 5, drop: 5, push: 2}   # push: the primitive's fixed cost
planner: {name: ompl-fcl, roadmap_size: 300, check_step: 0.05, seed: 0}
```

A `physics:` block (objects: `mass` in kg, `friction`; obstacles: `friction`) is read only
by the physical world (`symsynth simulate --world physics`, `execution/physics.py`, which
holds the defaults); it changes no costmap, so it is no part of the costmap's cache key.

`planner: {seconds: S}` instead of `roadmap_size` grows each mode's roadmap
for S seconds.  The roadmap then depends on the machine and its load: the
same seed no longer guarantees the same costmap.  `seconds` is part of the
cache key, so a costmap cached with one limit is not reused for another
(but is reused for the same one, whatever it would give on recomputing).
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from symsynth.scene.geometry import (Body, Contact, Geometry, Grasp, Material, PlannerSettings, Pose, Robot, Shape,
                                     point_text, vec3)
from symsynth.scene.mesh import MeshError, load_mesh

NUMBER = {"type": "number"}
POSITIVE = {"type": "number", "exclusiveMinimum": 0}
VEC3 = {"type": "array", "items": NUMBER, "minItems": 3, "maxItems": 3}
VEC2 = {"type": "array", "items": NUMBER, "minItems": 2, "maxItems": 2}
POSE_KEYS = {"xyz": VEC3, "rpy": VEC3}
POSE = {"type": "object", "additionalProperties": False, "properties": POSE_KEYS}
SHAPE_KEYS = {
    "box": {"type": "array", "items": POSITIVE, "minItems": 3, "maxItems": 3},
    "cylinder": {"type": "object", "additionalProperties": False, "required": ["radius", "height"],
                 "properties": {"radius": POSITIVE, "height": POSITIVE}},
    "mesh": {"type": "object", "additionalProperties": False, "required": ["file"],
             "properties": {"file": {"type": "string"}, "scale": POSITIVE}},
}
ONE_SHAPE = {"oneOf": [{"required": [kind]} for kind in SHAPE_KEYS]}

ROBOT = {
    "type": "object", "additionalProperties": False,
    "properties": {
        "urdf": {"type": "string"},
        "base": POSE,
        "home": {"type": "array", "items": NUMBER, "minItems": 1},
        "ee_link": {"type": "string"},
        "joints": {"type": "array", "items": {"type": "string"}, "minItems": 1},
        "fixed": {"type": "object", "additionalProperties": NUMBER},
        "opening": {"type": "number", "exclusiveMinimum": 0},
    },
}
#: An object's material for the physical world (`symsynth simulate --world physics`):
#: mass in kg, Coulomb friction coefficient (PyBullet multiplies the two bodies' coefficients).
OBJECT_PHYSICS = {"type": "object", "additionalProperties": False,
                  "properties": {"mass": POSITIVE, "friction": {"type": "number", "minimum": 0}}}
#: A static obstacle's (the table's): friction only, it does not move.
OBSTACLE_PHYSICS = {"type": "object", "additionalProperties": False,
                    "properties": {"friction": {"type": "number", "minimum": 0}}}
OBSTACLE = {"type": "object", "additionalProperties": False,
            "properties": {**SHAPE_KEYS, **POSE_KEYS, "physics": OBSTACLE_PHYSICS}, **ONE_SHAPE}
ABSENT_AT = {"type": "array", "items": {"type": "string"}, "uniqueItems": True}
GRASP = {"type": "object", "additionalProperties": False, "required": ["xyz"],
         "properties": {**POSE_KEYS, "approach": {"type": "number", "minimum": 0}, "absent_at": ABSENT_AT}}
CONTACT = {"type": "object", "additionalProperties": False, "required": ["primitive", "xyz"],
           "properties": {**POSE_KEYS, "approach": {"type": "number", "minimum": 0}, "absent_at": ABSENT_AT,
                          "primitive": {"type": "string", "pattern": "^[A-Za-z0-9_-]+$"}}}
ELSE_REGION = {
    "type": "object", "additionalProperties": False, "required": ["samples", "region"],
    "properties": {
        "samples": {"type": "integer", "minimum": 1},
        "region": {"type": "object", "additionalProperties": False, "required": ["min", "max"],
                   "properties": {"min": VEC2, "max": VEC2, "z": NUMBER}},
        "clearance": POSITIVE,
    },
}
COSTS = {"type": "object", "additionalProperties": {"type": "number", "minimum": 0},  # a primitive's fixed cost
         "properties": {"per_radian": {"type": "number", "minimum": 0},
                        "grab": {"type": "number", "minimum": 0},
                        "drop": {"type": "number", "minimum": 0}}}
PLANNER = {
    "type": "object", "additionalProperties": False,
    "properties": {
        "name": {"type": "string"},
        "roadmap_size": {"type": "integer", "minimum": 2},
        "seconds": POSITIVE,
        "check_step": POSITIVE,
        "resolution": POSITIVE,  # check_step's old name (deprecated)
        "seed": {"type": "integer", "minimum": 0},
    },
}
#: Keys an object may have in a physical scene besides `tags` and `at`.
OBJECT_KEYS = {**SHAPE_KEYS, **POSE_KEYS, "physics": OBJECT_PHYSICS}

PANDA_URDF = "franka_panda/panda.urdf"
PANDA_HOME = (0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785)
PANDA_FINGERS = {"panda_finger_joint1": 0.04, "panda_finger_joint2": 0.04}


#: Else samples a region may ask for (`else_places`).
MAX_ELSE_SAMPLES = 64


class Report(Protocol):
    def add(self, path: tuple, message: str) -> None: ...

    def warn(self, path: tuple, message: str) -> None: ...


def pose_of(spec: dict[str, Any]) -> Pose:
    return Pose.from_rpy(tuple(spec.get("xyz", (0, 0, 0))), tuple(spec.get("rpy", (0, 0, 0))))


def geometry_from_data(data: dict[str, Any], source: Path | None, report: Report) -> Geometry | None:
    """The geometry of validated physical scene data; problems of meaning
    (a URDF that is missing, a joint it lacks) go to `report`."""
    base = source.parent if source else Path.cwd()
    robot = _robot(data.get("robot") or {}, base, report)
    obstacles = tuple(Body(name, _shape(spec, base, ("obstacles", name), report), pose_of(spec))
                      for name, spec in (data.get("obstacles") or {}).items())
    shapes = {name: _shape(spec, base, ("objects", name), report)
              for name, spec in data["objects"].items()}
    initial = {name: pose_of(spec) for name, spec in data["objects"].items()
               if spec.get("at", "Else") == "Else" and "xyz" in spec}
    places = {name: pose_of(spec) for name, spec in data["locations"].items()}
    samples = else_places(data, places, initial, report)
    for name, pose in initial.items():  # drawn samples start with these; given ones must have them
        if not any(_same_pose(pose, sample) for sample in samples.values()):
            where = ("one of else_samples (" + ", ".join(samples) + ")" if samples
                     else "an Else sample: the scene has none (no else_samples, no else region)")
            report.add(("objects", name, "xyz"), f"{name} starts at Else at {point_text(pose.xyz)}, which is "
                       f"not {where}; add its pose to else_samples, so that the costmap reaches it")
    places.update(samples)
    grasps = {name: Grasp(name, pose_of(spec), float(spec.get("approach", 0.05)),
                          absent_at=_absent_at(spec, ("grasps", name), places, report))
              for name, spec in data["grasps"].items()}
    contacts = {name: Contact(name, pose_of(spec), float(spec.get("approach", 0.05)),
                              absent_at=_absent_at(spec, ("contacts", name), places, report),
                              primitive=spec["primitive"])
                for name, spec in (data.get("contacts") or {}).items()}
    costs = {key: float(value) for key, value in (data.get("costs") or {}).items()
             if key not in ("per_radian", "grab", "drop")}
    settings = data.get("planner", {})
    if "seconds" in settings and "roadmap_size" in settings:
        report.add(("planner", "seconds"), "give the roadmap either a size (roadmap_size) or a time limit "
                   "(seconds), not both")
    step = settings.get("check_step", PlannerSettings.check_step)
    if "resolution" in settings and "check_step" in settings:
        report.add(("planner", "resolution"), "give check_step only (resolution is its old name)")
    elif "resolution" in settings:  # the old name, read as check_step for now
        report.warn(("planner", "resolution"), "deprecated: rename it check_step (radians between collision "
                    "checks along a segment; 'resolution' now means only the game's cost unit, --resolution)")
        step = settings["resolution"]
    planner = PlannerSettings(
        name=settings.get("name", PlannerSettings.name),
        roadmap_size=settings.get("roadmap_size", PlannerSettings.roadmap_size),
        seconds=settings.get("seconds"),
        check_step=float(step),
        seed=settings.get("seed", PlannerSettings.seed),
    )
    if robot is None:
        return None
    materials = {name: Material(spec["physics"].get("mass"), spec["physics"].get("friction"))
                 for group in ("objects", "obstacles") for name, spec in (data.get(group) or {}).items()
                 if "physics" in spec}
    return Geometry(robot=robot, obstacles=obstacles, shapes=shapes, places=places, grasps=grasps,
                    initial=initial, per_radian=float(data.get("costs", {}).get("per_radian", 1.0)),
                    planner=planner, contacts=contacts, primitive_costs=costs, materials=materials)


def _absent_at(spec: dict[str, Any], where: tuple, places: dict[str, Pose], report: Report) -> frozenset[str]:
    """A grasp's or contact's `absent_at`: places (locations or Else
    samples) where it has no anchor by declaration (semantics §5)."""
    found = []
    for i, place in enumerate(spec.get("absent_at", [])):
        if place in places:
            found.append(place)
        else:
            report.add(where + ("absent_at", i), f"{place!r} is no place of the scene; expected a location or "
                       f"an Else sample: {', '.join(places)}")
    return frozenset(found)


def else_places(data: dict[str, Any], locations: dict[str, Pose], initial: dict[str, Pose],
                report: Report) -> dict[str, Pose]:
    """Else samples: the explicit `else_samples` mapping, or `else.samples`
    poses in `else.region`.

    Drawn samples start with the `initial` poses (of the objects that start
    at Else with a pose), in object order: the robot must be able to fetch an
    object where it really stands, and a costmap only has motions to
    samples (a pose that is no sample leaves the first transit to it out of
    E_p; the simulator would have to plan it at run time).  The remaining
    samples are drawn uniformly in the region (seeded by the planner seed),
    each at least `clearance` (default 0.1 m) from every location and every
    earlier sample.  With more such objects than `samples`, each still gets
    its sample.  Explicit samples must include those poses themselves
    (`geometry_from_data` reports one that is missing, as it does when the
    scene has no Else samples at all)."""
    if "else_samples" in data:
        return {name: pose_of(spec) for name, spec in data["else_samples"].items()}
    spec = data.get("else")
    if spec is None:
        return {}
    region = spec["region"]
    low, high = np.array(region["min"], float), np.array(region["max"], float)
    if np.any(low > high):
        report.add(("else", "region"), f"min {list(region['min'])} must not exceed max {list(region['max'])} "
                   "in either coordinate")
        return {}
    if spec["samples"] > MAX_ELSE_SAMPLES:
        report.add(("else", "samples"), f"at most {MAX_ELSE_SAMPLES} Else samples, found {spec['samples']}: "
                   "each is an anchor of every grasp, and the costmap has a motion between every two")
        return {}
    z, clearance = float(region.get("z", 0.0)), float(spec.get("clearance", 0.1))
    rng = np.random.default_rng(data.get("planner", {}).get("seed", 0))
    taken = [np.array(p.xyz[:2]) for p in locations.values()]
    samples: dict[str, Pose] = {}
    for pose in initial.values():
        samples[f"e{len(samples) + 1}"] = pose
        taken.append(np.array(pose.xyz[:2]))
    for _ in range(1000 * spec["samples"]):
        if len(samples) >= spec["samples"]:
            break
        xy = rng.uniform(low, high)
        if all(np.linalg.norm(xy - other) >= clearance for other in taken):
            taken.append(xy)
            samples[f"e{len(samples) + 1}"] = Pose((float(xy[0]), float(xy[1]), z))
    else:
        report.add(("else", "region"), f"could not place {spec['samples']} samples {clearance} m apart "
                   "from each other and from the locations; enlarge the region or lower clearance")
    return samples


def _same_pose(a: Pose, b: Pose) -> bool:
    """Equal up to rounding (1 µm, 1 µrad): the same numbers written differently."""
    return bool(np.allclose(a.xyz, b.xyz, rtol=0.0, atol=1e-6)) and a.angle_to(b) <= 1e-6


def _shape(spec: dict[str, Any], base: Path, where: tuple, report: Report) -> Shape:
    if "box" in spec:
        return Shape("box", size=vec3(spec["box"]))
    if "cylinder" in spec:
        return Shape("cylinder", radius=float(spec["cylinder"]["radius"]),
                     height=float(spec["cylinder"]["height"]))
    mesh = base / spec["mesh"]["file"]
    if not mesh.is_file():
        report.add(where + ("mesh", "file"), f"mesh file {str(mesh)!r} not found")
    else:
        # read here, with the scene's other problems, before any planner does
        # (pybullet crashes on some files it cannot parse); read once (`mesh.py`)
        try:
            load_mesh(mesh)
        except MeshError as error:
            report.add(where + ("mesh", "file"), f"{error} (expected a triangle mesh in an .obj or .stl "
                       "file: pybullet, which the simulator and its planner use, reads no other)")
    return Shape("mesh", mesh=mesh, scale=float(spec["mesh"].get("scale", 1.0)))


def _robot(spec: dict[str, Any], base: Path, report: Report) -> Robot | None:
    urdf = _find_urdf(spec.get("urdf", PANDA_URDF), base)
    if urdf is None:
        report.add(("robot", "urdf"), f"URDF {spec.get('urdf')!r} not found next to the scene "
                   "nor in pybullet_data")
        return None
    try:
        tree = ElementTree.parse(urdf)
    except ElementTree.ParseError as error:
        report.add(("robot", "urdf"), f"{urdf}: not a valid URDF: {error}")
        return None
    links = {name for link in tree.iter("link") if (name := link.get("name")) is not None}
    movable = [name for j in tree.iter("joint") if j.get("type") in ("revolute", "prismatic", "continuous")
               and (name := j.get("name")) is not None]
    default = spec.get("urdf", PANDA_URDF) == PANDA_URDF
    fixed = dict(spec.get("fixed", PANDA_FINGERS if default else {}))
    joints = tuple(spec.get("joints", [j for j in movable if j not in fixed]))
    for name in list(joints) + list(fixed):
        if name not in movable:
            report.add(("robot",), f"joint {name!r} is not a movable joint of {urdf.name}; "
                       f"its movable joints: {', '.join(movable)}")
    ee_link = spec.get("ee_link", "panda_hand" if default else None)
    if ee_link is None:
        report.add(("robot",), "ee_link is required for a robot other than the default Panda")
    elif ee_link not in links:
        report.add(("robot", "ee_link"), f"link {ee_link!r} not in {urdf.name}; "
                   f"its links: {', '.join(sorted(links))}")
    home = tuple(float(v) for v in spec.get("home", PANDA_HOME if default else [0.0] * len(joints)))
    if len(home) != len(joints):
        report.add(("robot", "home"), f"expected {len(joints)} joint values ({', '.join(joints)}), "
                   f"found {len(home)}")
    opening = spec.get("opening")  # not checked unless given (module doc)
    return Robot(urdf=urdf, base=pose_of(spec.get("base", {})), home=home, ee_link=ee_link or "",
                 joints=joints, fixed=tuple(sorted(fixed.items())), opening=opening)


def _find_urdf(name: str, base: Path) -> Path | None:
    local = base / name
    if local.is_file():
        return local.resolve()
    import pybullet_data

    bundled = Path(pybullet_data.getDataPath()) / name
    return bundled if bundled.is_file() else None

