"""The compiled solver (`--solver compiled`): the explicit solver's algorithm
with its core in machine code (numba), on positions packed into integers.

Same game, same value as `solvers.explicit` (Dijkstra for min-cost
reachability games over the positions the start reaches); what changes is
how a position and its moves are represented (`solvers.packed`):

- `packed.tables`: a position is one 64-bit integer (each object's place,
  the end-effector, the grip; the DFA state beside it in a node's key); the
  costmap, the task's DFA and the classes of interchangeable objects are
  integer arrays;
- `packed.kernels`: numba functions (compiled on first use and cached on
  disk) generate the moves (docs/game-semantics.md §4-§5 as
  `game/abstraction.py` writes them) and solve the layers;
- `packed.explore`: the loop over layers of h (the human's moves left) and
  batches of nodes; a node is a robot-turn position, flagged when the human
  turn at the same position is reached (its pass leads to the node); layer k
  first, closed under robot moves, then the human's moves from it seed
  layer k - 1; a bar of the nodes found on a terminal after a second;
- solving goes back up (`kernels._solve`): the human's moves from layer h
  lead into layer h - 1, solved already, so each human turn's best reply K
  is a number before layer h is solved; Dijkstra runs on the robot moves
  alone.  A robot move is kept in 8 bytes (its target, and its cost in
  units shifted above its action's code); a human move as a 32-bit target
  while there are at most `HUMAN_MOVES_KEPT` of them, else they are
  generated again when solving;
- `packed.graph`: the solved nodes read back as a strategy and plays; the
  Python side maps a canonical answer back to real objects exactly as it
  does for the explicit solver.

The tests hold the kernels to the explicit solver's value on every
generated scene, and the strategy is followed through every human behaviour
in the real game.

Scenes the packing cannot hold (more than 62 bits per position, more than
16 task atoms, more than 62 locations and Else samples, a move's cost
beyond its 32-bit packing, more than 2^15 moves per position, 2^31 nodes or
robot moves) raise `TooLarge` (an `OutOfReach`, an `InputError`) naming the
limit; `--solver explicit` solves them, and `auto` goes on to it.
"""

from __future__ import annotations

import dataclasses
import sys
import threading
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from tqdm import tqdm

from symsynth.errors import InputError
from symsynth.game.abstraction import in_costmap_units, initial_state
from symsynth.game.solution import (OutOfReach, Solution, Step, check_parameters, task_formula, verdict,
                                    won_at_start)
from symsynth.game.symmetry import Symmetry
from symsynth.logic import ast
from symsynth.scene.model import Scene
from symsynth.solvers.packed import kernels
from symsynth.solvers.packed.graph import CompiledStrategy, Graph
from symsynth.solvers.packed.deadline import Deadline, HandOver
from symsynth.solvers.packed.explore import Progress, compile_growth, explore
from symsynth.solvers.packed.kernels import INF, _solve
from symsynth.solvers.packed.tables import BATCH, HUMAN_MOVES_KEPT, Tables, TooLarge, check_width

__all__ = ["TooLarge", "Tables", "Packed", "compile_kernels", "explore_packed", "kernels_cached",
           "solve_compiled"]


@dataclass
class Packed:
    """The compiled solver's game, explored and solved (`explore_packed`).

    `explored`: `packed.explore.explore`'s arrays (keys, hflag, lo, hi, r_off,
    r_tgt, r_move, the number of human moves, h_off, h_tgt; h_off and h_tgt
    empty when the human moves were too many to keep); `rval`: V at each
    node's robot turn (units, `INF`: infinite); `choice`: the worst-case
    strategy's move there (relative to r_off, -1: none); `top`: V at the
    start's human turn (node 0); `start`: the start's key."""

    tables: Tables
    start: int
    explored: tuple
    rval: np.ndarray
    choice: np.ndarray
    top: int
    seconds: dict[str, float] = field(default_factory=dict)

    @property
    def keeps_human_moves(self) -> bool:
        """Whether h_off and h_tgt hold every human move."""
        return len(self.explored[8]) == len(self.explored[0]) + 1


def explore_packed(scene: Scene, formula: ast.Formula, k: int, resolution: float, *, symmetric: bool = True,
                   progress: Progress | None = None) -> Packed | None:
    """The game the start reaches, explored and solved for V (None when
    ρ(v0) alone is accepted: nothing to play); `k` checked already.  The
    seconds of `tables`, `explore` and `solve` in `Packed.seconds`."""
    clock = time.perf_counter()
    tables, start = packed_start(scene, formula, k, resolution, symmetric)
    seconds = {"tables": time.perf_counter() - clock}
    return None if start is None else explore_tables(tables, start, seconds, progress)


def packed_start(scene: Scene, formula: ast.Formula, k: int, resolution: float,
                 symmetric: bool) -> tuple[Tables, int | None]:
    """The game's tables and the start's key (None when ρ(v0) alone is accepted)."""
    symmetry = Symmetry.of(scene, formula) if symmetric else None
    tables = Tables(scene, formula, resolution, symmetry, k)
    check_width(tables, k)
    v0 = initial_state(scene)
    q0 = tables.step(tables.dfa_index[tables.dfa.initial], tables.pack(v0))
    if tables.accepting[q0]:
        return tables, None
    return tables, int(tables.key(tables.canon(tables.pack(v0)), q0))


def explore_tables(tables: Tables, start: int, seconds: dict[str, float], progress: Progress | None = None,
                   deadline: Deadline | None = None) -> Packed:
    """`explore_packed` on built tables; with `deadline`, `HandOver` when the
    solve would not end in time (the arrays are dropped on the way out)."""
    clock = time.perf_counter()
    if deadline is not None:
        deadline.exploring()
    explored = explore(start, *tables.kernel_args(HUMAN_MOVES_KEPT, BATCH), progress=progress)
    seconds["explore"] = time.perf_counter() - clock
    keys, r_tgt = explored[0], explored[5]
    if deadline is not None:
        deadline.check_solve(seconds["explore"], len(keys))
    clock = time.perf_counter()
    if max(len(keys), len(r_tgt)) >= 1 << 31:
        raise TooLarge("the compiled solver holds fewer than 2^31 nodes and robot moves; "
                       f"this game has {len(keys)} nodes and {len(r_tgt)} robot moves")
    rval, choice, top, missing = _solve(*explored[:7], *explored[8:], *tables.human_args())
    if missing:
        raise RuntimeError(f"internal error: {missing} human moves left the explored nodes")
    seconds["solve"] = time.perf_counter() - clock
    return Packed(tables, start, explored, rval, choice, int(top), seconds)


def solve_compiled(scene: Scene, formula: str | ast.Formula | None = None, *,
                   k: int | None = None, budget: float | None = None,
                   resolution: float = 1.0, symmetric: bool = True,
                   time_limit: float | None = None) -> Solution:
    """E_p, a strategy and plays, as `solve_explicit` computes them.  With
    `time_limit` (seconds), the layered solve when it is predicted to end
    in time (`packed.deadline`), else the AND-OR search on the same tables
    in the time left (`andor.search_tables`): `Solution.lower_units <= E_p
    <= units` when it proves no more, `stats["handed_over"]` saying why.
    A game with a zero-cost robot move that the layered solve cannot finish
    in time is `OutOfReach` (the search does not take it)."""
    k = check_parameters(scene, k, resolution)
    took = compile_kernels() if time_limit is None else _prepare_search()
    seconds = {} if took is None else {"compile": took}
    deadline = None if time_limit is None else Deadline(time_limit)
    clock = time.perf_counter()
    formula = task_formula(scene, formula)
    tables, start = packed_start(scene, formula, k, resolution, symmetric)
    seconds["tables"] = time.perf_counter() - clock
    if start is None:
        return won_at_start(scene, k, resolution, budget, seconds | {"explore": 0.0, "solve": 0.0})
    try:
        packed = _explore_with_bar(tables, start, seconds, deadline)
    except HandOver as why:
        reason = f"the layered solve {why}"
    else:
        return _answer(packed, budget)
    assert deadline is not None  # HandOver comes from a deadline only
    return _hand_over(tables, formula, budget, seconds, deadline, reason)


def _explore_with_bar(tables: Tables, start: int, seconds: dict[str, float], deadline: Deadline | None) -> Packed:
    """`explore_tables` with a bar of the nodes found, layer by layer, on a
    terminal once exploring takes over a second (and the deadline checked)."""
    k = tables.k
    with tqdm(desc="compiled solver: exploring", unit=" nodes", unit_scale=True, delay=1.0, leave=False,
              disable=None) as bar:
        def progress(h: int, nodes: int, lo: np.ndarray, done: int) -> None:
            bar.update(nodes - bar.n)
            bar.set_postfix_str(f"layer h = {h} of {k}", refresh=False)
            if deadline is not None:
                deadline.check(h, nodes, lo, done)

        return explore_tables(tables, start, seconds, progress, deadline)


def _answer(packed: Packed, budget: float | None) -> Solution:
    """The solved layers as a Solution: E_p, the worst-case strategy, plays."""
    seconds = packed.seconds
    clock = time.perf_counter()
    tables, explored = packed.tables, packed.explored
    scene, k, resolution = tables.scene, tables.k, tables.resolution
    keys, hflag, r_tgt, human_moves = explored[0], explored[1], explored[5], int(explored[7])
    graph = Graph(tables, explored[:7], packed.rval, packed.choice)
    result = None if packed.top >= INF else packed.top
    realizable = verdict(result, resolution, budget)
    principal: tuple[Step, ...]
    counter: tuple[Step, ...] | None
    if result is None:
        principal, counter = (), graph.counter_play(0)
        strategy: Mapping = {}
    else:
        principal = graph.principal_play(0)
        counter = principal if realizable is False else None
        strategy = CompiledStrategy(graph)
    seconds["solve"] += time.perf_counter() - clock
    humans = int(np.count_nonzero(hflag))
    stats = {"edges": len(r_tgt) + human_moves + humans, "robot_moves": len(r_tgt), "human_moves": human_moves}
    solution = Solution(None if result is None else in_costmap_units(result, resolution), result, resolution, budget,
                        realizable, k, len(keys) + humans, seconds, strategy, principal, counter,
                        scene.object_names, stats)
    return solution if tables.symmetry is None else tables.symmetry.realize(solution)


def _hand_over(tables: Tables, formula: ast.Formula, budget: float | None, seconds: dict[str, float],
               deadline: Deadline, reason: str) -> Solution:
    """The AND-OR search on `tables` in the time the limit has left (the
    layered arrays are gone by now), its stats saying why it answered."""
    from symsynth.solvers import andor

    seconds["explore"] = deadline.clock() - deadline.explore_start  # until the hand-over
    reason += f"; the AND-OR search answered in the {max(deadline.left(), 0.0):.1f} s left"
    try:
        solution = andor.search_tables(tables, formula, budget, seconds, max(deadline.left(), 0.0))
    except andor.ZeroCost:
        raise OutOfReach(f"{reason.split(';')[0]}, and the AND-OR search that answers anytime does not take "
                         "a game with a robot move of 0 units: drop the time limit, or use the forward search "
                         "(--solver forward)") from None
    stats = dict(solution.stats) | {"handed_over": reason}
    if solution.exact and solution.units is None:  # lost, proven by the search: no layered counter play
        stats["counter_play"] = "not built: the layered solve that builds it would not end within the limit"
    return dataclasses.replace(solution, stats=stats)


def _prepare_search() -> float | None:
    """The layered solver's kernels and the AND-OR search's, compiled or
    loaded (a time limit may hand the game over): the seconds, None when
    this process has them already."""
    from symsynth.solvers import andor

    return andor.prepare()


_compiled = False  # compile_kernels has run in this process


def compile_kernels() -> float | None:
    """Compile the kernels now (or load them from numba's disk cache) by
    solving a game of two interchangeable blocks and one human move; the
    seconds it took, or None when this process has done it already.

    The first solve of a process calls it, so that its `seconds` show the
    compiling as `compile` rather than inside `explore` and `solve`;
    comparison runs call it (`solve_compiled.prepare`) before their clock
    starts.  A fresh install pays about 20 s of CPU here, a cached one a
    third of a second; on a terminal a line on stderr says so when it takes
    more than a second.  A cache numba cannot write is an `InputError`."""
    global _compiled
    if _compiled:
        return None
    from symsynth.scene.load import scene_from_data

    places, grasp = ["l1", "l2", "l3", "e1"], "top"
    anchors = ["home"] + [f"{x}/{grasp}" for x in places]
    motions = [{"mode": "empty", "from": s, "to": t, "rules": [{"free": [], "cost": 2}]}
               for s in anchors for t in anchors[1:] if s != t]
    motions += [{"mode": f"{o}/{grasp}", "from": s, "to": t, "rules": [{"free": [], "cost": 3}]}
                for o in ("a", "b") for s in anchors[1:] for t in anchors[1:4] if s != t]
    scene = scene_from_data({
        "name": "compile-kernels",
        "objects": {"a": {"tags": ["block"], "at": "l1"}, "b": {"tags": ["block"], "at": "Else"}},
        "locations": places[:3], "else_samples": ["e1"], "grasps": [grasp],
        "primitives": {"grab": 1, "drop": 1}, "human": {"k": 1},
        "task": "F(at(block, l2) & at(block, l3))",
        "costmap": {"format": "symsynth.costmap/1", "motions": motions}})
    clock = time.perf_counter()
    notice = threading.Timer(1.0, lambda: print(
        "compiling the compiled solver's kernels: once per install, about 20 s, cached afterwards",
        file=sys.stderr, flush=True))
    if sys.stderr.isatty():
        notice.start()
    _compiled = True  # the solve below must not come back here
    try:
        won = solve_compiled(scene).cost_bound is not None  # a game the robot wins: every kernel ran
        compile_growth()  # and those only a larger game calls
    except OSError as error:  # numba writes the compiled kernels to its cache as it goes
        _compiled = False
        raise InputError(f"cannot compile the compiled solver's kernels: numba could not write its cache "
                         f"({error.strerror or error}); set NUMBA_CACHE_DIR to a writable folder with room, "
                         "or choose another solver (--solver explicit)") from None
    except BaseException:
        _compiled = False
        raise
    finally:
        notice.cancel()
    if not won:
        raise RuntimeError("internal error: the compiled solver's warm-up game was not won")
    return time.perf_counter() - clock


def kernels_cached(andor: bool = False) -> bool:
    """Whether a solve now would compile nothing: this process has compiled
    or loaded the kernels already, or numba's disk cache holds machine code
    for every kernel as it is now (an index entry for this source file, this
    CPU and the kernel's bytecode, as numba itself checks before loading).
    With `andor`, the AND-OR search's kernels (`packed.search`, `packed.trap`,
    and `packed.replies` for its replanning upper end) too; a kernel numba
    inlines into its callers (`inline="always"`) has no cache entry of its
    own and needs none.  False
    when numba's cache cannot be read this way (its layout is numba's own):
    then the compile is expected."""
    from symsynth.solvers import andor as andor_search

    if _compiled and (not andor or andor_search._prepared):
        return True
    try:
        from numba.core.registry import CPUDispatcher

        from symsynth.solvers.packed import replies, search, trap

        extra = [v for module in (search, replies, trap) for v in vars(module).values()
                 if isinstance(v, CPUDispatcher)] if andor else []
        return all(_cached(kernel) for kernel in kernels.dispatchers() + extra
                   if kernel.targetoptions.get("inline") != "always")  # (compiled into their callers only)
    except (AttributeError, TypeError, OSError):  # numba's private cache layout changed
        return False


def _cached(kernel) -> bool:
    cache, codegen = kernel._cache, kernel.targetctx.codegen()
    index = cache._cache_file._load_index()
    return any(key == cache._index_key(key[0], codegen) for key in index)


solve_compiled.prepare = compile_kernels  # type: ignore[attr-defined]  # symsynth.solvers.prepare
