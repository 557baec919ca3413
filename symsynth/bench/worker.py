"""One run in a child process: `python -m symsynth.bench.worker` reads the
run (JSON) on stdin and writes its measurements (JSON) on the stdout it was
given; anything printed on the way (a planner's C library writes to file
descriptor 1) goes to stderr.

`execute(run)` starts that child with the run's memory limit (the address
space, `RLIMIT_AS`, set by the child itself before it works), waits at most
the run's seconds, and returns the measurements with the exit status:
ok, timeout, out-of-memory or error (with its message).  The child and the
planner's workers it forks are one process group, killed together; the
child is killed with its parent (`die_with_parent`), even by SIGKILL.
"""

from __future__ import annotations

import base64
import json
import os
import pickle
import platform
import resource
import signal
import subprocess
import sys
import time
from importlib import metadata
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from symsynth.scene import Scene

#: Packages whose versions each row records (those that decide the numbers).
PACKAGES = ("dd", "numpy", "scipy", "ompl", "python-fcl", "pybullet", "lark")
#: What a child that died for want of memory says on stderr (Python, OpenBLAS, CUDD, C++).
_OUT_OF_MEMORY = ("memoryerror", "out of memory", "memory allocation", "cannot allocate memory", "bad_alloc")
#: Lines of a failed child's stderr kept in its error message.
STDERR_LINES = 3


def execute(run: dict[str, Any]) -> dict[str, Any]:
    """The measurements of `run` (a `Run.to_json()`), made in a child process."""
    command = [sys.executable, "-m", "symsynth.bench.worker"]
    child = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, start_new_session=True)
    try:
        out, err = child.communicate(json.dumps(run).encode(), timeout=run["seconds"])
    except subprocess.TimeoutExpired:
        _kill(child)
        child.communicate()
        return {"status": "timeout", "error": f"still running after the limit of {run['seconds']:g} s"}
    except BaseException:  # an interrupt: no child left behind
        _kill(child)
        child.communicate()
        raise
    finally:
        _kill(child)  # the planner's workers, if the child left any
    text = err.decode(errors="replace").strip()
    try:
        found = json.loads(out.decode().strip().splitlines()[-1])
    except (IndexError, ValueError):  # died without an answer
        if any(sign in text.lower() for sign in _OUT_OF_MEMORY):
            return {"status": "out-of-memory", "error": f"beyond {run['memory_mb']} MB: {_tail(text)}"}
        how = (f"killed by {signal.Signals(-child.returncode).name}" if child.returncode < 0
               else f"exit status {child.returncode}")
        return {"status": "error", "error": f"the run's process ended without a result ({how}): {_tail(text)}"}
    return found


def _kill(child: subprocess.Popen) -> None:
    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _tail(text: str) -> str:
    return " | ".join(text.splitlines()[-STDERR_LINES:]) or "nothing on stderr"


def versions(planner: str | None) -> dict[str, str]:
    """symsynth's, the planner plugin's, Python's and `PACKAGES`' versions."""
    from symsynth import __version__
    from symsynth.planning.registry import planner_version

    found = {"symsynth": __version__, "python": platform.python_version()}
    if planner is not None:
        found[f"planner {planner}"] = planner_version(planner) or "unknown"
    for package in PACKAGES:
        try:
            found[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            continue
    return found


def measure(run: dict[str, Any]) -> dict[str, Any]:
    """Solve the run's cell and measure it (in this process)."""
    import dataclasses

    from symsynth.automata.shared import dfa_of
    from symsynth.problem import CostmapRequest, solve, with_costmap, with_task
    from symsynth.solvers import prepare

    row: dict[str, Any] = {"host": platform.node(), "cpus": os.cpu_count(), "load": os.getloadavg()[0],
                           "started": time.strftime("%Y-%m-%dT%H:%M:%S")}
    scene = scene_of(run)
    if not run.get("contacts", True):
        scene = scene.without_contacts()
    planner = None
    if scene.geometry is not None:
        settings = scene.geometry.planner
        if run["roadmap_size"] is not None:
            settings = dataclasses.replace(settings, roadmap_size=run["roadmap_size"])
        scene = dataclasses.replace(scene, geometry=dataclasses.replace(scene.geometry, planner=settings))
    problem = with_task(scene, None)  # the task as the scene loader parsed it
    request = CostmapRequest(run["method"] or "recursive", run["planner"], run["seed"], run["cache"], progress=False)
    clock = time.perf_counter()
    problem = with_costmap(problem, request)  # the costmap as solve obtains it (none to obtain: abstract)
    got = problem.obtained
    if got is not None:
        row["seconds_abstraction"] = time.perf_counter() - clock
        planner = got.planner
        row |= {"planner": got.planner, "roadmap_size": settings.roadmap_size, "costmap_cached": got.cached,
                "costmap_rules": sum(1 for _ in got.costmap.all_rules())}
        if got.stats is not None:
            s = got.stats
            row |= {f"seconds_{phase.replace(' ', '_')}": value for phase, value in s.seconds.items()}
            row |= {"roadmaps": s.roadmaps, "roadmap_vertices": s.vertices, "roadmap_edges": s.edges,
                    "edge_checks": s.edges, "graph_searches": s.motions, "planner_workers": s.workers}
    row["dfa_states"] = dfa_of(problem.formula).num_states  # the DFA every solver composes with the game
    row["seconds_prepare"] = prepare(run["solver"])  # once per process (compiling kernels), before the clock
    if run.get("objective", "worst") != "worst":
        from symsynth.solvers.objectives import prepare as prepare_objectives

        clock = time.perf_counter()
        prepare_objectives()
        row["seconds_prepare"] += time.perf_counter() - clock
        return row | _objective(run, problem) | {"versions": versions(planner)}
    clock = time.perf_counter()
    solution = solve(problem, run["solver"], k=run["k"], budget=run["budget"], resolution=run["resolution"])
    row["seconds_synthesis"] = time.perf_counter() - clock
    row |= {"k": solution.k, "E_p": "inf" if solution.cost_bound is None else solution.cost_bound, "units": solution.units,
            "realizable": solution.realizable, "positions": solution.states,
            "bdd_peak_nodes": solution.stats.get("peak_nodes"),
            "synthesis_phases": {name: round(s, 6) for name, s in solution.seconds.items()},
            "versions": versions(planner)}
    if run.get("world") is not None and solution.cost_bound is not None:
        row |= in_world(problem, run)
    return row


def scene_of(run: dict[str, Any]) -> Scene:
    """The run's scene: as the experiment loaded it (`runner.packed`, sent by
    the parent that checked the file), else read from its file."""
    if "scene" in run:
        return pickle.loads(base64.b64decode(run["scene"]))
    from symsynth.scene import load_scene

    return load_scene(run["scene_file"])


def in_world(problem: Any, run: dict[str, Any]) -> dict[str, Any]:
    """The solved strategy run once in `run["world"]` against a random
    human (seed: the run's), measured as `worlds.measured` does: whether
    it completed (and within the tolerance), the placement error at the
    end (metres), the `state` divergences (where the world did not do what
    the abstraction says), soundness bugs, the measured cost, the seconds."""
    from symsynth.bench.worlds import RANDOMIZE, measured
    from symsynth.execution.physics import Randomization
    from symsynth.problem import simulate

    physical = run["world"] == "physics"
    done = simulate(problem, "random", solver=run["solver"], seed=run["seed"], progress=False,
                    world=run["world"], randomization=Randomization.parse(RANDOMIZE) if physical else None)
    row = measured(done.runs)
    return {key: row[key] for key in ("completed", "within_tolerance", "placement_error", "state_divergences",
                                      "soundness_bugs", "cost", "seconds_simulation", "cpu_seconds_simulation")}


def _objective(run: dict[str, Any], problem: Any) -> dict[str, Any]:
    """`measure` for an objective of semantics §9: its value and seconds."""
    from symsynth.errors import InputError
    from symsynth.game.human_model import parse_model
    from symsynth.solvers.objectives import SOLVERS as OBJECTIVE_SOLVERS
    from symsynth.solvers.objectives import solve_objective

    text = run.get("human_model") or problem.scene.human_model
    model = None if text is None else parse_model(text, "human_models")
    if run["solver"] not in OBJECTIVE_SOLVERS:
        raise InputError(f"objective {run['objective']} is computed by the solvers {', '.join(OBJECTIVE_SOLVERS)}, "
                         f"not {run['solver']}")
    clock = time.perf_counter()
    s = solve_objective(problem.scene, problem.formula, objective=run["objective"], model=model, k=run["k"],
                        budget=run["budget"], resolution=run["resolution"], solver=run["solver"])
    took = time.perf_counter() - clock
    return {"seconds_synthesis": took, "k": s.k,
            "E_p": "inf" if s.cost_bound is None else s.cost_bound, "positions": s.states,
            "realizable": s.realizable, "human_model": s.human_model, "expected_cost": s.expected_cost,
            "class": s.position_class, "cooperative_cost": s.cooperative_cost,
            "run_costs": _run_costs(s, run["seed"]) if model is not None else None,
            "synthesis_phases": {name: round(t, 6) for name, t in s.seconds.items()}}


#: plays of an objective's strategy against its model per bench run (`run_costs`)
PLAYS = 200


def _run_costs(s: Any, seed: int) -> list[float] | None:
    """The costs (costmap units) of `PLAYS` plays of the objective's
    strategy against the human model, in the game, drawn by the run's seed;
    a play that does not finish (best effort) is left out.  None when there
    is no strategy to play."""
    import random

    from symsynth.solvers.objectives.play import run as play

    if s.arena is None or s.tables is None:
        return None
    rng = random.Random(f"bench/run_costs/{seed}")
    coop = s.tables[0] if s.objective == "best-effort" else None
    plays = [play(s.strategy(), int(s.budget_units or 0), "model", rng, coop=coop) for _ in range(PLAYS)]
    return [round(cost * s.resolution, 9) for cost, won in plays if won]


def peak_memory_mb() -> float:
    """The largest resident set of this process (VmHWM: `ru_maxrss` would
    carry over the larger one of the process that started this one, a Ray
    worker say) and of the planner's workers it forked, in MB."""
    own = 0
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            own = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:"))
    except (OSError, StopIteration, ValueError):  # not Linux
        own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return max(own, children) / 1024  # in KB on Linux


def main() -> int:
    from symsynth.errors import SymsynthError
    from symsynth.parallel import die_with_parent

    die_with_parent()
    answer = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)  # whatever the libraries print goes to stderr
    run = json.load(sys.stdin)
    limit = run["memory_mb"] << 20
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    try:
        row = measure(run) | {"status": "ok"}
    except MemoryError:
        row = {"status": "out-of-memory", "error": f"beyond {run['memory_mb']} MB"}
    except SymsynthError as error:
        row = {"status": "error", "error": str(error)}
    except Exception as error:  # noqa: BLE001 - a bug in one run is its row, the experiment goes on
        row = {"status": "error", "error": f"{type(error).__name__}: {error}"}
    row["peak_memory_mb"] = round(peak_memory_mb(), 1)
    answer.write(json.dumps(row) + "\n")
    answer.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
