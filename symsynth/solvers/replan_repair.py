"""The replanning strategy that may repair (issue 32): σ' pays at most what
σ pays (`solvers.replan_budget`) and is far cheaper to certify.

σ' follows a **route**: a list of robot actions to a win.  σ's route from a
position is its no-human plan (`solvers.replan`); σ' may also prefix it
with a repair.  At a human move m at turn y of its route, with h >= 1 moves
left after m, σ' either

- **replans** as σ does: its route is then σ's plan from m y; or
- **repairs**: carries the moved object back and the hand where it was
  (`packed.replies._repair_path`: each action generated at the state it is
  played in, its cost there, the DFA reading every letter, the last state
  y itself with y's DFA state, or a win), then goes on with the route it had
  from y, y a human turn again (one move fewer).

With no move left after m it replans (σ: a least-cost plan wins).  Write
c(y) for what the route costs from its turn y, and R'_h(route) for what σ'
may pay above c(start of the route) with h moves left; then

    R'_0 = 0,
    R'_h(route) = max(0, max over turns y of the route and moves m there of
                  min(V_0(m y) + R'_{h-1}(σ's plan from m y),
                      f(m, y) + c(y) + R'_{h-1}(repair ++ route from y)) - c(y)),

f the repair's cost (c(y) counts 0 after a repair that wins).  The turns
of "repair ++ route from y" are the repair's own (after each of its
actions but the last) and then y and the route's on; σ's plan from y is
the suffix of σ's plan through y (plans are read from the memo's chosen
actions, node after node), so the turns of a σ plan keep their own
answers as `solvers.replan_budget` keeps them.  σ' chooses the branch of
the smaller bound (or, as tests/test_replan_repair.py plays it, the repair
whenever it fits the budget left, else σ's branch), keeping its route (and
the budget left) as memory; by induction on h it pays at most c + R'_h
from a turn of its route (a repair's plan wins or comes back, σ's plans
win), so a yes to "R'_k(start) <= T - V_0(start)?" proves E_p <= T.  The
min contains σ's branch, so R' <= R position by position and every yes of
σ's question is one here.  The human's turns inside a repair cannot be left
out: without them the recursion claims 15 where E_p = 23 (a generated
scene, the tests' seed 55).

At h = 1 σ' is σ: the question there is `BudgetedBound`'s.  Only `_deeper`
(the moves at h >= 2) changes: each move is asked the repair first, which
needs no V_0 search: the repair's turns at h - 1 (at h - 1 = 1 the same
kernel question as σ's turns, `packed.replies._settle`, whose certificates
bound V_0 from above also where the route costs more than V_0), then the
route's from y (σ's turns: answered and kept as before).  Only a move the
repair does not fit goes to σ's branch.  A turn inside a repair has a
route that costs more than its V_0; at h = 1 its answer is kept as the
largest V_0 bound of its moves (what a route costs after it does not
matter there), above that it is asked each time.

Measured (bench/results/replan-repair.md): no cheaper than σ's question.
It asks 60 % fewer V_0, but each turn inside a repair is a new position
whose moves the replies' kernel must answer, and that kernel is the cost;
at 8 x 12 x k = 3 "<= 906?" 133.6 s against σ's 128.2 s.  So the solver
does not use it.
"""

from __future__ import annotations

import math

import numpy as np

from symsynth.solvers.packed import replies as rk
from symsynth.solvers.replan_budget import BudgetedBound

INF = math.inf

#: A route's turns before σ's plan: packed states, DFA states, what the route costs from each, its action there
Prefix = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
#: σ's plan that ends a route: (packed state, DFA state) of its first turn (a human turn), None after a win
Tail = tuple[int, int] | None


class RepairingBound(BudgetedBound):
    """"Does σ' pay at most T from the start?" (module doc); `within` and
    `least` as `BudgetedBound`'s, for σ' (σ itself at h <= 1)."""

    name = "σ'"

    @property
    def strategy(self):
        """Refused: a yes here certifies σ', which keeps a route as memory, and
        σ itself may pay more (B' < B on some scenes), so σ's strategy must not
        be returned for σ''s bound; the tests play σ' themselves."""
        raise NotImplementedError("σ' is not a positional strategy: its bound is not σ's")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._abs1: dict[tuple[int, int], tuple[float, float]] = {}  # a turn at h = 1: (largest no, least yes) of V_0
        self._tails: dict[tuple[int, int], tuple[np.ndarray, ...]] = {}
        self._path = np.empty((8, 4), np.int64)
        self.repaired = 0  # moves answered by a repair at h >= 2
        self.replanned = 0  # moves that went to σ's branch at h >= 2

    def worst_play(self, upper: int):
        """σ's plan with the human passing: σ' keeps no worst play."""
        return self.passing_play()

    # -- the moves at h >= 2 --------------------------------------------------------------
    def _deeper(self, xs: np.ndarray, qs: np.ndarray, left: np.ndarray, h: int, s: float,
                upper: np.ndarray | None = None) -> bool:
        """At h >= 2, the moves at σ's turns (xs, qs), V_0 there `left`: each
        within left + s under σ', a repair asked first (module doc)."""
        empty = _empty()
        for j in range(len(xs)):
            route = (empty, (int(xs[j]), int(qs[j])))
            if not self._turn_fits(int(xs[j]), int(qs[j]), float(left[j]), route, h, s):
                self._record((int(xs[j]), int(qs[j]), h), s, False)
                return False
            self._record((int(xs[j]), int(qs[j]), h), s, True)
        return True

    def _turn_fits(self, y: int, qy: int, c: float, route: tuple[Prefix, Tail], h: int, s: float) -> bool:
        """Every human move at turn (y, qy) of `route` (the route from y, y
        included), which costs c from y, h moves left there: σ' pays at most
        c + s after it."""
        count = self._replies(np.array([y]), np.array([qy]))
        keys = self._keys[:count].copy()
        hard = []
        for key in keys.tolist():
            if key < 0:  # the move makes the task hold
                continue
            w, q2 = self.memo.position(key)
            if self._repair_fits(y, qy, c, route, w, q2, h - 1, c + s):
                self.repaired += 1
            else:
                hard.append((w, q2))
        self.replanned += len(hard)
        branch = sorted(((self.value(w, q2), w, q2) for w, q2 in hard), reverse=True)
        return all(self._fits(w, q2, h - 1, c + s - v, False) for v, w, q2 in branch)

    def _repair_fits(self, y: int, qy: int, c: float, route: tuple[Prefix, Tail], w: int, q2: int, h: int,
                     b: float) -> bool:
        """σ' pays at most b from (w, q2), a move at turn y of `route`, h >= 1
        moves left, when it repairs."""
        self._look()
        count = int(rk._repair_path(y, qy, w, q2, self.memo.P, self.memo.G, self.memo.S(), self._path))
        if count < 0:
            return False
        if count == 0:  # the move left the state as it was (an object moved within Else)
            return self._route_fits(*route, h, b - c)
        path = self._path[:count].copy()
        won = bool(self.t.accepting[path[-1, 1]])
        units = np.cumsum(path[:, 2])
        after = 0.0 if won else c  # what the route costs after the repair
        if units[-1] + after > b:
            return False
        own = (path[:-1, 0], path[:-1, 1], units[-1] - units[:-1] + after, path[1:, 3])
        prefix, tail = (own, None) if won else (_join(own, route[0]), route[1])
        return self._route_fits(prefix, tail, h, b - units[-1] - after)

    def _route_fits(self, prefix: Prefix, tail: Tail, h: int, s: float) -> bool:
        """R'_h(route) <= s: at every turn of the prefix, then of σ's plan at the tail."""
        if s < 0:
            return False
        if tail is not None and not self._fits(*tail, h, s, True):
            return False
        if len(prefix[0]) == 0:
            return True
        if h == 1:
            return self._prefix_settles(prefix, tail, s)
        xs, qs, cs, codes = prefix
        for j in range(len(xs)):
            rest = ((xs[j:], qs[j:], cs[j:], codes[j:]), tail)
            if not self._turn_fits(int(xs[j]), int(qs[j]), float(cs[j]), rest, h, s):
                return False
        return True

    def _prefix_settles(self, prefix: Prefix, tail: Tail, s: float) -> bool:
        """V_0(m y) <= c(y) + s for every move m at every turn y of the prefix
        (at h = 1: σ' replans), each turn's answer kept as a bound on V_0."""
        xs, qs, cs, codes = prefix
        todo = []
        for j in range(len(xs)):
            no, yes = self._abs1.get((int(xs[j]), int(qs[j])), (-1.0, INF))
            if cs[j] + s <= no:
                return False
            if cs[j] + s < yes:
                todo.append(j)
        if not todo:
            return True
        plan = prefix if tail is None else _join(prefix, self._tail(*tail))
        turns = np.array(todo, np.int64)
        count = self._replies(xs[turns], qs[turns])
        turn = turns[self._turn[:count]]
        r, upper = self._settle(self._keys[:count].copy(), plan[2][turn] + s, turn, plan, self.memo)
        done = turn[r] if r < count else len(xs)
        largest = np.zeros(len(xs))
        np.maximum.at(largest, turn[:r], upper[:r])
        for j in todo:
            key = (int(xs[j]), int(qs[j]))
            no, yes = self._abs1.get(key, (-1.0, INF))
            if j < done:
                self._abs1[key] = (no, min(yes, float(largest[j])))
            elif j == done:
                self._abs1[key] = (max(no, float(cs[j] + s)), yes)
        return r >= count

    def _tail(self, x: int, q: int) -> tuple[np.ndarray, ...]:
        """σ's turns from (x, q), a human turn (`_turns`), kept."""
        found = self._tails.get((x, q))
        if found is None:
            xs, qs, left, codes = self._turns(x, q, True)
            found = self._tails[(x, q)] = (xs.copy(), qs.copy(), left.astype(np.float64), codes.copy())
        return found


def _empty() -> Prefix:
    return (np.empty(0, np.int64), np.empty(0, np.int64), np.empty(0), np.empty(0, np.int64))


def _join(a: tuple[np.ndarray, ...], b: tuple[np.ndarray, ...]) -> Prefix:
    return tuple(np.concatenate((u, v)) for u, v in zip(a, b))  # type: ignore[return-value]
