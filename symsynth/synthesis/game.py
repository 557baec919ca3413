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
"""

from __future__ import annotations

from dataclasses import dataclass, field

from symsynth.automata.bdd import Function
from symsynth.automata.symbolic import SymbolicDFA
from symsynth.synthesis.partition import Partition


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

    def rank(self, state: Function) -> int | None:
        """The least i with `state` (a cube over the DFA bits) in W_i; None outside W."""
        for i, won in enumerate(self.rounds, 1):
            if state & won != self.dfa.bdd.false:
                return i
        return None

    def choices(self, rank: int) -> Function:
        """C(q, x, y): the letters that lead from a state of rank `rank` into
        Acc \\/ W_{rank-1} (a BDD over DFA bits, inputs and outputs)."""
        dfa = self.dfa
        below = self.rounds[rank - 2] if rank >= 2 else dfa.bdd.false
        return dfa.bdd.let(dict(dfa.delta), dfa.accepting | below)


def solve_realizability(dfa: SymbolicDFA, partition: Partition, *, agent_first: bool = True) -> Realizability:
    """The reachability game of the module docstring on `dfa`; variables of
    the partition that the formula does not read play no part."""
    bdd = dfa.bdd
    inputs = tuple(a for a in dfa.atoms if a in partition.inputs)
    outputs = tuple(a for a in dfa.atoms if a in partition.outputs)
    xs, ys = set(inputs), set(outputs)
    step = dict(dfa.delta)  # q := delta(q, x, y)
    rounds: list[Function] = []
    win = bdd.false
    old = None
    while win != old:
        old = win
        # G(delta(q, x, y)) with G = Acc \/ W_i
        after = bdd.let(step, dfa.accepting | win) if dfa.bits else dfa.accepting | win
        if agent_first:
            pre = bdd.exist(ys, bdd.forall(xs, after)) if ys else bdd.forall(xs, after)  # \E y: \A x
        else:
            pre = bdd.forall(xs, bdd.exist(ys, after)) if xs else bdd.exist(ys, after)  # \A x: \E y
        win = win | pre
        if win != old:
            rounds.append(win)
    initial = dfa.state_cube(dfa.initial_assignment)
    realizable = initial & win != bdd.false
    return Realizability(realizable, agent_first, dfa, inputs, outputs, rounds)
