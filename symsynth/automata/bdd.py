"""The BDD backend and the few BDD routines the automata need.

The backend is chosen here, once: CUDD through `dd.cudd` (the `dd` wheel
ships it), or the pure-Python `dd.autoref` when CUDD is missing.  Everything
else imports `BDD` and `Function` from this module.
"""

from __future__ import annotations

import gc
import importlib
import sys
import warnings
from collections.abc import Collection, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any, TypeAlias


@contextmanager
def _without_networkx() -> Iterator[None]:
    """dd imports networkx when it is first imported (`dd._utils`, for its
    `to_nx` graph export, which symsynth does not use): 70-90 ms, a third
    of `symsynth dfa`'s whole run.  Inside the block `import networkx`
    fails (a None entry in sys.modules), so dd takes it as missing; after
    it, dd's lookup imports networkx on demand, so `to_nx` still works.
    Nothing changes when networkx is already imported."""
    if "networkx" in sys.modules:
        yield
        return
    sys.modules["networkx"] = None  # type: ignore[assignment]
    try:
        yield
    finally:
        del sys.modules["networkx"]
        utils = sys.modules.get("dd._utils")
        if utils is not None and getattr(utils, "_nx", True) is None:
            utils.import_module = importlib.import_module  # type: ignore[attr-defined]


with _without_networkx():
    try:
        from dd import cudd as _backend
        BACKEND = "cudd"
    except ImportError:  # pragma: no cover - only without the CUDD extension
        from dd import autoref as _backend
        BACKEND = "autoref"

#: The backend's manager and node types (`dd.cudd` or `dd.autoref`), untyped to the
#: type checker: dd.cudd is a compiled module without stubs.
BDD: TypeAlias = Any
Function: TypeAlias = Any
Cube = tuple[tuple[str, bool], ...]  # a conjunction of literals, as (variable, polarity)


def new_manager(*, reordering: bool = False, memory: int = 2**27, cache: int = 2**14) -> BDD:
    """A fresh manager.  Reordering is off unless asked for: several routines
    rely on declared order (atoms above the variables that follow them).

    `memory` (bytes) bounds what CUDD may give its computed table as it grows;
    `cache` is that table's initial number of slots."""
    # dd's default sizes CUDD for 1 GiB: 17-20 ms to create and free, more
    # than most compilations take.  Start small; CUDD grows on demand.
    if BACKEND != "cudd":  # pragma: no cover - only without CUDD
        bdd = _backend.BDD()
        bdd.configure(reordering=reordering)
        return bdd
    # CUDD's estimate does two things: it sets how long the unique table grows
    # freely before collecting garbage (`loose_up_to`, memory / 160), and it
    # reserves a stash of memory / 128 for running out of memory, allocated at
    # once: 45 ms for 4 GiB, paid by every game however small.  The stash is
    # kept at the size of `_STASHED`; the growth policy is the one asked for.
    bdd = _backend.BDD(memory_estimate=min(memory, _STASHED), initial_cache_size=cache)
    bdd.configure(reordering=reordering, loose_up_to=memory // _LOOSE_FRACTION)
    return bdd


#: The most a manager's estimate reserves at its creation (CUDD's stash).
_STASHED = 2**27
#: CUDD's `looseUpTo` is `maxMemory / sizeof(DdNode) / DD_MAX_LOOSE_FRACTION` = memory / (32 * 5).
_LOOSE_FRACTION = 160


@contextmanager
def fixed_order(bdd: BDD) -> Iterator[None]:
    """Dynamic reordering suspended inside the block, restored after.

    Sifting minimizes the BDDs alive when it runs, not the intermediate
    results of the operation under way: in the middle of a fixpoint over
    pairs of states it lifts the atoms above the state bits, and every
    BDD relating a state to its successor then remembers all atoms before
    it reads a bit (see `SymbolicDFA.minimize`)."""
    old = bdd.configure(reordering=False)["reordering"]
    try:
        yield
    finally:
        bdd.configure(reordering=old)


@contextmanager
def without_cyclic_gc() -> Iterator[None]:
    """Python's cyclic garbage collector paused, restored after.  BDD work
    makes Python objects by the million and no reference cycles (a
    compilation leaves none: tests/test_compose.py), but their allocation
    triggers full collections, each a walk over every object of the
    process (lark's, numpy's, ...: 16-21 ms here): a third of nim_03_01's
    0.05 s compilation when one falls inside, and urright14's transition
    bits made after the compilation took 15.2 s with it where they take
    11.7 s without (load 1.4-1.9)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def and_exists(bdd: BDD, u: Function, v: Function, qvars: Collection[str]) -> Function:
    """\\E qvars: u /\\ v, in one pass where the backend has it."""
    if BACKEND == "cudd":
        return _backend.and_exists(u, v, qvars)
    return bdd.exist(qvars, u & v)  # pragma: no cover - only without CUDD


def cofactor(bdd: BDD, values: Mapping[str, bool], u: Function) -> Function:
    """`u` with each variable of `values` fixed to its value.

    Not `bdd.let(values, u)`: with Boolean values dd.cudd's `let` is CUDD's
    `Cudd_Cofactor`, which on long runs leaves CUDD's count of dead nodes
    wrong (`Cudd_DebugCheck` fails after some 28,000 guards printed from
    Random/Syft's syft_2/001), and the process then aborts at the next
    garbage collection ("cuddGarbageCollect: problem in table ... dead
    count != deleted").  The same cofactors as one `Cudd_bddAndAbstract`
    with the cube of `values` kept the counts right over twice as many
    (docs/ltlf.md, "A CUDD abort, and why symsynth never calls
    `Cudd_Cofactor`").  Every Boolean substitution goes
    through here."""
    if not values:
        return u
    if BACKEND == "cudd":
        return _backend.and_exists(u, bdd.cube(dict(values)), values.keys())
    return bdd.let(dict(values), u)  # pragma: no cover - only without CUDD


def exists(bdd: BDD, u: Function, qvars: Sequence[str]) -> Function:
    """\\E qvars: u.  (dd.cudd's `exist` goes through its general
    `quantify`: twice the time of this one call on small BDDs.)"""
    if BACKEND == "cudd":
        return _backend.and_exists(u, bdd.true, qvars)
    return bdd.exist(qvars, u)  # pragma: no cover - only without CUDD


def swap(bdd: BDD, u: Function, renaming: Mapping[str, str]) -> Function:
    """`u` with each variable `x` of `renaming` exchanged with
    `renaming[x]`: a renaming when `u` reads none of the targets.  (CUDD's
    permutation, where dd's `let` composes a vector over every variable.)"""
    if BACKEND == "cudd":
        return bdd._swap(u, dict(renaming))
    inverse = {v: k for k, v in renaming.items()}  # pragma: no cover - only without CUDD
    return bdd.let({**renaming, **inverse}, u)  # pragma: no cover


def disjoin(bdd: BDD, items: Iterable[Function]) -> Function:
    """The disjunction of `items`, joined in a balanced tree: OR-ing them
    one by one into a growing result costs the result's size each time
    (quadratic on a DFA's relation of thousands of states: most of a
    minimization's time on Nim's products), pairwise about its size once
    per level."""
    layer = list(items)
    if not layer:
        return bdd.false
    while len(layer) > 1:
        layer = [layer[i] | layer[i + 1] if i + 1 < len(layer) else layer[i] for i in range(0, len(layer), 2)]
    return layer[0]


def restrict(bdd: BDD, u: Function, care: Function) -> Function:
    """A function equal to `u` where `care` holds, usually smaller
    (Coudert and Madre's restrict); `u` itself without CUDD."""
    if BACKEND == "cudd":
        return _backend.restrict(u, care)
    return u  # pragma: no cover - only without CUDD


def peak_nodes(bdd: BDD) -> int:
    """The most BDD nodes the manager has held at once."""
    if BACKEND != "cudd":  # pragma: no cover - only without CUDD
        return len(bdd)
    with warnings.catch_warnings():  # dd warns that the unrelated "mem" changed units
        warnings.simplefilter("ignore")
        return int(bdd.statistics()["peak_nodes"])


def shared_size(bdd: BDD, roots: Sequence[Function]) -> int:
    """The BDD nodes of `roots` together, shared nodes once (the constant
    too).  CUDD counts them in C: the walk below, one Python step a node,
    took 4.9 s of nim_06_01's 35.9 s as a process (`symsynth dfa` prints
    the count, 2,356,145 nodes; 0.7 s in C; load 3)."""
    if BACKEND == "cudd":
        return int(_backend.count_nodes(list(roots)))
    seen = set()  # pragma: no cover - only without CUDD
    stack = list(roots)
    while stack:
        u = stack.pop()
        key = int(u) if not getattr(u, "negated", False) else int(~u)
        if key in seen:
            continue
        seen.add(key)
        if u != bdd.true and u != bdd.false:
            stack.extend((u.low, u.high))
    return len(seen)


def branches(bdd: BDD, u: Function) -> tuple[Function, Function]:
    """The (low, high) cofactors of `u` with respect to its top variable.

    `dd.cudd` exposes complemented edges: the children of a negated node
    must be negated too.
    """
    low, high = u.low, u.high
    if getattr(u, "negated", False):
        return ~low, ~high
    return low, high


def split_letters(bdd: BDD, u: Function, top: int,
                  below: dict[Function, dict[Function, Function]] | None = None) -> dict[Function, Function]:
    """The nodes where the paths of `u` leave the atom levels (the levels
    above `top`: the letter read), each with the set of letters leading
    there, as a BDD over the atoms.

    Bottom-up over the BDD's nodes at atom levels (each node once, not each
    path: a path per letter class is exponential in the atoms): below[v]
    maps each node reachable from v to its guard.  A caller that splits
    many BDDs sharing nodes passes one `below` to all calls (the result
    must then not be modified)."""
    if below is None:
        below = {}
    true, false = bdd.true, bdd.false
    stack = [(u, False)]
    while stack:
        node, ready = stack.pop()
        if node in below:
            continue
        if node == true or node == false or node.level >= top:
            below[node] = {node: true}
            continue
        low, high = branches(bdd, node)
        if not ready:
            stack.append((node, True))
            stack.extend(child for child in ((low, False), (high, False)) if child[0] not in below)
            continue
        x = bdd.var(node.var)
        found = {succ: ~x & guard for succ, guard in below[low].items()}
        for succ, guard in below[high].items():
            found[succ] = found[succ] | (x & guard) if succ in found else x & guard
        below[node] = found
    return below[u]


def exits(bdd: BDD, u: Function, top: int, seen: set[Function] | None = None) -> Iterator[Function]:
    """The nodes where the paths of `u` leave the atom levels (the levels
    above `top`: the successors `split_letters` gives, without their
    guards), each once, in the order a depth-first walk (high branch first)
    meets them.  `seen`: nodes walked already (by earlier calls sharing
    it), neither walked nor given again."""
    true, false = bdd.true, bdd.false
    seen = set() if seen is None else seen
    stack = [u]
    while stack:
        node = stack.pop()
        if node in seen:
            continue
        seen.add(node)
        if node == true or node == false or node.level >= top:
            yield node
        else:
            stack += branches(bdd, node)  # (high popped first)


def children_first(bdd: BDD, root: Function, done: Any) -> Iterable[tuple[Function, Function, Function]]:
    """The nodes under `root` not in `done`, each after its children, as
    `(node, low, high)` (cofactors as `branches` gives them), without
    recursion.  The caller adds each node it is given to `done` (a dict or
    set holding the terminals from the start) before asking for the next."""
    stack = [root]
    while stack:
        u = stack[-1]
        if u in done:
            stack.pop()
            continue
        low, high = branches(bdd, u)
        missing = [c for c in (low, high) if c not in done]
        if missing:
            stack.extend(missing)
            continue
        stack.pop()
        yield u, low, high


def is_constant(bdd: BDD, u: Function) -> bool:
    return u == bdd.true or u == bdd.false


def isop(bdd: BDD, f: Function) -> list[Cube]:
    """An irredundant sum of products of `f` (Minato–Morreale).

    Returns cubes whose disjunction is exactly `f`; no cube and no literal
    can be dropped.  Used to print guards readably.
    """
    memo: dict[tuple[Function, Function], tuple[Function, list[Cube]]] = {}

    def rec(lower: Function, upper: Function) -> tuple[Function, list[Cube]]:
        # returns (cover, cubes) with lower <= cover <= upper
        if lower == bdd.false:
            return bdd.false, []
        if upper == bdd.true:
            return bdd.true, [()]
        key = (lower, upper)
        if key in memo:
            return memo[key]
        top = min((u for u in (lower, upper) if not is_constant(bdd, u)), key=lambda u: u.level)
        var = top.var
        x = bdd.var(var)
        l0, l1 = _split_on(bdd, lower, top.level)
        u0, u1 = _split_on(bdd, upper, top.level)
        c0, cubes0 = rec(l0 & ~u1, u0)  # minterms that need x = 0
        c1, cubes1 = rec(l1 & ~u0, u1)  # minterms that need x = 1
        rest_lower = (l0 & ~c0) | (l1 & ~c1)
        cs, cubes_s = rec(rest_lower, u0 & u1)  # the rest, independent of x
        cover = (~x & c0) | (x & c1) | cs
        cubes = ([((var, False),) + c for c in cubes0]
                 + [((var, True),) + c for c in cubes1] + cubes_s)
        memo[key] = (cover, cubes)
        return cover, cubes

    return rec(f, f)[1]


def _split_on(bdd: BDD, u: Function, level: int) -> tuple[Function, Function]:
    """The cofactors of `u` on the variable at `level`, at or above `u`'s top."""
    if is_constant(bdd, u) or u.level != level:
        return u, u
    return branches(bdd, u)


def format_cubes(cubes: Iterable[Cube], names: Mapping[str, str] | None = None) -> str:
    """Print a sum of products with `!`, `&`, `|`, `true`, `false`."""
    names = names or {}
    terms = []
    for c in cubes:
        lits = [("" if value else "!") + names.get(var, var) for var, value in c]
        terms.append(" & ".join(lits) if lits else "true")
    if not terms:
        return "false"
    if "true" in terms:
        return "true"
    if len(terms) == 1:
        return terms[0]
    return " | ".join(f"({t})" if " & " in t else t for t in terms)


def lexmin(bdd: BDD, f: Function, variables: Iterable[str]) -> tuple[bool, ...]:
    """The least satisfying assignment of `f` over `variables` (false < true,
    first variable most significant).  A canonical name for a non-empty set
    that does not depend on the variable order."""
    values = []
    for var in variables:
        low = f & ~bdd.var(var)
        if low != bdd.false:
            f, value = low, False
        else:
            f, value = f & bdd.var(var), True
        values.append(value)
    return tuple(values)
