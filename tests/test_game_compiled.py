"""The compiled solver (symsynth/solvers/compiled.py) against the explicit
one written in Python: the same positions explored, the same value, and a
strategy that wins within it against every human behaviour, on generated
scenes with and without contacts and with interchangeable objects."""

from __future__ import annotations

import io
import multiprocessing
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np
import pytest

from symsynth.errors import InputError
from symsynth.game.abstraction import initial_state
from symsynth.game.solution import task_formula
from symsynth.game.symmetry import Symmetry
from symsynth.logic import parse_ltlf
from symsynth.solvers import compiled
from symsynth.solvers.compiled import Tables, solve_compiled
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers.packed.explore import explore as _explore
from symsynth.solvers.packed.kernels import _human_moves, _letter
from symsynth.testing.gamegen import alike_scene, random_scene
from support.games import PICK, make_scene, worst_case_of

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("chunk", range(4))
def test_same_positions_and_value_as_the_explicit_solver(chunk):
    kinds = {"finite": 0, "infinite": 0}
    for seed in range(60 * chunk, 60 * (chunk + 1)):
        contacts = seed % 3 == 0
        scene = random_scene(3000 + seed, positive=seed % 2 == 0, contacts=contacts)
        k = seed % 4
        compiled = solve_compiled(scene, k=k, symmetric=False)
        explicit = solve_explicit(scene, k=k, symmetric=False)
        assert (compiled.units, compiled.states) == (explicit.units, explicit.states), (seed, k)
        kinds["infinite" if compiled.units is None else "finite"] += 1
        if compiled.units is not None and seed % 5 == 0:
            assert worst_case_of(scene, compiled, parse_ltlf(scene.task)) == compiled.units
            assert sum(s.cost for s in compiled.principal_play) == pytest.approx(compiled.cost_bound)
    assert kinds["finite"] >= 15 and kinds["infinite"] >= 10, kinds


@pytest.mark.parametrize("kept", [0, 40])
def test_human_moves_generated_again_when_too_many_to_keep(kept, monkeypatch):
    """Past `HUMAN_MOVES_KEPT` human moves (none, or dropped after 40 once the
    exploration is under way) the solver generates them again and looks
    their values up in a rebuilt table: still the explicit solver's value and
    positions, and a strategy that wins within it."""
    monkeypatch.setattr(compiled, "HUMAN_MOVES_KEPT", kept)
    checked = past = 0
    for seed in range(40):
        scene = random_scene(3000 + seed, positive=seed % 2 == 0, contacts=seed % 3 == 0) if seed % 2 else \
            alike_scene(seed, contacts=seed % 4 == 0)
        k, symmetric = (1 + seed % 3, False) if seed % 2 else (None, True)
        got = solve_compiled(scene, k=k, symmetric=symmetric)
        explicit = solve_explicit(scene, k=k, symmetric=symmetric)
        assert (got.units, got.states) == (explicit.units, explicit.states), seed
        if got.units is not None:
            assert worst_case_of(scene, got, parse_ltlf(scene.task)) == got.units
            checked += 1
        past += got.stats.get("human_moves", 0) > kept
    assert past >= 15 and checked >= 10, (past, checked)  # the path ran, on games with a finite value too


def test_two_threads_and_small_batches(monkeypatch):
    """The human moves generated on two of numba's threads (when it has two),
    in batches of 3 nodes (so that a batch's targets are found in the table,
    added by an earlier node of the batch, or new), their values taken in
    parallel when they are not kept: the explicit solver's value and
    positions, and the strategy the solver picks on one thread."""
    threads = numba.get_num_threads()
    checked = 0
    try:
        for seed in range(24):
            scene = random_scene(3100 + seed, positive=seed % 2 == 0, contacts=seed % 3 == 0) if seed % 2 else \
                alike_scene(50 + seed, contacts=seed % 4 == 0)
            k, symmetric = (1 + seed % 3, False) if seed % 2 else (None, True)
            numba.set_num_threads(1)
            monkeypatch.setattr(compiled, "BATCH", 1 << 13)
            one = solve_compiled(scene, k=k, symmetric=symmetric)
            numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
            monkeypatch.setattr(compiled, "BATCH", 3)
            monkeypatch.setattr(compiled, "HUMAN_MOVES_KEPT", 0 if seed % 4 < 2 else 1 << 29)
            got = solve_compiled(scene, k=k, symmetric=symmetric)
            explicit = solve_explicit(scene, k=k, symmetric=symmetric)
            assert (got.units, got.states) == (explicit.units, explicit.states), seed
            assert dict(got.strategy) == dict(one.strategy), seed
            if got.units is not None:
                assert worst_case_of(scene, got, parse_ltlf(scene.task)) == got.units
                checked += 1
    finally:
        numba.set_num_threads(threads)
    assert checked >= 6, checked


def _solve_in_child(scene, k, out):
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    out.put(solve_compiled(scene, k=k, symmetric=False).units)


@pytest.mark.filterwarnings("ignore:This process .* is multi-threaded:DeprecationWarning")
def test_solving_in_a_forked_child_after_the_parent(monkeypatch):
    """The bench and `symsynth.parallel` fork: a child forked after the
    parent ran the parallel kernels solves too (GNU OpenMP, numba's default
    layer here, terminates such a child), and gets the explicit solver's value."""
    monkeypatch.setattr(compiled, "HUMAN_MOVES_KEPT", 0)  # the parallel values of the human moves, too
    scene, k = random_scene(3003, positive=False, contacts=False), 3
    threads = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    try:
        here = solve_compiled(scene, k=k, symmetric=False).units
    finally:
        numba.set_num_threads(threads)
    context = multiprocessing.get_context("fork")
    out = context.Queue()
    child = context.Process(target=_solve_in_child, args=(scene, k, out))
    child.start()
    child.join(120)
    assert child.exitcode == 0
    assert out.get(timeout=10) == here == solve_explicit(scene, k=k, symmetric=False).units


PREPARED = """
import sys
from numba.core.registry import CPUDispatcher
from symsynth.scene import load_scene
from symsynth.solvers import SOLVERS, prepare
from symsynth.solvers.packed import kernels
sys.path.insert(0, "tests")
from symsynth.testing.gamegen import alike_scene, random_scene

def signatures():
    return {name: len(getattr(kernels, name).signatures) for name in dir(kernels)
            if isinstance(getattr(kernels, name), CPUDispatcher)}

assert prepare("explicit") == 0.0 and prepare("symbolic") == 0.0  # no set-up: nothing run
assert sum(signatures().values()) == 0
seconds = prepare(sys.argv[1])
ready = signatures()
from bench.gamefamily import pattern_scene
for scene in (random_scene(5, positive=False, contacts=True), alike_scene(2, contacts=False),
              load_scene("scenes/push-abstract.yaml"), pattern_scene(5, 7)):  # the last grows its tables
    SOLVERS["compiled"](scene)
print(seconds > 0, {name: count for name, count in signatures().items() if count != ready[name]})
"""


@pytest.mark.parametrize("solver", ["compiled", "auto"])
def test_prepare_compiles_every_kernel_a_solve_uses(solver):
    """`prepare` (what comparison runs call before their clock) leaves
    nothing for a solve to compile: in a fresh process, solving games with
    and without slides, human moves and interchangeable objects, and one
    large enough to grow its tables, afterwards adds no specialization to
    any kernel.  (Without it, the first solve
    compiles `_explore` and `_solve`.)"""
    done = subprocess.run([sys.executable, "-c", PREPARED, solver], capture_output=True, text=True,
                          cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[-2] == "True {}"


FIRST_SOLVE = """
import sys
from symsynth.scene import load_scene
from symsynth.solvers.compiled import solve_compiled
scene = load_scene("scenes/toy.yaml")
first, second = solve_compiled(scene), solve_compiled(scene)
print(sorted(first.seconds), sorted(second.seconds), first.units == second.units == 50)
"""


def test_the_first_solve_of_a_process_shows_compiling_apart():
    """In a fresh process the first solve reports the kernels' compiling
    (or loading) as a phase of its own, `compile`, and later ones do not;
    the toy's value is the hand-solved 50 either way."""
    done = subprocess.run([sys.executable, "-c", FIRST_SOLVE], capture_output=True, text=True,
                          cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[-2] == ("['compile', 'explore', 'solve', 'tables'] "
                                            "['explore', 'solve', 'tables'] True")
    assert done.stderr == ""  # no terminal: no notice


class _Terminal(io.StringIO):
    def isatty(self):
        return True


@pytest.mark.parametrize("takes, said", [(1.3, True), (0.0, False)])
def test_a_terminal_is_told_when_compiling_takes_long(monkeypatch, takes, said):
    """On a terminal, compiling that takes over a second gets a line on
    stderr (a fresh install's first solve takes about 20 s)."""
    def slow_solve(scene):
        time.sleep(takes)
        return solve_explicit(scene)
    monkeypatch.setattr(compiled, "_compiled", False)
    monkeypatch.setattr(compiled, "solve_compiled", slow_solve)  # the warm-up game's solve
    monkeypatch.setattr(sys, "stderr", _Terminal())
    assert compiled.compile_kernels() >= takes
    assert compiled.compile_kernels() is None  # once per process
    assert ("compiling the compiled solver's kernels" in sys.stderr.getvalue()) == said


def test_a_cache_that_cannot_be_written_is_said_so(monkeypatch):
    """numba writes each kernel to its cache as it compiles it; a cache it
    cannot write (a full disk, `ulimit -f`) is one message naming the way
    out, not a traceback, and the next solve tries again."""
    def cannot_write(scene):
        raise OSError(27, "File too large")
    monkeypatch.setattr(compiled, "_compiled", False)
    monkeypatch.setattr(compiled, "solve_compiled", cannot_write)  # the warm-up game's solve
    with pytest.raises(InputError, match=r"numba could not write its cache \(File too large\); "
                                         "set NUMBA_CACHE_DIR"):
        compiled.compile_kernels()
    assert not compiled._compiled


@pytest.mark.parametrize("seed", range(30))
def test_interchangeable_objects(seed):
    """Canonical positions as game/symmetry.py orders them: the same count as
    the explicit solver's, the plain value, strategies in real objects."""
    scene = alike_scene(seed, contacts=seed % 2 == 0)
    plain = solve_explicit(scene, symmetric=False)
    reduced = solve_explicit(scene)
    compiled = solve_compiled(scene)
    assert (compiled.units, compiled.states) == (plain.units, reduced.states)
    if compiled.units is not None:
        assert worst_case_of(scene, compiled, parse_ltlf(scene.task)) == compiled.units


def test_too_many_atoms_is_an_input_error():
    motions = {("empty", "home", "l1/top"): 1}
    task = "F(" + " & ".join(f"(occupied(l1) | free(l2) | at(block, l{1 + i % 2}))" for i in range(9)) + ")"
    scene = make_scene({"a": "l1"}, ["l1", "l2"], motions, task=task)
    solve_compiled(scene)  # 3 atoms: fine
    atoms = " & ".join(f"at(o{i}, l1)" for i in range(17))
    scene = make_scene({f"o{i}": "Else" for i in range(17)}, ["l1"], motions, task=f"F({atoms})")
    with pytest.raises(InputError, match="at most 16 atoms"):
        solve_compiled(scene)


def test_a_move_too_costly_for_the_packing_is_an_input_error():
    """A robot move is stored as units << code_bits | code in 31 bits: one
    block, two locations and one grasp need code_bits = 7 (the largest code,
    a slide of object 1 with frame 1 to place 3: ((4 * 2 + 1) * 2 + 1) * 4 + 3
    = 79), so 2^24 units is the first cost refused; `explicit` solves it."""
    def scene(cost):
        motions = {**{key: 7 for key in PICK}, ("b/top", "l1/top", "l2/top"): cost}
        return make_scene({"b": "l1"}, ["l1", "l2"], motions, else_samples=["e1"], task="F(at(b, l2))")
    assert solve_compiled(scene((1 << 24) - 1 - 10)).units == solve_explicit(scene((1 << 24) - 1 - 10)).units
    with pytest.raises(InputError, match="a move of 16777216 units"):
        solve_compiled(scene(1 << 24))
    assert solve_explicit(scene(1 << 24)).units is not None


@pytest.mark.parametrize("seed", range(30))
def test_human_moves_come_out_canonical(seed):
    """The kernel's human moves at a canonical state shift one member's key to
    its place in the class instead of sorting: at every explored human turn,
    each move equals `_canon` of the same move made without classes (the
    plain move, sorted afresh), and its letter, computed per moved object,
    equals the one `_letter` reads off the canonical state object by object."""
    scene = alike_scene(seed, contacts=seed % 2 == 0)
    formula = task_formula(scene, None)
    t = Tables(scene, formula, 1.0, Symmetry.of(scene, formula), 2)
    v0 = t.canon(t.pack(initial_state(scene)))
    keys, hflag = _explore(t.key(v0, t.step(t.dfa_index[t.dfa.initial], v0)), *t.kernel_args())[:2]
    n = t.n
    classes = len(t.class_offsets) - 1
    obj_class, obj_pos = np.full(n, -1, np.int64), np.zeros(n, np.int64)
    for c in range(classes):
        for r in range(t.class_offsets[c], t.class_offsets[c + 1]):
            obj_class[t.class_members[r]], obj_pos[t.class_members[r]] = c, r - t.class_offsets[c]
    size = 4 * (n * (t.F + t.m + 2) + t.m + 2)
    fast, plain, scratch = np.empty(size, np.int64), np.empty(size, np.int64), np.empty(n, np.int64)
    letters = np.empty(size, np.int64)
    checked = 0
    for key in keys[hflag == 1]:
        x = np.int64(int(key) >> t.qbits)
        assert t.canon(int(x)) == int(x)
        args = (x, n, t.m, t.F, t.pb, t.eb, t.gb)
        count = _human_moves(*args, fast, obj_class, obj_pos, t.class_members, t.class_offsets,
                             t.place_rank, t.rank_place, scratch, letters, t.atom_at, t.free_at, t.free_all)
        assert _human_moves(*args, plain, np.full(n, -1, np.int64), obj_pos, t.class_members,
                            t.class_offsets, t.place_rank, t.rank_place, scratch, np.empty(size, np.int64),
                            t.atom_at, t.free_at, t.free_all) == count
        for e in range(count):
            assert fast[e] == t.canon(int(plain[e])), (seed, t.unpack(int(x)), t.unpack(int(plain[e])))
            # the letter computed per moved object is the canonical state's, read object by object
            assert letters[e] == _letter(fast[e], n, t.pb, t.atom_at, t.free_at, t.free_all)
            checked += 1
    assert checked > 0 or classes == 0


def test_exploring_reports_its_progress_layer_by_layer():
    """The exploring loop calls back after every batch with the layer and the
    nodes found so far (what the terminal's bar shows): every layer that has
    nodes, from k down, counts that never fall and never pass the nodes
    explored, and a call for every batch (of 4 nodes here).  The layers'
    first nodes passed with it give the closed layers' final sizes
    (`deadline.layer_sizes`, which the time limit's prediction reads)."""
    from symsynth.solvers.packed.deadline import layer_sizes
    from symsynth.solvers.packed.explore import explore

    scene = random_scene(3007, positive=True, contacts=False)
    formula = task_formula(scene, None)
    t = Tables(scene, formula, 1.0, None, 3)
    v0 = t.pack(initial_state(scene))
    calls, seen = [], []
    explored = explore(t.key(v0, t.step(t.dfa_index[t.dfa.initial], v0)), *t.kernel_args(batch=4),
                       progress=lambda h, nodes, lo, done: (calls.append((h, nodes)),
                                                            seen.append(layer_sizes(h, nodes, lo, done))))
    keys, lo, hi = explored[0], explored[2], explored[3]
    final = [int(hi[h] - lo[h]) for h in range(3, -1, -1)]
    for sizes, passed in seen:
        assert sizes[:-1] == final[:len(sizes) - 1] and 0 <= sizes[-1] <= final[len(sizes) - 1], (sizes, final)
        assert passed <= 2 * sum(final) - final[-1]
    assert max(len(sizes) for sizes, _ in seen) >= 3
    assert [h for h, _ in calls] == sorted((h for h, _ in calls), reverse=True)
    assert {h for h, _ in calls} == {h for h in range(4) if hi[h] > lo[h]}
    assert all(a[1] <= b[1] for a, b in zip(calls, calls[1:]))
    assert calls[-1][1] <= len(keys) and len(calls) >= len(keys) // 4  # a call per batch of 4 nodes
