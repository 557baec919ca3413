"""A winning strategy as BDDs, for specs too large to list as a machine.

The strategy keeps the DFA's state bits `q` as its memory and computes its
outputs from them:

- `output[y](q)` with the agent first (a Moore machine: it speaks before it
  hears), `output[y](q, x)` with the environment first (Mealy);
- `delta[b](q, x, y)`: the next value of state bit `b` (the DFA's own);
- `accepting(q)`: the play is won (the trace read so far satisfies the
  formula), the agent may stop;
- `winning(q)` = W, and `rounds[i-1]` = W_i (wins within i letters): the
  outputs are meaningful on W only.

Playing it: `q := initial`; each step the agent's outputs and the
environment's inputs make a letter (in the order of the step), `q :=
delta(q, x, y)`, until `accepting(q)`.

How the outputs are chosen.  M(q, x, y) = \\/_i (W_i \\ W_{i-1})(q) /\\
(Acc \\/ W_{i-1})(delta(q, x, y)) holds for the letters that lead a state
of rank i one round closer to winning (the moves of `Realizability.choices`).
With the agent first the outputs may not look at x: A(q, y) = \\A x: M;
with the environment first A = M.  The outputs are then fixed one at a time,
in order, false where possible:

    f_y = ! \\E y_rest: A[y := false]        A := A[y := f_y]

so A stays satisfiable on W and the functions pick, state by state, the
lexicographically least allowed output, the one the explicit machine
(`machine.py`) lists.

File format `symsynth.strategy-bdd/1` (JSON): `agent_first`, `inputs`,
`outputs`, `state_bits`, `initial` (bit -> bool), `variables` (the BDD
variable order, top first: every node's variable is above its children's,
so loading in this order builds each node in one step), `nodes` and `roots`.  A node is `[variable, low, high]`:
"if variable then high else low".  A reference is 0 (false), 1 (true) or
k >= 2 (the node `nodes[k - 2]`); children come before their parents.
`roots`: `delta` (bit -> reference), `accepting`, `winning`, `rounds`
(list), `output` (output -> reference).  No complement edges, so the file
can be evaluated without a BDD library (follow high or low from a root
until 0 or 1).  (dd's own JSON dump was tried: its loader fails on a
constant root, which an output function often is.)
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from symsynth.automata.bdd import BDD, Function, children_first, cofactor, new_manager
from symsynth.errors import InputError, read_text
from symsynth.synthesis.game import Realizability, least_outputs

FORMAT = "symsynth.strategy-bdd/1"
Assignment = Mapping[str, bool]


@dataclass
class SymbolicStrategy:
    bdd: BDD
    agent_first: bool
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    bits: tuple[str, ...]
    initial: dict[str, bool]
    delta: dict[str, Function]
    accepting: Function
    winning: Function
    rounds: list[Function]
    output: dict[str, Function]

    def move(self, state: Assignment, inputs: Assignment) -> dict[str, bool]:
        """The outputs at `state` (with the environment first: after `inputs`;
        with the agent first they do not depend on them)."""
        given = dict(state) | ({} if self.agent_first else dict(inputs))
        return {y: self._value(self.output[y], given) for y in self.outputs}

    def step(self, state: Assignment, letter: Assignment) -> dict[str, bool]:
        """The state after the letter (every input and output valued)."""
        given = dict(state) | dict(letter)
        return {b: self._value(self.delta[b], given) for b in self.bits}

    def is_accepting(self, state: Assignment) -> bool:
        return self._value(self.accepting, state)

    def rank(self, state: Assignment) -> int | None:
        """The least i with `state` in W_i; None outside W."""
        return next((i for i, won in enumerate(self.rounds, 1) if self._value(won, state)), None)

    def _value(self, f: Function, values: Assignment) -> bool:
        # restrict f to the variables it reads; every one must be valued
        support = self.bdd.support(f)
        return cofactor(self.bdd, {v: bool(values[v]) for v in support}, f) == self.bdd.true

    def to_json(self) -> dict[str, Any]:
        roots = {"delta": dict(self.delta), "accepting": self.accepting, "winning": self.winning,
                 "rounds": list(self.rounds), "output": dict(self.output)}
        nodes, refs = _export(self.bdd, roots)
        return {"format": FORMAT, "agent_first": self.agent_first, "inputs": list(self.inputs),
                "outputs": list(self.outputs), "state_bits": list(self.bits), "initial": self.initial,
                "variables": sorted(self.bits + self.inputs + self.outputs, key=self.bdd.level_of_var),
                "roots": refs, "nodes": nodes}


def symbolic_strategy(game: Realizability) -> SymbolicStrategy:
    """The strategy of the module docstring for a realizable `game`."""
    if not game.realizable:
        raise ValueError("no winning strategy")
    dfa, bdd = game.dfa, game.dfa.bdd
    xs = set(game.inputs)
    unowned = set(dfa.atoms) - xs - set(game.outputs)
    if unowned:
        raise ValueError(f"variables of neither player: {sorted(unowned)}")
    moves = bdd.false
    below = bdd.false
    after = bdd.false  # (Acc \/ W_{i-1})(delta(q, x, y)), grown by the new states' preimage (game.py)
    taken = bdd.false
    for won in game.rounds:
        target = dfa.accepting | below
        after, taken = after | game.preimage(target & ~taken), target
        # (W_i \ W_{i-1})(q) /\ (Acc \/ W_{i-1})(delta(q, x, y))
        moves |= won & ~below & after
        below = won
    allowed = bdd.forall(xs, moves) if game.agent_first and xs else moves  # \A x: M (agent first)
    output = least_outputs(bdd, allowed, game.outputs)  # f_y = !\E y_rest: A[y := false], A := A[y := f_y]
    return SymbolicStrategy(bdd, game.agent_first, game.inputs, game.outputs, dfa.bits,
                            dict(dfa.initial_assignment), {b: dfa.delta[b] for b in dfa.bits}, dfa.accepting,
                            below, list(game.rounds), output)


def write_json(strategy: SymbolicStrategy) -> str:
    return json.dumps(strategy.to_json(), separators=(",", ":")) + "\n"


def _export(bdd: BDD, roots: dict[str, Any]) -> tuple[list[list], dict[str, Any]]:
    """The nodes under `roots` without complement edges, children first."""
    index: dict[Function, int] = {bdd.false: 0, bdd.true: 1}
    nodes: list[list] = []

    def ref(root: Function, where: str) -> int:
        for u, low, high in children_first(bdd, root, index):
            index[u] = len(nodes) + 2
            nodes.append([u.var, index[low], index[high]])
        return index[root]

    return nodes, _map(roots, ref)


def _map(value, leaf, where: str = "roots"):
    """`value` with each leaf replaced by `leaf(it, where)`, dicts and lists kept.
    (Module level, not a nested recursive function: a closure that refers to
    itself is a reference cycle, and the garbage collector may then free the
    BDD manager before the nodes the closure holds.)"""
    if isinstance(value, dict):
        return {k: _map(v, leaf, f"{where}.{k}") for k, v in value.items()}
    if isinstance(value, list):
        return [_map(v, leaf, f"{where}[{i}]") for i, v in enumerate(value)]
    return leaf(value, where)


def read_symbolic_strategy(path: str | Path) -> SymbolicStrategy:
    """Load a strategy file into a fresh BDD manager; a malformed file is an
    InputError naming the key."""
    try:
        data = json.loads(read_text(Path(path), "strategy file"))
    except json.JSONDecodeError as error:
        raise InputError(f"{path}:{error.lineno}:{error.colno}: not JSON: {error.msg}") from None

    def need(key: str, kind: type) -> Any:
        if not isinstance(data, dict) or not isinstance(data.get(key), kind):
            raise InputError(f"{path}: key '{key}': expected a {kind.__name__}")
        return data[key]
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"{path}: key 'format': expected {FORMAT!r}")
    variables = need("variables", list)
    bdd = new_manager()
    bdd.declare(*variables)
    built = [bdd.false, bdd.true]
    for k, node in enumerate(need("nodes", list)):
        if not (isinstance(node, list) and len(node) == 3 and node[0] in bdd.vars
                and all(isinstance(c, int) and 0 <= c < len(built) for c in node[1:])):
            raise InputError(f"{path}: key 'nodes[{k}]': expected [variable, low, high] with children "
                             "among the nodes before it")
        var, low, high = node
        built.append(bdd.ite(bdd.var(var), built[high], built[low]))
    roots = need("roots", dict)
    for key, kind in (("delta", dict), ("accepting", int), ("winning", int), ("rounds", list), ("output", dict)):
        if not isinstance(roots.get(key), kind):
            raise InputError(f"{path}: key 'roots.{key}': expected a {kind.__name__}")

    def get(value, where: str) -> Function:
        if not isinstance(value, int) or not 0 <= value < len(built):
            raise InputError(f"{path}: key '{where}': expected a node reference below {len(built)}")
        return built[value]
    fn = _map(roots, get)
    return SymbolicStrategy(bdd, bool(need("agent_first", bool)), tuple(need("inputs", list)),
                            tuple(need("outputs", list)), tuple(need("state_bits", list)),
                            dict(need("initial", dict)), fn["delta"], fn["accepting"], fn["winning"],
                            fn["rounds"], fn["output"])

