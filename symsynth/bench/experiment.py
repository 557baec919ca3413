"""An experiment file: its schema, its checks, and the runs it expands to.

    name: paper
    scenes:                                   # paths are from the experiment file
      - {file: ../scenes/arch.yaml}
      - {file: ../scenes/line.yaml, label: line, params: {obstacles: 0}}
      - {file: "../scenes/line-obstacles-{obstacles}.yaml", label: line,
         sweep: {obstacles: [1, 2, 3, 4]}}
    methods: [sg, recursive]                  # costmap methods (physical scenes)
    solvers: [symbolic]
    objectives: [worst, expected]             # semantics §9 (default: worst)
    human_models: ["random(0.3)"]             # the model of expected (default: the scene's)
    trials: 10                                # seeds 0..9 (or seeds: [...])
    limits: {seconds: 600, memory_mb: 4096}
    worlds: [kinematic, physics]              # physical scenes: the strategy run once per seed

Every list under a matrix key is one axis; the runs are the product of the
axes and the seeds.  An abstract scene has its costmap already, so the
costmap axes (methods, planners, roadmap_sizes) and the worlds do not apply to it: its
runs have them empty, and the product does not repeat them.  Problems are
reported together as `file:line: key.path: message` (`ExperimentError`).
"""

from __future__ import annotations

import hashlib
import itertools
import string
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import jsonschema

from symsynth.errors import InputError
from symsynth.scene.load import MODEL_PATTERN
from symsynth.solvers import SOLVERS
from symsynth.planning.methods import METHODS
from symsynth.scene import Scene, load_scene
from symsynth.scene.load import Report, non_finite, schema_message
from symsynth.scene.yamlpos import read_yaml

NAME = {"type": "string", "pattern": "^[A-Za-z0-9_.-]+$"}
SCALAR = {"type": ["string", "number", "boolean"]}


def _axis(items: dict) -> dict:
    return {"type": "array", "minItems": 1, "uniqueItems": True, "items": items}


SCHEMA: dict[str, Any] = {
    "type": "object",
    "required": ["name", "scenes"],
    "additionalProperties": False,
    "properties": {
        "name": NAME,
        "description": {"type": "string"},
        "scenes": _axis({
            "type": "object",
            "required": ["file"],
            "additionalProperties": False,
            "properties": {
                "file": {"type": "string", "minLength": 1},
                "label": NAME,
                "params": {"type": "object", "propertyNames": {"pattern": "^[A-Za-z_][A-Za-z0-9_]*$"},
                           "additionalProperties": SCALAR},
                "sweep": {"type": "object", "minProperties": 1,
                          "propertyNames": {"pattern": "^[A-Za-z_][A-Za-z0-9_]*$"},
                          "additionalProperties": _axis(SCALAR)},
            },
        }),
        "methods": _axis({"enum": list(METHODS)}),
        "planners": _axis({"type": "string"}),
        "solvers": _axis({"enum": list(SOLVERS)}),
        "k": _axis({"type": "integer", "minimum": 0}),
        "budgets": _axis({"type": ["number", "null"], "minimum": 0}),
        "resolutions": _axis({"type": "number", "exclusiveMinimum": 0}),
        "roadmap_sizes": _axis({"type": "integer", "minimum": 2}),
        # on / off: YAML reads the bare words as booleans
        "contacts": _axis({"enum": [True, False, "on", "off"]}),
        # physical scenes: the strategy also run once per seed in this world (execution.simulate)
        "worlds": _axis({"enum": ["kinematic", "physics"]}),
        # semantics §9: what the solve optimizes, and the human model of `expected`
        "objectives": _axis({"enum": ["worst", "expected", "best-effort"]}),
        "human_models": _axis({"type": "string", "pattern": MODEL_PATTERN}),
        "trials": {"type": "integer", "minimum": 1, "maximum": 10_000},
        "seeds": _axis({"type": "integer", "minimum": 0}),
        "limits": {"type": "object", "additionalProperties": False,
                   "properties": {"seconds": {"type": "number", "exclusiveMinimum": 0},
                                  "memory_mb": {"type": "integer", "minimum": 64}}},
        "cache": {"type": "boolean"},
        "plots": {"type": "object", "additionalProperties": False,
                  "properties": {"x": {"type": "string"}}},
    },
}

#: Limits of a run when the file gives none.
DEFAULT_SECONDS = 3600.0
DEFAULT_MEMORY_MB = 8192


class ExperimentError(InputError):
    """An experiment file with problems; the message lists all of them."""


@dataclass(frozen=True)
class Run:
    """One run: everything the child process needs, all plain values (it is
    sent as JSON).  What the file leaves out is the scene's own (k, planner,
    roadmap size), filled in here so the cell names it; None means "not
    applicable" (the costmap settings of an abstract scene)."""

    scene_file: str
    label: str
    params: dict[str, Any]
    physical: bool
    method: str | None
    planner: str | None
    solver: str
    k: int
    budget: float | None
    resolution: float
    roadmap_size: int | None
    seed: int
    cache: bool
    seconds: float
    memory_mb: int
    #: False: the scene without its contacts (`Scene.without_contacts`),
    #: the displacement primitives off.
    contacts: bool = True
    #: The world the strategy is then run in once (a random human, the
    #: run's seed; physics randomized by `worlds.RANDOMIZE`), None: not run.
    world: str | None = None
    #: semantics §9: `worst` (E_p alone), `expected` or `best-effort`
    objective: str = "worst"
    #: the human model of `expected` as a scene writes it (None: the scene's)
    human_model: str | None = None

    @property
    def cell(self) -> str:
        """The run's settings without its seed: runs of one cell are trials of each other."""
        parts = [self.label + "".join(f" {k}={v}" for k, v in self.params.items())]
        if self.physical:
            parts += [s for s in (self.method, self.planner) if s is not None]  # both set for a physical scene
            parts.append(f"roadmap={self.roadmap_size}")
        parts += [self.solver, f"k={self.k}"]
        if self.budget is not None:
            parts.append(f"budget={self.budget:g}")
        if self.resolution != 1:
            parts.append(f"resolution={self.resolution:g}")
        if not self.contacts:
            parts.append("contacts=off")
        if self.world is not None:
            parts.append(f"world={self.world}")
        if self.objective != "worst":
            parts.append(f"objective={self.objective}")
        if self.human_model is not None:
            parts.append(f"model={self.human_model}")
        return " ".join(parts)

    @property
    def id(self) -> str:
        """A stable name of the run (its cell and its seed, wherever the files
        are): what --resume looks for in the CSV."""
        key = f"{self.cell}|seed={self.seed}"
        return hashlib.sha256(key.encode()).hexdigest()[:12]

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True)
class Experiment:
    name: str
    source: Path
    runs: tuple[Run, ...]
    plot_x: str | None = None
    description: str = ""
    cells: tuple[str, ...] = field(default=())
    #: The scenes as loaded when the file was checked, by `Run.scene_file`:
    #: handed to the runs' processes, which need not read them again.
    scenes: dict[str, Scene] = field(default_factory=dict, repr=False, compare=False)


    def first_trials(self, n: int) -> Experiment:
        """The runs of the first `n` seeds only (a quick look, or the first
        part of a long experiment that a later --resume completes)."""
        seeds = list(dict.fromkeys(run.seed for run in self.runs))[:n]
        return replace(self, runs=tuple(run for run in self.runs if run.seed in seeds))


def load_experiment(path: str | Path) -> Experiment:
    """The experiment of a YAML file, checked, with its runs expanded."""
    path = Path(path)
    data, lines = read_yaml(path, "experiment", ExperimentError)
    report = Report(str(path), lines, "experiment", ExperimentError)
    _check_schema(data, report)
    if "trials" in data and "seeds" in data:
        report.add(("seeds",), "give trials (seeds 0..trials-1) or seeds, not both")
    # the scene files are read now, so that a missing one is said with the problems above
    scenes = [variant for i, entry in enumerate(data.get("scenes") or []) if _readable(entry)
              for variant in _variants(entry, i, path.parent, report)]
    report.raise_if_any()
    runs = _runs(data, scenes, report)
    plot_x = data.get("plots", {}).get("x")
    names = {name for _, _, params, _ in scenes for name in params}
    if plot_x is not None and plot_x not in names:
        report.add(("plots", "x"), f"{plot_x!r} is no scene parameter; the parameters are: "
                                   f"{', '.join(sorted(names)) or 'none'}")
    report.raise_if_any()
    ordered = tuple(runs.values())
    return Experiment(data["name"], path, ordered, plot_x, data.get("description", ""),
                      tuple(dict.fromkeys(run.cell for run in ordered)),
                      {file: scene for file, _, _, scene in scenes})


def _check_schema(data: Any, report: Report) -> None:
    """The experiment's keys and values against `SCHEMA`, each problem at
    its key's line (an unknown key at its own)."""
    if not isinstance(data, dict):
        report.add((), "expected a mapping with name, scenes, ...")
        report.raise_if_any()
    for error in sorted(jsonschema.Draft202012Validator(SCHEMA).iter_errors(data),
                        key=lambda e: list(map(str, e.absolute_path))):
        where = tuple(error.absolute_path)
        if error.validator == "additionalProperties" and isinstance(error.instance, dict):
            allowed = error.schema.get("properties", {})
            for key in (key for key in error.instance if key not in allowed):  # at the key's own line
                report.add(where + (key,), f"unknown key {key!r}; allowed keys: {', '.join(sorted(allowed))}")
            continue
        report.add(where, schema_message(error))
    for where, value in non_finite(data):
        report.add(where, f"expected a finite number, found {value}")


def _runs(data: dict, scenes: list, report: Report) -> dict[str, Run]:
    """Every combination of the axes, by id (an abstract scene's runs repeat
    over the costmap axes: one run each)."""
    limits = data.get("limits", {})
    seeds = data.get("seeds", range(data.get("trials", 1)))
    runs: dict[str, Run] = {}
    # Seed by seed, every cell within each: a change in the machine's load falls on every cell
    # alike, and an experiment stopped early has whole trials of every cell.
    for (seed, (file, label, params, scene), method, planner, solver, k, budget, resolution, size, contacts,
         objective, model, world) in \
            itertools.product(seeds, scenes, data.get("methods", ["recursive"]), data.get("planners", [None]),
                              data.get("solvers", ["symbolic"]), data.get("k", [None]),
                              data.get("budgets", [None]), data.get("resolutions", [1.0]),
                              data.get("roadmap_sizes", [None]), data.get("contacts", [True]),
                              data.get("objectives", ["worst"]), data.get("human_models", [None]),
                              data.get("worlds", [None])):
        physical = scene.geometry is not None
        run = Run(file, label, params, physical, method if physical else None,
                  (planner or scene.geometry.planner.name) if physical else None, solver,
                  scene.k if k is None else k, None if budget is None else float(budget), float(resolution),
                  (size or scene.geometry.planner.roadmap_size) if physical else None, seed,
                  bool(data.get("cache", False)),
                  float(limits.get("seconds", DEFAULT_SECONDS)), int(limits.get("memory_mb", DEFAULT_MEMORY_MB)),
                  contacts in (True, "on"), world if physical else None, objective,
                  model if objective == "expected" else None)
        same = runs.setdefault(run.id, run)  # an abstract scene's runs repeat over the costmap axes
        if same.scene_file != run.scene_file:
            report.add(("scenes",), f"{same.scene_file} and {run.scene_file} have the same label and "
                                    f"parameters ({run.label!r}): give one a label of its own")
            report.raise_if_any()
    return runs


def _readable(entry: Any) -> bool:
    """Whether a `scenes` entry has the shape `_variants` reads (the schema
    says what is wrong with one that has not)."""
    return (isinstance(entry, dict) and isinstance(entry.get("file"), str)
            and isinstance(entry.get("params", {}), dict) and isinstance(entry.get("sweep", {}), dict)
            and all(isinstance(values, list) for values in entry.get("sweep", {}).values()))


def _variants(entry: dict, index: int, base: Path, report: Report) -> list[tuple[str, str, dict, Scene]]:
    """(file, label, params, scene) of each value combination of the
    entry's sweep; the file's `{name}` fields are filled with the values."""
    where = ("scenes", index)
    sweep = entry.get("sweep", {})
    fixed = entry.get("params", {})
    for name in sorted(set(sweep) & set(fixed)):
        report.add(where + ("sweep", name), f"{name!r} is also in params; give it in one of them")
    fields = {name for _, name, _, _ in string.Formatter().parse(entry["file"]) if name is not None}
    missing = fields - set(sweep) - set(fixed)
    if missing:
        report.add(where + ("file",), f"the file names {', '.join(sorted(missing))}, which neither "
                                      "params nor sweep gives")
        return []
    found = []
    for values in itertools.product(*sweep.values()):
        params = dict(fixed) | dict(zip(sweep, values))
        file = (base / entry["file"].format(**params)).resolve()
        try:
            scene = load_scene(file)
        except InputError as error:
            report.add(where + ("file",), f"{file}: " + str(error).replace("\n", "\n  "))
            continue
        found.append((str(file), entry.get("label", scene.name), params, scene))
    return found

