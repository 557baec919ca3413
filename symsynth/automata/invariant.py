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

from symsynth.automata import moves as moves_
from symsynth.automata.bdd import Function, branches, cofactor, exits, split_letters
from symsynth.automata.growth import grew
from symsynth.automata.progression import GuardedDFA, Progression, TooDense, TooLarge
from symsynth.automata.rows import below_atoms
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


#: H's targets times the states with allowed letters, per state, up to which
#: a sparse invariant's edges are read off H (`Invariants.dfa`; measured on
#: the single counters: reading them off H pays up to about 1,000 targets
#: a state, decoding the moves from 3,000 on)
SPLIT_TARGETS = 512


class Invariants:
    """Builds the DFAs of one-step invariants in a `Progression`'s manager
    (atoms above everything else; guards are BDDs over the atoms)."""

    def __init__(self, progression: Progression):
        self.progression = progression
        self.bdd = progression.bdd
        self._primed = {key: f"#y{i}" for i, key in enumerate(progression.atom_keys)}
        self._unprimed = {name: key for key, name in self._primed.items()}
        self._declared = False

    @property
    def below_atoms(self) -> int:
        """The first level below the atoms (rows.py's bits may come above them)."""
        return below_atoms(self.bdd, self.progression.atom_keys)

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
        """The complete DFA of `P G body` (`invariant_shape`'s parts), given
        by its moves (moves.py); `TooLarge` past `max_edges` edges, or past
        `max_degree` successors per state on average (plus a slack of 2,000
        edges) once there are 100 states.

        States: the prefix's, the start of `G body` (state `k`), the
        cofactors of `H` (the nodes where its paths leave the atom levels:
        every letter leads somewhere from the start, so these are all the
        states), and the sink.  With Next(x, z) = H with each cofactor
        replaced by its number, a cofactor state `c` moves by
        `allowed_c(x) ? Next : sink`: a few BDD operations per state,
        whatever its number of successors (Nim's merged invariants: 50 to
        80 successors per state, each a guard to split off by the letters
        otherwise)."""
        self._declare()
        bdd = self.bdd
        moves_f, ends = self._evaluate(body)  # F(x, y), E(x)
        e = bdd.var("#e")
        h = (e & ends) | (~e & moves_f)
        k = len(prefix)
        cofactors = self._cofactors(h)
        dead = bdd.false in cofactors  # a first letter after which nothing is allowed: the sink's
        if dead:
            cofactors.remove(bdd.false)
        allowed = [bdd.let(self._unprimed, cofactor(bdd, {"#e": False}, node)) for node in cofactors]  # F(x0, y := x)
        sink = k + 1 + len(cofactors)
        has_sink = dead or any(a != bdd.true for a in allowed)
        n = sink + 1 if has_sink else sink
        grew(n, n)
        names = moves_.bits(bdd, "z", moves_.width(n))
        cubes = [moves_.cube(bdd, names, i) for i in range(n)]
        number = {node: k + 1 + i for i, node in enumerate(cofactors)}
        if dead:
            number[bdd.false] = sink
        step = self._relabel(h, {node: cubes[i] for node, i in number.items()})  # Next(x, z)
        accepting = [i >= 1 and prefix[i - 1] is ast.WeakNext for i in range(k + 1)]
        accepting += [cofactor(bdd, {"#e": True}, node) == bdd.true for node in cofactors]
        moves = [cubes[i + 1] for i in range(k)] + [step]
        moves += [step if ok == bdd.true else bdd.ite(ok, step, cubes[sink]) for ok in allowed]
        if has_sink:
            accepting.append(False)
            moves.append(cubes[sink])
        degrees = moves_.count_edges(bdd, moves)
        count = sum(degrees)
        if max_edges is not None and count > max_edges:
            raise TooLarge(f"more than {max_edges} edges")
        if max_degree is not None and n >= 100 and count > max_degree * n + 2000:
            raise TooDense(f"more than {max_degree} successors per state")
        edges = None
        # its products take its edges (sparse): read them off H, unless the
        # states with allowed letters times H's targets (a conjunction
        # each, 0.2 us) pass SPLIT_TARGETS per state (a counter's 4,097
        # states would cost 16 million: 5.5 s of counter_11's 8 s; decoded
        # from the moves state by state instead, when a product asks)
        restricted = sum(ok != bdd.true for ok in allowed)
        if count <= moves_.SPARSE_DEGREE * n and len(cofactors) * restricted <= SPLIT_TARGETS * n:
            edges = self._edges(h, k, allowed, number, sink, has_sink)
        return GuardedDFA(bdd, 0, accepting, edges, moves=moves, degrees=degrees)

    def _edges(self, h: Function, k: int, allowed: list[Function], number: dict[Function, int], sink: int,
               has_sink: bool) -> list[dict[int, Function]]:
        """`dfa`'s edges, read off H: the prefix's chain, the start's letters
        into each cofactor, and each cofactor state's the same where its
        letter is allowed, into the sink where not."""
        bdd = self.bdd
        split = split_letters(bdd, h, self.below_atoms)  # cofactor -> the letters into it
        after = {number[node]: guard for node, guard in split.items()}
        edges = [{i + 1: bdd.true} for i in range(k)] + [after]
        for ok in allowed:  # allowed(x) ? the letters' successors : the sink
            if ok == bdd.true:
                edges.append(dict(after))
                continue
            out = {t: guard & ok for t, guard in after.items()}
            out[sink] = out.get(sink, bdd.false) | ~ok
            edges.append({t: guard for t, guard in out.items() if guard != bdd.false})
        if has_sink:
            edges.append({sink: bdd.true})
        return edges

    def _cofactors(self, h: Function) -> list[Function]:
        """The nodes where the paths of `h` leave the atom levels, in the
        order a depth-first walk (high branch first) meets them."""
        return list(exits(self.bdd, h, self.below_atoms))

    def _relabel(self, h: Function, label: dict[Function, Function]) -> Function:
        """`h` with each node where its paths leave the atom levels replaced
        by `label[node]`: one `ite` per node at the atom levels."""
        bdd, top = self.bdd, self.below_atoms
        done: dict[Function, Function] = {}
        stack = [h]
        while stack:
            node = stack[-1]
            if node in done:
                stack.pop()
                continue
            if node in label and (node == bdd.true or node == bdd.false or node.level >= top):
                done[node] = label[node]
                stack.pop()
                continue
            low, high = branches(bdd, node)
            missing = [c for c in (low, high) if c not in done]
            if missing:
                stack += missing
                continue
            stack.pop()
            done[node] = bdd.ite(bdd.var(node.var), done[high], done[low])
        return done[h]
