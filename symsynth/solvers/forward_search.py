"""The forward solver's memo and its bounded AND-OR search: "is val(p) <= b?"
asked depth first, with what is proven about each position (lo, hi) kept
across questions and rounds.

The algorithm and why it is exact are in `solvers.forward`, which drives
the rounds, answers with a deadline and builds the strategies from this
memo.
"""

from __future__ import annotations

import heapq
import math
import operator
import time
from collections.abc import Callable, Iterator, Mapping

from symsynth.automata.symbolic import State as DFAState
from symsynth.game.abstraction import State, in_costmap_units
from symsynth.game.graph import PASS, GameGraph, Node
from symsynth.game.solution import Step

INF = math.inf
deadline_clock = time.perf_counter  # what deadlines are measured by (tests count questions instead)


class OutOfTime(Exception):
    """The search's deadline passed (raised from inside the search)."""


Key = tuple[State, DFAState, int]  # (v, q, h)


class Search:
    """The memo and the bounded AND-OR search (module doc).

    Positions (v, q, h) get integer ids on first sight; a robot-turn and a
    human-turn position with the same (v, q, h) share the id, with separate
    bounds.  Moves are generated once per id and kept as ids.
    """

    check_mask = 0x3FF  # the deadline is looked at every 1024 questions

    def __init__(self, game: GameGraph, bound: Callable[[State, int, bool], float]):
        self.game = game
        self.bound = bound
        self.ids: dict[Key, int] = {}
        self.keys: list[Key] = []
        self.lo_r: list[float] = []
        self.lo_h: list[float] = []
        self.hi_r: dict[int, tuple[int, str]] = {}  # (hi, action)
        self.hi_h: dict[int, int] = {}
        self._robot: dict[int, list[tuple[int, str, int]]] = {}  # (units, action, id; WIN = -1)
        self._human: dict[int, list[int]] = {}  # pass first; WIN = -1
        self._refuter: dict[int, int] = {}  # the reply that last showed val > b
        self._zero: dict[int, bool] = {}  # robot positions with a zero-cost action
        self.closures = 0
        self.calls = 0
        self.rounds = 0
        self.on_round: Callable[[int], None] | None = None  # told of each round's budget (solve_forward)
        self.explored = 0  # qualitative explorations run
        self.tightened = 0  # `_tighten` passes run
        self._tightened_at = 0  # `calls` at the last one
        self.deadline: float | None = None  # perf_counter time: past it, a question raises OutOfTime

    def id(self, key: Key) -> int:
        i = self.ids.get(key)
        if i is None:
            i = self.ids[key] = len(self.keys)
            self.keys.append(key)
            v, q, h = key
            lo_r, lo_h = self.bound(v, h, True), self.bound(v, h, False)
            for below in range(h):  # val grows with h
                j = self.ids.get((v, q, below))
                if j is not None:
                    lo_r = max(lo_r, self.lo_r[j])
                    lo_h = max(lo_h, self.lo_h[j])
            self.lo_r.append(lo_r)
            self.lo_h.append(max(lo_h, lo_r))  # the human may pass
        return i

    # -- moves ------------------------------------------------------------------------
    def robot_options(self, i: int) -> list[tuple[int, str, int]]:
        """(units, action, id of the human position after, or -1 for a win)."""
        out = self._robot.get(i)
        if out is None:
            v, q, h = self.keys[i]
            out = self._robot[i] = [
                (units, action, -1 if node is None else self.id((node.v, node.q, node.h)))
                for action, node, units, _ in self.game.moves(Node(v, q, h, True))]
        return out

    def human_options(self, i: int) -> list[int]:
        """Ids of the robot positions after the pass and each move; -1 for a win."""
        out = self._human.get(i)
        if out is None:
            v, q, h = self.keys[i]
            out = self._human[i] = [
                -1 if node is None else self.id((node.v, node.q, node.h))
                for _, node, _, _ in self.game.moves(Node(v, q, h, False))]
        return out

    def steps(self, i: int, robot: bool) -> list[tuple[str, int, State, int]]:
        """(action, units, state after, id after or -1 for a win) of each
        move at i, in the order of `game.moves`: for writing plays."""
        v, q, h = self.keys[i]
        after = ([j for _, _, j in self.robot_options(i)] if robot else self.human_options(i))
        return [(action, units, state, j)
                for (action, _, units, state), j in zip(self.game.moves(Node(v, q, h, robot)), after)]

    # -- "val <= b?" ----------------------------------------------------------------------
    def robot(self, i: int, b: int) -> bool:
        self.calls += 1
        if self.deadline is not None and self.calls & self.check_mask == 0 and deadline_clock() > self.deadline:
            raise OutOfTime
        hi = self.hi_r.get(i)
        if hi is not None and hi[0] <= b:
            return True
        if self.lo_r[i] > b:
            return False
        if self._zero_cost(i):
            return self._closure(i, b)
        # every action costs >= 1: the questions below have smaller budgets
        for f, units, action, j in self._ranked(i):
            if f > b:
                break
            if j < 0:
                self._prove_robot(i, units, action)
                return True
            if self.human(j, b - units):
                self._prove_robot(i, units + self.hi_h[j], action)
                return True
        self._bellman_robot(i)
        return False

    def human(self, i: int, b: int) -> bool:
        self.calls += 1
        if self.deadline is not None and self.calls & self.check_mask == 0 and deadline_clock() > self.deadline:
            raise OutOfTime
        hi = self.hi_h.get(i)
        if hi is not None and hi <= b:
            return True
        lo_h, lo_r = self.lo_h, self.lo_r
        if lo_h[i] > b:
            return False
        replies = [j for j in self.human_options(i) if j >= 0]
        worst = max((lo_r[j] for j in replies), default=0)
        if worst > lo_h[i]:
            lo_h[i] = worst
        if worst > b:
            return False
        replies.sort(key=lambda j: -lo_r[j])
        first = self._refuter.get(i)
        if first is not None:
            replies.insert(0, first)
        for j in replies:
            if not self.robot(j, b):
                if lo_r[j] > lo_h[i]:
                    lo_h[i] = lo_r[j]
                self._refuter[i] = j
                return False
        self._prove_human(i, max((self.hi_r[j][0] for j in replies), default=0))
        return True

    def _prove_robot(self, i: int, hi: int, action: str) -> None:
        old = self.hi_r.get(i)
        if old is None or hi < old[0]:
            self.hi_r[i] = (hi, action)

    def _prove_human(self, i: int, hi: int) -> None:
        old = self.hi_h.get(i)
        if old is None or hi < old:
            self.hi_h[i] = hi

    def _estimates(self, i: int) -> Iterator[tuple[float, int, str, int]]:
        """(c + lo(after), c, action, after) for each action of the robot
        position `i`; a win's estimate is its cost c."""
        lo_h = self.lo_h
        return ((units if j < 0 else units + lo_h[j], units, action, j)
                for units, action, j in self.robot_options(i))

    def _ranked(self, i: int) -> list[tuple[float, int, str, int]]:
        """`_estimates` in increasing order (`robot_options`' order on ties)."""
        return sorted(self._estimates(i), key=operator.itemgetter(0))

    def _bellman_robot(self, i: int) -> None:
        """lo := min over actions of c + lo(after), if larger: still a lower bound."""
        best = min((f for f, _, _, _ in self._estimates(i)), default=INF)
        if best > self.lo_r[i]:
            self.lo_r[i] = best

    def _zero_cost(self, i: int) -> bool:
        zero = self._zero.get(i)
        if zero is None:
            zero = self._zero[i] = any(units == 0 and j >= 0 for units, _, j in self.robot_options(i))
        return zero

    def _closure(self, start: int, b: int) -> bool:
        """"val(start) <= b?" where zero-cost actions can lead back to it with
        the same budget: the robot positions reachable from `start` by
        zero-cost actions and passes (with the human positions between)
        form a small reachability game at budget b, solved as a least
        fixpoint.  Its exits (actions that cost something, human moves) ask
        questions with a smaller budget or fewer human moves, which never
        come back here.  Positions left out of the fixpoint have val > b."""
        self.closures += 1
        robots, humans = self._zero_cost_region(start)
        lo_r, lo_h, hi_r, hi_h = self.lo_r, self.lo_h, self.hi_r, self.hi_h
        won_r = {x for x in robots if x in hi_r and hi_r[x][0] <= b}
        won_h = {y for y in humans if y in hi_h and hi_h[y] <= b}
        exits_tried: set[int] = set()
        moves_ok: dict[int, bool] = {}
        changed = True
        while changed:
            changed = False
            for x in robots:
                if x in won_r or lo_r[x] > b:
                    continue
                proven = self._closure_robot(x, b, won_h, x not in exits_tried)
                exits_tried.add(x)
                if proven:
                    won_r.add(x)
                    changed = True
            for y in humans:
                if y in won_h or lo_h[y] > b:
                    continue
                replies = self.human_options(y)
                if replies[0] not in won_r:
                    continue
                if y not in moves_ok:
                    moves_ok[y] = all(self.robot(j, b) for j in replies[1:] if j >= 0)
                if moves_ok[y]:
                    self._prove_human(y, max(hi_r[j][0] for j in replies if j >= 0))
                    won_h.add(y)
                    changed = True
        # the others have val > b; then Bellman's equations on the raised bounds
        for x in robots:
            if x not in won_r and lo_r[x] <= b:
                lo_r[x] = b + 1
        for y in humans:
            if y not in won_h and lo_h[y] <= b:
                lo_h[y] = b + 1
        for x in robots:
            if x not in won_r:
                self._bellman_robot(x)
        return start in won_r

    def _zero_cost_region(self, start: int) -> tuple[list[int], list[int]]:
        """The robot positions reachable from `start` by zero-cost actions
        and passes, and the human positions between them."""
        robots, humans = [start], []
        seen_r, seen_h = {start}, set()
        for x in robots:  # grows while iterated
            for units, _, j in self.robot_options(x):
                if units == 0 and j >= 0 and j not in seen_h:
                    seen_h.add(j)
                    humans.append(j)
                    p = self.human_options(j)[0]  # the pass
                    if p not in seen_r:
                        seen_r.add(p)
                        robots.append(p)
        return robots, humans

    def _closure_robot(self, x: int, b: int, won_h: set[int], exits: bool) -> bool:
        """One robot position of a closure: proven within b by a zero-cost
        action into a human position won already, or (`exits`: not tried
        before, whose answers do not change within the closure) by an
        action that costs, asked with the budget left."""
        for f, units, action, j in self._ranked(x):
            if f > b:
                break
            if units == 0 and j >= 0:
                if j in won_h:
                    self._prove_robot(x, self.hi_h[j], action)
                    return True
            elif exits:
                if j < 0:
                    self._prove_robot(x, units, action)
                    return True
                if self.human(j, b - units):
                    self._prove_robot(x, units + self.hi_h[j], action)
                    return True
        return False

    # -- values ---------------------------------------------------------------------------
    def value_human(self, key: Key) -> int | None:
        """val of a human-turn position (the start): units, None when infinite."""
        return self._value(self.id(key), self.human, self.lo_h, self.hi_h)

    def value_robot(self, key: Key) -> int | None:
        """val of a robot-turn position, in units; None when infinite."""
        return self._value(self.id(key), self.robot, self.lo_r, self.hi_r)

    def _value(self, i: int, ask, lo: list[float], hi: Mapping) -> int | None:
        """The least b with a yes, asked from b = lo up.  (Galloping above lo
        and then halving, tried for tasks without a bound, made budgets so
        large in games of infinite value that the search blew up before the
        trap check could see the trap: O(positions x budget).)  The trap
        check is skipped for a position with a proven hi: its value is finite
        (the strategy's lookups, `solve -o`, would otherwise run it over
        everything generated again and again)."""
        rounds = 0
        while True:
            b = lo[i]
            if b == INF:
                return None
            b = int(b)
            self.rounds += 1
            rounds += 1
            if self.on_round is not None:
                self.on_round(b)
            if ask(i, b):
                return b
            if lo[i] <= b:  # the search from here is a proof: val > b
                lo[i] = b + 1
            if self.calls - self._tightened_at > len(self.keys):  # (at most doubles the work)
                self._tighten()
            if rounds & (rounds - 1) == 0 and rounds >= 8 and i not in hi:  # 8, 16, 32, ...
                self._qualitative()

    def _tighten(self) -> None:
        """Bellman's equations solved on what the search generated, to raise
        lo where a question at a time raises it by little: around a cycle of
        cheap actions (two transits between objects, 2 units each) each
        failed question lifts the cycle's lo by the cycle's cost only, while
        its way out costs 10^6 (one such cycle took 500,000 rounds).

        The least solution L of lo(p) = min over actions of c + lo(after)
        (robot), max over replies (human), 0 at a win, with every position
        not expanded yet fixed at its lo, is at most val (val solves the
        same equations, with every unexpanded position at val >= lo), and
        inf where the human keeps the robot within what was generated from
        reaching a win.  The equations' functions never give less than
        their arguments (costs >= 0), so Knuth's generalization of
        Dijkstra's algorithm (1977) finds L in one pass, smallest first.
        Then lo := max(lo, L).  Robot roles at ids [0, n), human at [n, 2n)."""
        self.tightened += 1
        self._tightened_at = self.calls
        n = len(self.keys)
        lo_r, lo_h = self.lo_r, self.lo_h
        value = _least_solution(*self._equations(), n)
        for i in range(n):
            if value[i] > lo_r[i]:
                lo_r[i] = value[i]
            if value[n + i] > lo_h[i]:
                lo_h[i] = value[n + i]

    def _equations(self) -> tuple[list[list[tuple[int, int]]], list[int], list[tuple[float, int]]]:
        """`_tighten`'s equations over the roles (robot at [0, n), human at
        [n, 2n)): who waits on each role and the units it adds, the replies
        a human role waits for, and the roles whose value is known (a win,
        or an unexpanded position at its lo)."""
        n = len(self.keys)
        users: list[list[tuple[int, int]]] = [[] for _ in range(2 * n)]  # (who waits, units it adds)
        waiting = [0] * (2 * n)  # a human role: replies not yet final
        heap: list[tuple[float, int]] = []
        for i in range(n):
            options = self._robot.get(i)
            if options is None:
                heap.append((self.lo_r[i], i))
            else:
                for units, _, j in options:
                    if j < 0:
                        heap.append((units, i))
                    else:
                        users[n + j].append((i, units))
            replies = self._human.get(i)
            if replies is None:
                heap.append((self.lo_h[i], n + i))
            else:
                live = [j for j in replies if j >= 0]
                waiting[n + i] = len(live)
                if not live:
                    heap.append((0, n + i))
                for j in live:
                    users[j].append((n + i, 0))
        return users, waiting, heap

    def _qualitative(self) -> None:
        """Positions the human can keep from winning forever, found within what
        the search has generated: an expanded robot position all of whose
        actions lead to such human positions, an expanded human position with
        a reply to such a robot position (the pass included), and nothing
        else.  Unexpanded positions count as won (they may be) unless their
        lo is already inf, so what is left is a trap the human can close:
        lo = inf there, and never a finite position's.  Cost: linear in what
        was generated."""
        self.explored += 1
        n = len(self.keys)
        # maybe-won: robot role at ids [0, n), human role at [n, 2n); WIN is won
        askers: list[list[int]] = [[] for _ in range(2 * n)]
        count = [0] * (2 * n)  # human positions: replies not yet won
        ready = []
        lo_r, lo_h = self.lo_r, self.lo_h
        for i in range(n):
            options = self._robot.get(i)
            if lo_r[i] == INF:
                pass  # known lost
            elif options is None or any(j < 0 for _, _, j in options):
                ready.append(i)
            else:
                for _, _, j in options:
                    askers[n + j].append(i)
            replies = self._human.get(i)
            if lo_h[i] == INF:
                pass
            elif replies is None:
                ready.append(n + i)
            else:
                live = [j for j in replies if j >= 0]
                count[n + i] = len(live)
                if not live:
                    ready.append(n + i)
                for j in live:
                    askers[j].append(n + i)
        won = bytearray(2 * n)
        for x in ready:
            won[x] = 1
        while ready:
            x = ready.pop()
            for y in askers[x]:
                if won[y]:
                    continue
                if y < n:  # a robot position: one won action is enough
                    won[y] = 1
                    ready.append(y)
                else:
                    count[y] -= 1
                    if count[y] == 0:
                        won[y] = 1
                        ready.append(y)
        for i in range(n):
            if not won[i]:
                self.lo_r[i] = INF
            if not won[n + i]:
                self.lo_h[i] = INF

    # -- plays ------------------------------------------------------------------------------
    def principal_play(self, start: Key, units: int) -> tuple[Step, ...]:
        """The strategy against the human's worst replies (the first reply of
        largest value, the pass first), the rule the explicit solver plays by."""
        def worst(i: int, left: int) -> tuple[str, State, int]:
            # the human's turn at i, of value `left`: the first reply of that value
            for action, _, state, j in self.steps(i, robot=False):
                if (left == 0) if j < 0 else not self.robot(j, left - 1):
                    return action, state, j  # replies are within `left` (proven): this one is `left`
            raise RuntimeError("internal error: no reply of the value")
        return self._play(start, units, worst)

    def proven_play(self, start: Key) -> tuple[Step, ...]:
        """The proven entries' strategy against the replies of largest proven
        hi (the pass first on ties), without further search: the play of an
        anytime answer."""
        def largest(i: int, _: int) -> tuple[str, State, int]:
            action, _, state, j = max(self.steps(i, robot=False),
                                      key=lambda x: -1 if x[3] < 0 else self.hi_r[x[3]][0])
            return action, state, j
        return self._play(start, 0, largest)

    def _play(self, start: Key, units: int, reply: Callable[[int, int], tuple[str, State, int]]
              ) -> tuple[Step, ...]:
        """The play from `start` of the proven entries' actions against the
        human's `reply(position, units left of `units`)`, until a win."""
        play: list[Step] = []
        i, left = self.id(start), units
        while True:
            action, state, j = reply(i, left)
            if action != PASS:
                play.append(Step("human", action, 0.0, state))
            if j < 0:
                return tuple(play)
            _, chosen = self.hi_r[j]
            (cost, state, i), = [(u, w, nxt) for a, u, w, nxt in self.steps(j, robot=True) if a == chosen]
            play.append(Step("robot", chosen, in_costmap_units(cost, self.game.resolution), state))
            if i < 0:
                return tuple(play)
            left -= cost

    def counter_play(self, start: Key) -> tuple[Step, ...]:
        """The explicit solver's counter play (`explicit._counter_play`),
        walked on the memo: from the start (a human position of infinite
        value) the human takes its first reply of infinite value, the pass
        first; the robot its first action of the fewest units (all its
        actions lead to positions of infinite value); until the robot has no
        action or a position comes back.  A reply is lost when its lo is
        inf, won when it has a hi, and otherwise searched now (`_lost`)."""
        r = self.game.resolution
        play: list[Step] = []
        i, robot, seen = self.id(start), False, set()
        while (i, robot) not in seen:
            seen.add((i, robot))
            steps = self.steps(i, robot)
            if robot:
                if not steps:
                    break
                step = min(steps, key=operator.itemgetter(1))  # the first of the fewest units
            else:
                step = next(x for x in steps if x[3] >= 0 and self._lost(x[3]))
            action, units, state, after = step
            if action != PASS:
                play.append(Step("robot" if robot else "human", action, in_costmap_units(units, r), state))
            i, robot = after, not robot
            if i < 0:
                raise RuntimeError("internal error: the counter play reached a win")
        return tuple(play)

    def _lost(self, i: int) -> bool:
        """Whether the robot position `i` has infinite value."""
        if self.lo_r[i] == INF:
            return True
        if i in self.hi_r:
            return False
        return self._value(i, self.robot, self.lo_r, self.hi_r) is None

    # -- reporting ---------------------------------------------------------------------------
    def positions(self) -> int:
        """Twice the (v, q, h) the search generated: each stands for a
        robot-turn and a human-turn position, though the search may have
        reached only one of the two (an upper bound on what it generated)."""
        return 2 * len(self.keys)

    def stats(self) -> dict[str, object]:
        return {"calls": self.calls, "rounds": self.rounds, "positions": len(self.keys),
                "proven": len(self.hi_r) + len(self.hi_h), "closures": self.closures,
                "qualitative": self.explored, "tightened": self.tightened}


def _least_solution(users: list[list[tuple[int, int]]], waiting: list[int], heap: list[tuple[float, int]],
                    n: int) -> list[float]:
    """Knuth's generalization of Dijkstra's algorithm on `Search._equations`:
    each role's least value, smallest first (a robot role at its first
    action known, a human role at its last reply), INF where none."""
    heapq.heapify(heap)
    value = [INF] * (2 * n)
    while heap:
        x_value, x = heapq.heappop(heap)
        if x_value == INF:
            break
        if value[x] != INF:
            continue
        value[x] = x_value
        for y, units in users[x]:
            if value[y] != INF:
                continue
            if y < n:  # one action of the robot role y is now known
                heapq.heappush(heap, (units + x_value, y))
            else:
                waiting[y] -= 1
                if waiting[y] == 0:  # its last reply, so its largest (taken smallest first)
                    heapq.heappush(heap, (x_value, y))
    return value
