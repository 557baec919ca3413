"""The turns a play of the expected-cost strategy reaches, and the most it
may still pay from each, in machine code.

A robot turn is (node, budget left, count of robot turns remembered);
the strategy's move there is its step function's choice at that budget
(`Steps.choice`), or the worst-case move once the count reaches the
waiting bound.  From every turn the start's replies reach, depth first:
the move, and

    worst(i, b, w) = c                                     if the move wins
                   = c + max over the replies j of the move's target t
                         (the pass is the robot turn t itself) of
                         worst(j, b - c, count(w + 1))     (0 for a reply that wins)

what an adversary that knows the strategy maximizes
(`play.still_to_pay`, whose Python recursion this replaces: 2 million
turns on the line scene at k = 5 took 14.5 s there).  A play that comes
back to a turn on its own path goes in circles (the strategy never
wins against that human); a turn where the strategy has no move is a
bug of the solver; either stops the walk with the turn named.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit
from numba.core import types
from numba.typed import Dict

OK, CIRCLE, NO_MOVE, NEGATIVE = 0, 1, 2, 3


@dataclass(frozen=True)
class Turns:
    """Turn k is (node[k], budget[k], count[k]); move[k] is the strategy's
    edge there and worst[k] the most it may still pay from there."""

    node: np.ndarray
    budget: np.ndarray
    count: np.ndarray
    move: np.ndarray
    worst: np.ndarray


def expected_turns(arena, steps, waiting: int | None, budget: int) -> Turns:
    """Every turn a play of the expected-cost strategy (`steps`, switching
    to the worst-case moves after `waiting` robot turns) reaches from the
    start with `budget` left, against every human.  A `RuntimeError` where
    a play goes in circles or the strategy has no move."""
    status, where, node, left, count, move, worst = _walk(
        arena.r_units.astype(np.int64), arena.r_tgt.astype(np.int64), arena.h_off.astype(np.int64),
        arena.h_tgt.astype(np.int64), steps.xo.astype(np.int64), steps.xlev.astype(np.int64),
        steps.xch.astype(np.int64), arena.wchoice.astype(np.int64), -1 if waiting is None else int(waiting),
        int(budget))
    if status == CIRCLE:
        raise RuntimeError(f"a play goes in circles at node {node[where]} with budget {left[where]}")
    if status == NO_MOVE:
        raise RuntimeError(f"no move at node {node[where]} with budget {left[where]}")
    if status == NEGATIVE:
        raise RuntimeError(f"a move at node {node[where]} costs more than its budget {left[where]}")
    return Turns(node, left, count, move, worst)


@njit(cache=True)
def _grow(a, size):
    if size < len(a):
        return a
    b = np.empty(2 * len(a), a.dtype)
    b[:len(a)] = a
    return b


@njit(cache=True)
def _room(node, left, count, move, worst, state, n):
    """The turns' arrays, grown when turn n does not fit."""
    return (_grow(node, n), _grow(left, n), _grow(count, n), _grow(move, n), _grow(worst, n),
            _grow(state, n))


@njit(cache=True)
def _choice(xo, xlev, xch, i, b):
    """`Steps.choice`: the move of the last breakpoint at or below b (-1: none)."""
    lo, hi = xo[i], xo[i + 1]
    while lo < hi:  # the first breakpoint above b
        mid = (lo + hi) // 2
        if xlev[mid] <= b:
            lo = mid + 1
        else:
            hi = mid
    return -1 if lo == xo[i] else xch[lo - 1]


@njit(cache=True)
def _walk(r_units, r_tgt, h_off, h_tgt, xo, xlev, xch, wchoice, waiting, budget):
    counts = waiting + 1 if waiting >= 0 else 1
    index = Dict.empty(key_type=types.int64, value_type=types.int64)
    size = 1024
    node = np.empty(size, np.int64)
    left = np.empty(size, np.int64)
    count = np.empty(size, np.int64)
    move = np.empty(size, np.int64)
    worst = np.zeros(size, np.int64)
    state = np.zeros(size, np.int8)  # 1 on the path, 2 done
    stack = np.empty(1024, np.int64)
    cursor = np.empty(1024, np.int64)  # the next reply to look at: -1 the pass
    n = 0
    for r in range(-1, h_off[1] - h_off[0]):
        start = 0 if r < 0 else h_tgt[h_off[0] + r]
        if start < 0:
            continue
        key = (start * (budget + 1) + budget) * counts
        if key in index:
            continue
        index[key] = n
        node, left, count, move, worst, state = _room(node, left, count, move, worst, state, n)
        node[n], left[n], count[n], worst[n], state[n] = start, budget, 0, 0, 0
        n += 1
        sp = 0
        stack[0], cursor[0] = n - 1, -2  # -2: not entered yet
        while sp >= 0:
            x = stack[sp]
            if cursor[sp] == -2:  # enter: the move
                i, b, w = node[x], left[x], count[x]
                e = wchoice[i] if waiting >= 0 and w >= waiting else _choice(xo, xlev, xch, i, b)
                if e < 0:
                    return NO_MOVE, x, node[:n], left[:n], count[:n], move[:n], worst[:n]
                move[x] = e
                if r_units[e] > b:
                    return NEGATIVE, x, node[:n], left[:n], count[:n], move[:n], worst[:n]
                state[x] = 1
                cursor[sp] = -1
                continue
            e = move[x]
            t = r_tgt[e]
            k = cursor[sp]
            if t < 0 or k >= h_off[t + 1] - h_off[t]:  # the move wins, or every reply looked at
                worst[x] += r_units[e]
                state[x] = 2
                sp -= 1
                if sp >= 0:
                    parent = stack[sp]
                    worst[parent] = max(worst[parent], worst[x])
                continue
            cursor[sp] = k + 1
            j = t if k < 0 else h_tgt[h_off[t] + k]
            if j < 0:
                continue  # the human's reply completes the task: nothing more to pay
            b = left[x] - r_units[e]
            w = min(count[x] + 1, waiting) if waiting >= 0 else 0
            key = (j * (budget + 1) + b) * counts + w
            if key in index:
                y = index[key]
            else:
                y = n
                index[key] = y
                node, left, count, move, worst, state = _room(node, left, count, move, worst, state, n)
                node[y], left[y], count[y], worst[y], state[y] = j, b, w, 0, 0
                n += 1
            if state[y] == 2:
                worst[x] = max(worst[x], worst[y])
            elif state[y] == 1:
                return CIRCLE, y, node[:n], left[:n], count[:n], move[:n], worst[:n]
            else:
                sp += 1
                stack = _grow(stack, sp)
                cursor = _grow(cursor, sp)
                stack[sp], cursor[sp] = y, -2
    return OK, -1, node[:n], left[:n], count[:n], move[:n], worst[:n]
