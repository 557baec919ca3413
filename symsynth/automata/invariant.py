"""Explicit DFA of an invariant `P G f` whose `f` looks one step ahead.

`f` is a Boolean combination of propositions on the current letter, `X g`,
`WX g` (with `g` propositional) and `last`; `P` is a prefix of `X` / `WX`
(often empty).  Such invariants are the bulk of the game benchmarks (the
counters, Nim): dozens of constraints between a letter and the next one.

Formula progression builds their DFA with the state "what the next letters
must satisfy" as a BDD whose atoms sit above the obligations, and a
constraint like `counter_i <-> X carry_i` for every bit makes that BDD
exponential in the bits.  Here the state is read off the letter instead:
with the next letter's atoms as primed copies `y`,

    F(x, y) = f with `X g`, `WX g` as g(y), `last` false   (a next letter y exists)
    E(x)    = f with `X g` false, `WX g` true, `last` true  (the trace ends at x)

after a letter `x` the trace is accepted iff it ends here and `E(x)`, and
a next letter `y` is allowed iff `F(x, y)`.  So letters with the same
cofactor `(E(x), F(x, .))` lead to the same state, and the states are these
cofactors: the nodes where the paths of

    H(x, e, y) = e & E(x) | !e & F(x, y)        (x above e and y)

leave the atom levels.  From state `c = H(x0, ., .)` a letter `x` is
allowed iff `F(x0, x)`, and it leads to the state of `x`: the successors of
`c` are where the paths of `F(x0, y := x) & H` leave the atom levels, and
the letters that lead nowhere go to the sink.  Two states with the same
cofactor accept the same words, so the automaton is minimal up to the
initial state, the prefix and the sink (the caller minimizes).
"""

from __future__ import annotations

from symsynth.automata.bdd import Function
from symsynth.automata.progression import GuardedDFA, Progression, TooDense, TooLarge, split_letters
from symsynth.logic import ast


def invariant_shape(formula: ast.Formula) -> tuple[list[type], ast.Formula] | None:
    """`(prefix, f)` when the NNF `formula` is `P G f` with `P` a list of
    `ast.Next` / `ast.WeakNext` (outermost first) and `f` of next-depth at
    most one (see the module doc); else None."""
    prefix: list[type] = []
    node = formula
    while isinstance(node, (ast.Next, ast.WeakNext)):
        prefix.append(type(node))
        node = node.arg
    if not isinstance(node, ast.Always):
        return None
    stack = [(node.arg, False)]  # (subformula, under X / WX)
    while stack:
        f, under = stack.pop()
        if isinstance(f, (ast.Next, ast.WeakNext)):
            if under:
                return None
            stack.append((f.arg, True))
        elif isinstance(f, ast.Last):
            if under:
                return None
        elif isinstance(f, (ast.And, ast.Or)):
            stack += [(f.left, under), (f.right, under)]
        elif isinstance(f, ast.Not):
            if not isinstance(f.arg, ast.Atom):
                return None
        elif not isinstance(f, (ast.Atom, ast.Const)):
            return None
    return prefix, node.arg


class Invariants:
    """Builds the DFAs of one-step invariants in a `Progression`'s manager
    (atoms above everything else; guards are BDDs over the atoms)."""

    def __init__(self, progression: Progression):
        self.progression = progression
        self.bdd = progression.bdd
        self.num_atoms = len(progression.atom_keys)
        self._primed = {key: f"#y{i}" for i, key in enumerate(progression.atom_keys)}
        self._unprimed = {name: key for key, name in self._primed.items()}
        self._declared = False

    def _declare(self) -> None:
        if not self._declared:  # below the atoms: declared after them
            self.bdd.declare("#e", *self._primed.values())
            self._declared = True

    def _evaluate(self, body: ast.Formula) -> tuple[Function, Function]:
        """`(F, E)` of the module doc, bottom-up over `body` (no recursion).
        Built directly rather than from `Progression.unfold(body)`, whose
        separate variables for `X g` and `WX g` make the counters' BDD
        exponential in the bits (180,000 nodes at seven bits)."""
        bdd, progression = self.bdd, self.progression
        values: dict[int, tuple[Function, Function]] = {}
        stack = [(body, False)]
        while stack:
            node, ready = stack.pop()
            if id(node) in values:
                continue
            if isinstance(node, (ast.And, ast.Or)) and not ready:
                stack += [(node, True), (node.left, False), (node.right, False)]
                continue
            if isinstance(node, (ast.And, ast.Or)):
                (f1, e1), (f2, e2) = values[id(node.left)], values[id(node.right)]
                values[id(node)] = (f1 & f2, e1 & e2) if isinstance(node, ast.And) else (f1 | f2, e1 | e2)
            elif isinstance(node, (ast.Next, ast.WeakNext)):  # g on the next letter; at the end, X false, WX true
                after = bdd.let(self._primed, progression.unfold(node.arg))
                values[id(node)] = (after, bdd.false if isinstance(node, ast.Next) else bdd.true)
            elif isinstance(node, ast.Last):
                values[id(node)] = (bdd.false, bdd.true)
            else:  # atom, negated atom, constant: this letter
                now = progression.unfold(node)
                values[id(node)] = (now, now)
        return values[id(body)]

    def dfa(self, prefix: list[type], body: ast.Formula, max_edges: int | None = None,
            max_degree: int | None = None) -> GuardedDFA:
        """The complete DFA of `P G body` (`invariant_shape`'s parts), its
        states in BFS order; `TooLarge` past `max_edges` edges, or past
        `max_degree` successors per state on average (plus a slack of 2,000
        edges) over the states built so far, once there are 100."""
        self._declare()
        bdd, progression = self.bdd, self.progression
        moves, ends = self._evaluate(body)  # F(x, y), E(x)
        e = bdd.var("#e")
        h = (e & ends) | (~e & moves)

        k = len(prefix)
        accepting = [i >= 1 and prefix[i - 1] is ast.WeakNext for i in range(k + 1)]
        edges: list[dict[int, Function]] = [{i + 1: bdd.true} for i in range(k)] + [{}]
        index: dict[Function, int] = {}
        order: list[Function] = []
        sink: list[int] = []
        count = k
        filled = [0]  # states whose edges are built
        below: dict = {}  # split_letters' memo: the states' BDDs share nodes of h

        def state(node: Function) -> int:
            if node == bdd.false:
                if not sink:
                    sink.append(len(accepting))
                    accepting.append(False)
                    edges.append({sink[0]: bdd.true})
                return sink[0]
            found = index.get(node)
            if found is None:
                found = index[node] = len(accepting)
                order.append(node)
                accepting.append(bdd.let({"#e": True}, node) == bdd.true)
                edges.append({})
            return found

        def fill(source: int, u: Function) -> None:
            nonlocal count
            out = edges[source]
            for node, guard in split_letters(bdd, u, self.num_atoms, below).items():
                target = state(node)
                out[target] = out[target] | guard if target in out else guard
            count += len(out)
            filled[0] += 1
            if max_edges is not None and count > max_edges:
                raise TooLarge(f"more than {max_edges} edges")
            if max_degree is not None and filled[0] >= 100 and count > max_degree * filled[0] + 2000:
                raise TooDense(f"more than {max_degree} successors per state")

        fill(k, h)  # the first letter of G body: any letter, to its cofactor
        for node in order:  # grows while we walk it: BFS
            allowed = bdd.let(self._unprimed, bdd.let({"#e": False}, node))  # F(x0, y := x)
            fill(index[node], allowed & h)
        return GuardedDFA(bdd, 0, accepting, edges)
