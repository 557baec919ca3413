"""Fixtures shared by test files: the paper's scenes on small roadmaps,
with their costmaps computed once per test session.

The suite runs on pytest-xdist workers (pyproject's addopts); work that
every worker would repeat is done by the first worker that needs it while
the others wait for its result (`once`)."""

from __future__ import annotations

import fcntl
import pickle

import pytest

from support.paper import PLANNERS, SCENES, small
from symsynth.planning.build import compute_costmaps

# The example plugins are repositories of their own: their tests run there,
# with the plugin installed (tests/test_*_plugin.py), not in this session.
collect_ignore = ["plugins"]


def xdist_worker(config) -> bool:
    """Whether this process is a pytest-xdist worker (not the only process
    of a run with -n 0, nor one without the plugin)."""
    return hasattr(config, "workerinput")


def once(config, tmp_path_factory, name: str, compute):
    """compute(), done once per run: in one process, directly; under xdist
    by the first worker to get here, while the others wait on a lock in the
    run's shared temporary folder and read the pickled result."""
    if not xdist_worker(config):
        return compute()
    shared = tmp_path_factory.getbasetemp().parent  # the run's folder, above each worker's own
    result = shared / f"{name}.pickle"
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file is closed
        if result.exists():
            return pickle.loads(result.read_bytes())
        value = compute()
        result.write_bytes(pickle.dumps(value))
        return value


def _paper(name):
    scene = small(name)
    costmaps, _ = compute_costmaps(scene, ("sg", "recursive"), PLANNERS[name], progress=False)
    return scene, costmaps


@pytest.fixture(scope="session")
def paper_arch(request, tmp_path_factory):
    """(arch scene, {"sg": costmap, "recursive": costmap}) by the pybullet planner."""
    return once(request.config, tmp_path_factory, "paper_arch", lambda: _paper("arch"))


@pytest.fixture(scope="session")
def paper_line(request, tmp_path_factory):
    """(line scene, {"sg": costmap, "recursive": costmap}) by the ompl-fcl planner."""
    return once(request.config, tmp_path_factory, "paper_line", lambda: _paper("line"))


@pytest.fixture(scope="session", autouse=True)
def compiled_kernels_once(request, tmp_path_factory):
    """The compiled solver's numba kernels are compiled on first use and
    cached on disk (symsynth/solvers/compiled.py: cache=True); on a fresh
    install that takes about 19 s of CPU, and two workers that both reach
    the solver before the cache is written both pay it.  So a worker of a
    run of several test files compiles them up front (`prepare`: a small
    game's solve compiles every specialization) while the others wait and
    then load the cache (about 0.3 s)."""
    if not xdist_worker(request.config) or len({item.path for item in request.session.items}) < 2:
        return
    from symsynth.solvers import prepare

    once(request.config, tmp_path_factory, "compiled_kernels", lambda: prepare("compiled"))
    prepare("compiled")  # in a worker that waited: loads the kernels from the cache now
