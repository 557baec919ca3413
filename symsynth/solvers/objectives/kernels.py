"""The numba kernels of semantics §9 on an `Arena` (arena.py's layout).

- `human_values`: V at the human turns, from V at the robot turns;
- `cooperative`: C, the least robot cost of a winning play when robot and
  human choose together, by Dijkstra's algorithm backwards from the win
  over every move (the human's cost nothing);
- `distances`: the least robot cost from the initial position to each
  turn, forwards; a turn reached with budget b left has b <= B - distance,
  which bounds the budgets the expectation is computed for;
  `cooperative_start`: the same search stopped at the win, C at the start;
- (EX itself, at every (turn, budget left): `steps.py`, step functions of the budget);
- `has_cycle`, `truncated`: whether the expected-cost strategy can go in
  circles (waiting on zero-cost moves), and what it guarantees when it
  stops waiting after n robot turns.
"""

from __future__ import annotations

import numpy as np
from numba import njit

INF = np.int64(1 << 60)


@njit(cache=True)
def human_values(rval, h_off, h_tgt):
    """vh[i] = max(rval[i], the values of i's human moves (0: a move that wins))."""
    n = len(rval)
    vh = rval.copy()
    for i in range(n):
        for e in range(h_off[i], h_off[i + 1]):
            t = h_tgt[e]
            v = 0 if t < 0 else rval[t]
            if v > vh[i]:
                vh[i] = v
    return vh


@njit(cache=True)
def _by_target(off, tgt, n):
    """The edges of a CSR graph grouped by target (-1 targets left out):
    (start of each target's group, the edges, their sources)."""
    start = np.zeros(n + 1, np.int64)
    for e in range(len(tgt)):
        if tgt[e] >= 0:
            start[tgt[e] + 1] += 1
    for j in range(n):
        start[j + 1] += start[j]
    fill = start[:n].copy()
    edges = np.empty(start[n], np.int64)
    sources = np.empty(start[n], np.int64)
    for i in range(n):
        for e in range(off[i], off[i + 1]):
            t = tgt[e]
            if t >= 0:
                edges[fill[t]] = e
                sources[fill[t]] = i
                fill[t] += 1
    return start, edges, sources


@njit(cache=True)
def _push(x, d, W, head, e_node, e_dist, e_next, used):
    e_node[used] = x
    e_dist[used] = d
    e_next[used] = head[d % W]
    head[d % W] = used
    return used + 1


@njit(cache=True)
def _buckets(r_units, room):
    """An empty bucket queue for Dijkstra over move costs `r_units`: (W,
    head, e_node, e_dist, e_next), W buckets (above the costliest move) and
    room for `room` entries (one per improvement at most)."""
    W = 1
    for e in range(len(r_units)):
        W = max(W, r_units[e] + 1)
    head = np.full(W, -1, np.int64)
    return W, head, np.empty(room, np.int64), np.empty(room, np.int64), np.empty(room, np.int64)


@njit(cache=True)
def _pop(d, W, head, e_next):
    """(entry, its distance): the bucket queue's next entry from distance
    `d` on (one is waiting: the callers count them)."""
    while head[d % W] < 0:
        d += 1
    x = head[d % W]
    head[d % W] = e_next[x]
    return x, d


@njit(cache=True)
def cooperative(hflag, r_off, r_tgt, r_units, h_off, h_tgt):
    """(rc, hc, choice): C at each robot turn and human turn (INF: losing),
    and the robot move (absolute edge index, -1: none) on a cheapest
    cooperative play.  Turn ids: robot i is i, human i is n + i.  Dijkstra
    backwards from the win with a bucket queue (Dial's: costs are small
    integers, so the turns waiting to settle sit in a ring of W buckets,
    W above the costliest move), as the compiled solver's layers do."""
    n = len(hflag)
    rs, re_, rsrc = _by_target(r_off, r_tgt, n)  # robot moves into human turn t
    hs, he, hsrc = _by_target(h_off, h_tgt, n)  # human moves into robot turn t
    W, head, e_node, e_dist, e_next = _buckets(r_units, len(r_tgt) + len(h_tgt) + 2 * n + 1)
    used = 0
    dist = np.full(2 * n, INF, np.int64)
    choice = np.full(n, -1, np.int64)
    for i in range(n):
        for e in range(r_off[i], r_off[i + 1]):
            if r_tgt[e] < 0 and r_units[e] < dist[i]:
                dist[i] = r_units[e]
                choice[i] = e
        if dist[i] < INF:
            used = _push(i, dist[i], W, head, e_node, e_dist, e_next, used)
        if hflag[i]:
            for e in range(h_off[i], h_off[i + 1]):
                if h_tgt[e] < 0:
                    dist[n + i] = 0
            if dist[n + i] == 0:
                used = _push(n + i, 0, W, head, e_node, e_dist, e_next, used)
    done = np.zeros(2 * n, np.uint8)
    pending = used
    d = 0
    while pending > 0:
        x, d = _pop(d, W, head, e_next)
        pending -= 1
        y = e_node[x]
        if done[y] or e_dist[x] != dist[y]:
            continue  # settled already, or a stale entry
        done[y] = 1
        if y < n:  # a robot turn: the human turns whose pass or move leads here
            if hflag[y] and d < dist[n + y]:
                dist[n + y] = d
                used = _push(n + y, d, W, head, e_node, e_dist, e_next, used)
                pending += 1
            for p in range(hs[y], hs[y + 1]):
                j = hsrc[p]
                if d < dist[n + j]:
                    dist[n + j] = d
                    used = _push(n + j, d, W, head, e_node, e_dist, e_next, used)
                    pending += 1
        else:  # a human turn: the robot moves into it
            t = y - n
            for p in range(rs[t], rs[t + 1]):
                e, i = re_[p], rsrc[p]
                c = d + r_units[e]
                if c < dist[i]:
                    dist[i] = c
                    choice[i] = e
                    used = _push(i, c, W, head, e_node, e_dist, e_next, used)
                    pending += 1
    return dist[:n].copy(), dist[n:].copy(), choice


@njit(cache=True)
def distances(hflag, r_off, r_tgt, r_units, h_off, h_tgt):
    """(dr, dh): the least robot cost from node 0's human turn to each robot
    turn and human turn (INF: not reached).  Turn ids: robot i is i, human
    i is n + i."""
    dist, _ = _forward(hflag, r_off, r_tgt, r_units, h_off, h_tgt, False)
    n = len(hflag)
    return dist[:n].copy(), dist[n:2 * n].copy()


@njit(cache=True)
def cooperative_start(hflag, r_off, r_tgt, r_units, h_off, h_tgt):
    """C at node 0's human turn (INF: losing): the same search, stopped
    when the win is settled, so it reads only the turns cheaper to reach
    than C (a quarter of them at 5 x 7 of the game family)."""
    _, win = _forward(hflag, r_off, r_tgt, r_units, h_off, h_tgt, True)
    return win


@njit(cache=True)
def _forward(hflag, r_off, r_tgt, r_units, h_off, h_tgt, stop):
    """Dijkstra with a bucket queue (as `cooperative`) from node 0's human
    turn over every move, human moves free: (the distance of each turn
    (robot i is i, human i is n + i), the distance of the win); with
    `stop`, it ends when the win (id 2n) is settled, the others left as far
    as they got."""
    n = len(hflag)
    W, head, e_node, e_dist, e_next = _buckets(r_units, len(r_tgt) + len(h_tgt) + 2 * n + 2)
    dist = np.full(2 * n + 1, INF, np.int64)
    dist[n] = 0
    used = _push(n, 0, W, head, e_node, e_dist, e_next, 0)
    pending = 1
    d = 0
    while pending > 0:
        x, d = _pop(d, W, head, e_next)
        pending -= 1
        y = e_node[x]
        if e_dist[x] != dist[y]:
            continue  # a stale entry
        if y == 2 * n:
            if stop:
                break
            continue
        if y >= n:
            i = y - n
            if d < dist[i]:
                dist[i] = d
                used = _push(i, d, W, head, e_node, e_dist, e_next, used)
                pending += 1
            for e in range(h_off[i], h_off[i + 1]):
                t = h_tgt[e]
                t = 2 * n if t < 0 else t
                if d < dist[t]:
                    dist[t] = d
                    used = _push(t, d, W, head, e_node, e_dist, e_next, used)
                    pending += 1
        else:
            for e in range(r_off[y], r_off[y + 1]):
                t = r_tgt[e]
                t = 2 * n if t < 0 else n + t
                c = d + r_units[e]
                if c < dist[t]:
                    dist[t] = c
                    used = _push(t, c, W, head, e_node, e_dist, e_next, used)
                    pending += 1
    return dist, dist[2 * n]


@njit(cache=True)
def has_cycle(B, hflag, r_tgt, r_units, h_off, h_tgt, choice, xo, xlo):
    """Whether the expected-cost strategy, followed from node 0's human turn
    with budget B against every human (each pass and move), can come back to
    a robot turn with the same budget: then it waits on zero-cost moves and
    is not B-safe by itself (semantics §9)."""
    total = xo[len(xo) - 1]
    colour = np.zeros(total, np.uint8)  # 0 new, 1 on the stack, 2 done
    stack_s = np.empty(total + 1, np.int64)  # (robot turn state, next successor to try)
    stack_k = np.empty(total + 1, np.int64)
    stack_b = np.empty(total + 1, np.int64)
    # the start's human turn: its pass and moves, each a root
    roots = [np.int64(0)]
    for e in range(h_off[0], h_off[1]):
        if h_tgt[e] >= 0:
            roots.append(h_tgt[e])
    for r in roots:
        s = xo[r] + B - xlo[r]
        if s >= xo[r + 1] or colour[s]:
            continue
        top = 0
        stack_s[0], stack_k[0], stack_b[0] = s, -1, B
        colour[s] = 1
        while top >= 0:
            s, kk, b = stack_s[top], stack_k[top], stack_b[top]
            e = choice[s]
            t = r_tgt[e]
            nb = b - r_units[e]
            # successors: the pass (kk = -1), then the human moves of t
            nxt = -1
            if t >= 0:
                while True:
                    if kk == -1:
                        j = t
                    elif h_off[t] + kk < h_off[t + 1]:
                        j = h_tgt[h_off[t] + kk]
                    else:
                        break
                    kk += 1
                    if j >= 0:
                        nxt = j
                        break
            stack_k[top] = kk
            if nxt < 0:
                colour[s] = 2
                top -= 1
                continue
            s2 = xo[nxt] + nb - xlo[nxt]
            if colour[s2] == 1:
                return True
            if colour[s2] == 0:
                colour[s2] = 1
                top += 1
                stack_s[top], stack_k[top], stack_b[top] = s2, -1, nb
    return False


@njit(cache=True)
def truncated(B, rounds, hflag, r_tgt, r_units, rval, stay, h_off, h_tgt, h_prob, choice, xo, xlo, target):
    """The least n <= rounds such that the strategy "the expected-cost
    strategy for n robot turns, then a worst-case optimal one" has an
    expected cost at most `target` at the start, and that bound; (-1,
    the bound after `rounds`) when none does.  Bound: the worst-case
    strategy costs at most V from where it takes over, so g_0(i, b) = V(i)
    and g_{n+1}(i, b) = c + E_model[g_n at the human turn after]."""
    n = len(hflag)
    g = np.empty(xo[n], np.float64)
    for i in range(n):
        for s in range(xo[i], xo[i + 1]):
            g[s] = rval[i]
    new = g.copy()
    bound = np.inf
    for r in range(rounds + 1):
        y = stay[0] * g[xo[0] + B - xlo[0]] if xo[0] + B - xlo[0] < xo[1] else np.inf
        for e in range(h_off[0], h_off[1]):
            j = h_tgt[e]
            if j >= 0 and h_prob[e] > 0.0:
                y += h_prob[e] * g[xo[j] + B - xlo[j]]
        bound = y
        if bound <= target:
            return r, bound
        for i in range(n):
            for s in range(xo[i], xo[i + 1]):
                e = choice[s]
                b = xlo[i] + s - xo[i]
                t = r_tgt[e]
                c = r_units[e]
                if t < 0:
                    new[s] = c
                else:
                    v = stay[t] * g[xo[t] + b - c - xlo[t]]
                    for f in range(h_off[t], h_off[t + 1]):
                        j = h_tgt[f]
                        if j >= 0 and h_prob[f] > 0.0:
                            v += h_prob[f] * g[xo[j] + b - c - xlo[j]]
                    new[s] = c + v
        g, new = new, g
    return -1, bound


@njit(cache=True)
def markov(node_choice, stay, r_tgt, r_units, h_off, h_tgt, h_prob, finish):
    """A strategy that plays node_choice[i] at every robot turn i (-1: none,
    the play ends unwon), against the model: with `finish`, the probability
    of winning from each robot turn (value iteration from 0, the least
    fixpoint); else the expected cost (from 0 too, which is the cost of a
    strategy that wins with probability 1 and never circles at zero cost,
    like the worst-case one).  Iterated until no value moves by 1e-13."""
    n = len(node_choice)
    x = np.zeros(n)
    for _ in range(1_000_000):
        moved = 0.0
        for i in range(n):
            e = node_choice[i]
            if e < 0:
                continue
            t = r_tgt[e]
            if t < 0:
                y = 1.0 if finish else float(r_units[e])
            else:
                y = stay[t] * x[t]
                for f in range(h_off[t], h_off[t + 1]):
                    j = h_tgt[f]
                    if h_prob[f] > 0.0 and j >= 0:
                        y += h_prob[f] * x[j]
                    elif h_prob[f] > 0.0 and finish:
                        y += h_prob[f]  # a move that wins
                if not finish:
                    y += r_units[e]
            d = abs(y - x[i])
            if d > moved:
                moved = d
            x[i] = y
        if moved <= 1e-13:
            break
    return x
