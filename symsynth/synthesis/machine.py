"""A winning strategy as an explicit machine, for specs small enough to list.

Its states are the DFA states a play can reach under the strategy.  With
the agent first, each state has one output (a Moore machine: the agent
speaks before it hears) and a successor per input; with the environment
first, an output per input (a Mealy machine).  A successor is another
state or `"win"` (the trace read so far is accepted).  The outputs come from
`Realizability.choices`, so every play wins within the initial state's rank.
"""

from __future__ import annotations

import itertools
import json
from dataclasses import dataclass
from typing import Any

from symsynth.automata.bdd import Function, cofactor, lexmin
from symsynth.errors import InputError
from symsynth.synthesis.game import Realizability, least_outputs

#: Listing enumerates every input letter of every state: at most this many inputs.
MAX_INPUTS = 12
MAX_STATES = 10_000

Assignment = dict[str, bool]


class TooLarge(InputError):
    """The strategy has too many inputs or states to list."""


@dataclass(frozen=True)
class Move:
    input: Assignment
    output: Assignment
    next: int | str  # a state number or "win"


@dataclass(frozen=True)
class Machine:
    agent_first: bool
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    states: tuple[tuple[bool, ...], ...]  # DFA state of each machine state; 0 is initial
    moves: tuple[tuple[Move, ...], ...]

    def to_json(self) -> dict[str, Any]:
        return {"format": "symsynth.strategy-machine/1",
                "agent_first": self.agent_first, "inputs": list(self.inputs), "outputs": list(self.outputs),
                "initial": 0,
                "states": [{"id": i, "moves": [{"input": m.input, "output": m.output, "next": m.next}
                                               for m in moves]}
                           for i, moves in enumerate(self.moves)]}

    def to_dot(self) -> str:
        lines = ["digraph strategy {", "  rankdir=LR;", '  win [shape=doublecircle, label="win"];']
        for i, moves in enumerate(self.moves):
            lines.append(f'  s{i} [shape=circle, label="{i}"];')
            for m in moves:
                label = f"{_text(m.input)} / {_text(m.output)}"
                target = "win" if m.next == "win" else f"s{m.next}"
                lines.append(f'  s{i} -> {target} [label="{label}"];')
        lines.append("}")
        return "\n".join(lines) + "\n"


def _text(values: Assignment) -> str:
    return " ".join(("" if v else "!") + k for k, v in values.items()) or "-"


def strategy_machine(game: Realizability) -> Machine:
    """The explicit winning strategy of a realizable `game`."""
    if not game.realizable:
        raise ValueError("no winning strategy to list")
    if len(game.inputs) > MAX_INPUTS:
        raise TooLarge(f"the strategy reads {len(game.inputs)} inputs; an explicit machine is listed for at "
                       f"most {MAX_INPUTS} (2^{MAX_INPUTS} letters per state)")
    dfa, bdd = game.dfa, game.dfa.bdd
    letters = [dict(zip(game.inputs, values)) for values in itertools.product((False, True), repeat=len(game.inputs))]
    index = {dfa.initial: 0}
    order = [dfa.initial]
    machine_moves = []
    accepting: dict[tuple[bool, ...], bool] = {}
    for state in order:  # grows while walked: breadth first
        if len(order) > MAX_STATES:
            raise TooLarge(f"the strategy has more than {MAX_STATES} states; too many to list")
        cube = dfa.state_cube(state)
        rank = game.rank(cube)
        if rank is None:  # the walk follows winning moves only, which stay in W
            raise ValueError(f"the strategy reached DFA state {state} outside the winning region")
        values = dict(zip(dfa.bits, state))
        choices = game.choices(rank, values)
        if game.agent_first:  # one output for every input: \A x: C
            sure = bdd.forall(set(game.inputs), choices) if game.inputs else choices
            output = {y: bdd.true if v else bdd.false for y, v in zip(game.outputs, lexmin(bdd, sure, game.outputs))}
        else:  # an output per input: the least one C allows, as functions of x
            output = least_outputs(bdd, choices, game.outputs)
        # the output and the successor (delta(state, x, output)) at every input letter at once
        nexts = [cofactor(bdd, values, dfa.delta[b]) for b in dfa.bits]
        if output:
            nexts = [bdd.let(output, f) for f in nexts]
        table = _table(bdd, list(output.values()) + nexts, game.inputs)
        moves = []
        for x in letters:
            value = table[tuple(x.values())]
            chosen = dict(zip(game.outputs, value[:len(game.outputs)]))
            after = value[len(game.outputs):]
            if after not in accepting:
                accepting[after] = dfa.is_accepting(after)
            if accepting[after]:
                target: int | str = "win"
            else:
                if after not in index:
                    index[after] = len(order)
                    order.append(after)
                target = index[after]
            moves.append(Move(x, chosen, target))
        machine_moves.append(tuple(moves))
    return Machine(game.agent_first, game.inputs, game.outputs, tuple(order), tuple(machine_moves))


def _table(bdd, functions: list[Function], inputs: tuple[str, ...]) -> dict[tuple[bool, ...], tuple[bool, ...]]:
    """The values of `functions` (BDDs over `inputs`) at every assignment to
    the inputs (in their order): the letters split by the value of each
    function in turn, then each part's letters listed (a few parts, where
    evaluating every function at every letter is a BDD call per pair)."""
    parts: list[tuple[tuple[bool, ...], Function]] = [((), bdd.true)]
    for f in functions:
        parts = [(value + (bit,), part) for value, guard in parts
                 for bit, part in ((False, guard & ~f), (True, guard & f)) if part != bdd.false]
    table: dict[tuple[bool, ...], tuple[bool, ...]] = {}
    for value, guard in parts:
        for letter in bdd.pick_iter(guard, care_vars=set(inputs)):
            table[tuple(letter[x] for x in inputs)] = value
    return table


def write_json(machine: Machine) -> str:
    return json.dumps(machine.to_json(), indent=1) + "\n"
