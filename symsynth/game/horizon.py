"""How many human moves a play can use, and solving a large `k` without
iterating to it.

Every solver's work grows with `k` (one layer of positions per move left).
The value `V(h)` (E_p against a human with `h` moves) never decreases with
`h` (the human may pass), and beyond a point more moves can make no
difference.  Two facts say where, and this module uses them to solve a
game with `k` moves by solving one with `h <= k`.

**Infinite stays infinite.**  If `V(h) = inf` then `V(k) = inf` for every
`k >= h`: a human with `k` moves plays the one that wins with `h`.

**A strategy leaves the human moves it cannot use.**  Let every robot
action cost at least `c > 0` units (`least_units`), `V(h)` be finite, and
`m = floor(V(h) / c)`.  Against an optimal strategy `s_h` of the `h`-game,
every play takes at most `m` robot actions before the win (each costs at
least `c`, all of them at most `V(h)`).  At a human turn before the win the
robot still owes one more action (the human may pass), so at most `m - 1`
actions and hence at most `m - 1` human moves came before it: the human
never holds fewer than `h - m + 1` moves at its turn.  If `m < h` it always
holds one at least, so its counter never restricts it.  Then in the game
with `k >= h` moves, the strategy `s'(v, q, c) = s_h(v, q, c - (k - h))`
(the counter shifted) meets exactly the plays `s_h` meets, each human turn
offering the same moves, and pays at most `V(h)`: `V(k) <= V(h)`, and
with monotonicity `V(k) = V(h)`.  (`m <= h` would do; `m < h` is checked.)

Neither fact bounds `k` in general: the human can always move an object
that is not in the hand, and each move may cost the robot a constant more
(the toy gains 27 units per move, the benchmark family 107), so `V(k)`
can grow without end and the play uses every move; then the game is solved
with all `k`, one layer at a time, with a progress bar.

`solve_game` tries `h = 8, 16, 32, ...` below `k` (at most about twice the
work of solving `k` itself when neither fact applies) and returns the
solution for `k`: the same value and plays, the strategy shifted.  When
the value still grows at `h = MAX_LAYERS` and `k` is larger, the game is
refused with the values seen: it would need more than `MAX_LAYERS` layers
of positions, each as large as the game with one human move.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Iterator, Mapping

from tqdm import tqdm

from symsynth.errors import InputError
from symsynth.game.abstraction import quantize
from symsynth.game.solution import Position, Solution, check_parameters
from symsynth.logic import ast
from symsynth.scene.model import Scene

#: Below this `k` the game is solved as it is, without trying smaller ones.
FIRST_TRY = 8
#: The most human moves solved layer by layer (`solve_game`).
MAX_LAYERS = 256


class TooManyMoves(InputError):
    """A `k` whose every move may count, beyond `MAX_LAYERS` (the message
    starts with `k = K`; the command line says where K came from)."""


def least_units(scene: Scene, resolution: float) -> int:
    """A lower bound on the units of every robot action of the scene: the
    least of grab, drop and every costmap rule, rounded up (semantics §4, §5).

    A motion costs the largest rule cost over its start and goal anchors,
    and 0 only for a pair with start = goal; the only motion whose every
    pair is such is a transit between objects in Else with a single Else
    sample (both ends `e1/a`), so then the bound is 0."""
    if len(scene.else_samples) == 1:
        return 0
    costs = [scene.grab_cost, scene.drop_cost]
    if scene.costmap is not None:
        costs += [rule.cost for rule in scene.costmap.all_rules()]
    return min((quantize(c, resolution) for c in costs if math.isfinite(c)), default=0)


def moves_usable(units: int, least: int) -> int | None:
    """The human moves a play can use against an optimal strategy of value
    `units` (module docstring: at most `floor(units / least)`); None when
    not bounded (zero-cost actions)."""
    return units // least if least > 0 else None


def solve_game(solver: Callable[..., Solution], scene: Scene, formula: str | ast.Formula | None = None,
               *, k: int | None = None, budget: float | None = None, resolution: float = 1.0,
               tried: Callable[[int, Solution], None] | None = None) -> Solution:
    """`solver`'s solution for `k` human moves (default: the scene's), found
    by solving with fewer moves where the module docstring's facts allow.
    `tried(h, solution)` is told of each smaller game solved on the way."""
    k = check_parameters(scene, k, resolution)
    least = least_units(scene, resolution)
    h, seen = FIRST_TRY, []
    with tqdm(desc="human moves tried", unit=" solves", delay=1.0, leave=False, disable=None) as bar:
        while h < k and h <= MAX_LAYERS:
            bar.set_postfix_str(f"k = {h} of {k}")
            solution = solver(scene, formula, k=h, budget=budget, resolution=resolution)
            bar.update()
            if tried is not None:
                tried(h, solution)
            usable = None if solution.units is None else moves_usable(solution.units, least)
            if solution.units is None or (usable is not None and usable < h):
                return for_more_moves(solution, k, usable)
            seen.append((h, solution.units))
            h *= 2
    if k > MAX_LAYERS:
        raise TooManyMoves(
            f"k = {k}: the value still grows with the human's moves ("
            + ", ".join(f"E_p = {u} units with {m}" for m, u in seen[-3:])
            + f"), so every one of the {k} moves may count, and the game is solved one layer of "
            f"positions per move: at most {MAX_LAYERS} moves are solved that way")
    return solver(scene, formula, k=k, budget=budget, resolution=resolution)


def for_more_moves(solution: Solution, k: int, usable: int | None) -> Solution:
    """The solution of the same game with `k >= solution.k` moves, by the
    module docstring's facts: the same value and plays, the strategy read
    with the counter shifted by `k - solution.k`."""
    shift = k - solution.k
    stats = dict(solution.stats) | {"solved_with_k": solution.k}
    if usable is not None:
        stats["moves_usable"] = usable
    return dataclasses.replace(solution, k=k, strategy=ShiftedStrategy(solution.strategy, shift),
                               stats=stats)


class ShiftedStrategy(Mapping):
    """`inner`'s actions with every position's moves-left raised by `shift`:
    position (v, q, c) here is (v, q, c - shift) there."""

    def __init__(self, inner: Mapping[Position, str], shift: int):
        self._inner = inner
        self._shift = shift

    def __getitem__(self, position: Position) -> str:
        v, q, c = position
        if c < self._shift:
            raise KeyError(position)
        return self._inner[(v, q, c - self._shift)]

    def __iter__(self) -> Iterator[Position]:
        return ((v, q, c + self._shift) for v, q, c in self._inner)

    def __len__(self) -> int:
        return len(self._inner)
