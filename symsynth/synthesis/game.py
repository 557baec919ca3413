"""LTLf realizability as a reachability game on the symbolic DFA.

Each step the two players fix a letter together: with the agent first, the
agent chooses its outputs `y`, then the environment its inputs `x`; with the
environment first, the other way round.  The DFA reads `x ∪ y`; the agent
wins as soon as the trace read so far is accepted (LTLf: non-empty traces,
so the initial state, which has read nothing, is never a win by itself).

W is the least set of DFA states from which the agent forces acceptance:

    W_0 = false
    W_{i+1} = W_i \\/ Pre(Acc \\/ W_i)
    Pre(G)(q) = \\E y: \\A x: G(delta(q, x, y))     (agent first)
              = \\A x: \\E y: G(delta(q, x, y))     (environment first)

W_i holds the states from which the agent wins within i letters.  The spec
is realizable iff the initial state is in W.  A winning strategy at a state
first won in round i plays a `y` that leads into Acc \\/ W_{i-1} whatever
the environment does (`choices`); every play then wins within i letters.

How each round is computed (Double-Counter 05, 4,101 states, 61 rounds:
17 s with `bdd.let(delta, G)` every round, 0.5 s so):

- G(delta(q, x, y)) is, past the first rounds, a relational product with
  the transition relation, built once (`preimage.py`); it is distributive
  over \\/ in G, as the substitution is: the fixpoint keeps `after` =
  (Acc \\/ W_i)(delta) and adds the preimage of the round's new states;
- Pre is taken only at the states not yet won that have an edge into those
  new states (the others cannot change), so the quantifiers over x and y
  run on a few states' letters, not on every state's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from symsynth.automata.bdd import BDD, Function, cofactor
from symsynth.automata.symbolic import SymbolicDFA
from symsynth.synthesis.partition import Partition
from symsynth.synthesis.preimage import Preimage


@dataclass
class Realizability:
    """The solved game: the verdict, the rounds W_1, W_2, ... and what a
    strategy needs to choose its outputs."""

    realizable: bool
    agent_first: bool
    dfa: SymbolicDFA
    inputs: tuple[str, ...]  # the environment's variables the formula reads
    outputs: tuple[str, ...]  # the agent's
    rounds: list[Function] = field(repr=False)  # W_1, W_2, ... (W_i: wins within i letters)
    preimage: Preimage = field(repr=False)  # G -> G(delta(q, x, y)), for the strategies

    def rank(self, state: Function) -> int | None:
        """The least i with `state` (a cube over the DFA bits) in W_i; None outside W."""
        for i, won in enumerate(self.rounds, 1):
            if state & won != self.dfa.bdd.false:
                return i
        return None

    def choices(self, rank: int, state: dict[str, bool]) -> Function:
        """C(x, y): the letters that lead from `state` (an assignment to the
        DFA bits), of rank `rank`, into Acc \\/ W_{rank-1}."""
        dfa, bdd = self.dfa, self.dfa.bdd
        below = self.rounds[rank - 2] if rank >= 2 else bdd.false
        if not dfa.bits:
            return dfa.accepting | below
        here = {b: cofactor(bdd, state, dfa.delta[b]) for b in dfa.bits}  # delta(state, x, y): small
        return bdd.let(here, dfa.accepting | below)


def least_outputs(bdd: BDD, allowed: Function, outputs: tuple[str, ...]) -> dict[str, Function]:
    """The lexicographically least outputs that `allowed` (over the outputs
    and other variables) permits, each a function of the other variables,
    fixed one at a time, false where possible: f_y = !\\E y_rest:
    A[y := false], then A := A[y := f_y]."""
    functions = {}
    for i, y in enumerate(outputs):
        rest = set(outputs[i + 1:])
        zero = cofactor(bdd, {y: False}, allowed)
        f = ~(bdd.exist(rest, zero) if rest else zero)
        allowed = bdd.let({y: f}, allowed)
        functions[y] = f
    return functions


def solve_realizability(dfa: SymbolicDFA, partition: Partition, *, agent_first: bool = True,
                        preimage: Preimage | None = None,
                        progress: Callable[[int], None] | None = None) -> Realizability:
    """The reachability game of the module docstring on `dfa`; variables of
    the partition that the formula does not read play no part.  `preimage`:
    how G(delta) is computed (preimage.py; by default its own settings).
    `progress(i)` is called after round i (the number of rounds is not
    known in advance: at most the DFA's states)."""
    bdd = dfa.bdd
    inputs = tuple(a for a in dfa.atoms if a in partition.inputs)
    outputs = tuple(a for a in dfa.atoms if a in partition.outputs)
    xs, ys = set(inputs), set(outputs)
    preimage = Preimage(dfa) if preimage is None else preimage
    rounds: list[Function] = []
    win = bdd.false
    after = bdd.false  # (Acc \/ W_i)(delta(q, x, y))
    taken = bdd.false  # the states whose preimage `after` holds
    old = None
    while win != old:
        old = win
        target = dfa.accepting | win
        new = preimage(target & ~taken)  # (G \ taken)(delta(q, x, y))
        after, taken = after | new, target
        # the states not won with a letter into a new state: \E x, y: new, minus W_i
        moving = bdd.exist(xs | ys, new) & ~win if xs | ys else new & ~win
        here = after & moving
        if agent_first:
            pre = bdd.exist(ys, bdd.forall(xs, here)) if ys else bdd.forall(xs, here)  # \E y: \A x
        else:
            pre = bdd.forall(xs, bdd.exist(ys, here)) if xs else bdd.exist(ys, here)  # \A x: \E y
        # reachable states only: the codes no state reaches (past the last
        # state of an explicit DFA) step to some real state and would be won
        # one round after it, a round no play has
        win = win | (pre & dfa.reachable)
        if win != old:
            rounds.append(win)
        if progress is not None:
            progress(len(rounds))
    initial = dfa.state_cube(dfa.initial_assignment)
    realizable = initial & win != bdd.false
    return Realizability(realizable, agent_first, dfa, inputs, outputs, rounds, preimage)
