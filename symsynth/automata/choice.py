"""Which construction `compile_ltlf(construction="auto")` uses: a rule read
off the formula, then a bounded race.

The compositional construction (compose.py) builds a minimal DFA for each
part of the formula alone; progression (progression.py) builds the states
of the whole formula reachable from its start.  Each loses badly somewhere:

- progression, where its obligations are exponential in the formula's
  size: an equivalence with a next on one side (`counter_i <-> X carry_i`:
  the counters, Double-Counter counters_03 3.0 s against 0.12 s), and a
  Boolean combination of temporal parts over disjoint atoms, whose states
  progression multiplies out (GFand's `G p1 & F p2 & ... & F pn`: 2^(n-1)
  states with 2^(n-1) successors each, where the compositional construction
  keeps the parts apart in a symbolic product);
- the compositional construction, where a part is large alone and small in
  context: SYNTCOMP's chomp, whose `G ASSERT` tracks every subset of the
  board (1,538 states at 2 x 5) while the boards reachable from the initial
  one are few (64 states in all).

A third shape loses less but often: a Boolean skeleton over many temporal
parts that share atoms (assume-guarantee: `(G(r1 -> F !r1) & ...) ->
(G(r1 -> F g1) & ... & G !(g1 & g2) & ...)`), where progression's states
are sets of the parts' residues and the compositional construction builds
each part alone (ag04: 43 ms against 7.5 ms; MONA 10 ms).

So `auto` takes the compositional construction when the formula has one of
the three shapes above (`rule`), and otherwise progresses the whole formula
under a budget, AUTO_EDGES edges, and at most AUTO_DEGREE successors per
state on average over its first AUTO_DENSE_AFTER states; past the budget
the work is dropped and the compositional construction runs.  (Nim's
formula has chomp's shape, `Init & (G A -> (G B & U))`, but its states are
dense from the start, 228 successors each over the first 16 at five heaps,
684 at six: progression and its minimization by guards cost 16 s at five
heaps, the compositional construction 4 s, on moves.  Chomp's first 16
states have 8-9 successors; a few later ones thousands, 36 on average at 4 x 3.)

A third construction, backward (backward.py: the formula evaluated
backwards, its reverse determinized, minimal as built), wins on one shape:
deep alternation of until-like and release-like operators along a path of
the formula (`p1 U (p2 R (p3 U ...))`, URright): 4.6x at seven alternating
operators (urright08), 17x at nine, 100x at eleven (urright12: 4 s
against 397 s), where progression's states before minimization grow with
every alternation.  Every other formula of the benchmark families has at
most three (`alternation`), and backward loses on them, badly where the
minimal DFA is a product of parts (GFand, AG, counters: its reversed
automaton tracks every part at once).  So `auto` takes it, before
progression, when the formula has AUTO_ALTERNATION alternating operators
or more and no more than AUTO_OBLIGATIONS obligations (its reversed
automaton's state bits: past that, the image of the reachable set, over
twice as many bits, is what costs: Nim nim_03_01's 26 took 15 s for one).
Measurements: docs/ltlf.md, "Choosing the construction".
"""

from __future__ import annotations

from symsynth.logic import ast

#: Progression's budget under `auto`: edges in all (chomp 4 x 3: 76,419), ...
AUTO_EDGES = 200_000
#: ... and successors per state on average over the first AUTO_DENSE_AFTER
#: states (chomp 2 x 5 and 4 x 3: 8.1 and 9.2; Nim nim_05_01: 228, nim_06_01: 684).
#: (32 states at first: AG's, Nim's and Syft's dropped attempts cost more, docs/ltlf.md.)
AUTO_DEGREE = 64
AUTO_DENSE_AFTER = 16
#: Temporal parts from which the rule takes the compositional construction
#: even when they share atoms: the assume-guarantee family (`bench/ltlf_generated.py`)
#: has 9 at n = 3, 14 at n = 4 (progression 43 ms there against 7.5 ms), while
#: the formulas progression wins on have at most 7 (chomp 6, Dwyer's
#: conjunctions up to 7, Nim 3); docs/ltlf.md, "Choosing the construction".
MANY_PARTS = 8

#: The backward construction under `auto`: from this many alternating
#: until-like / release-like operators on one path (URright: n - 1 at n
#: atoms; urright06, 5, is a tie; every other family: at most 3) ...
AUTO_ALTERNATION = 6
#: ... and up to this many obligations (urright at n atoms: n - 1; nim_03_01: 26).
AUTO_OBLIGATIONS = 20

_LEAST = (ast.Until, ast.Eventually)  # until-like: a least fixpoint
_GREATEST = (ast.Release, ast.WeakUntil, ast.Always)  # release-like: a greatest one
_NEXT = (ast.Next, ast.WeakNext)
_TEMPORAL = (ast.Next, ast.WeakNext, ast.Eventually, ast.Always, ast.Until, ast.Release, ast.WeakUntil)
_BOOLEAN = (ast.Not, ast.And, ast.Or, ast.Implies, ast.Equiv)


def rule(formula: ast.Formula) -> str | None:
    """Why `formula` goes to the compositional construction directly (a
    sentence), or None when progression is tried first."""
    if _next_equivalence(formula):
        return "an equivalence with a next operand (progression is exponential in them)"
    parts = _temporal_parts(formula)
    if len(_connected(parts)) > 1:
        return "temporal parts over disjoint atoms (progression multiplies their states)"
    if len(parts) >= MANY_PARTS:
        return f"{len(parts)} temporal parts in its Boolean skeleton (progression's states combine their residues)"
    return None


def _has_next(node: ast.Formula) -> bool:
    stack = [node]
    while stack:
        f = stack.pop()
        if isinstance(f, _NEXT):
            return True
        stack.extend(ast.children(f))
    return False


def _next_equivalence(formula: ast.Formula) -> bool:
    """Whether an `<->` has a next (`X`, `WX`) in exactly one operand."""
    stack = [formula]
    while stack:
        f = stack.pop()
        if isinstance(f, ast.Equiv) and _has_next(f.left) != _has_next(f.right):
            return True
        stack.extend(ast.children(f))
    return False


def _temporal_parts(formula: ast.Formula) -> list[set[str]]:
    """The atoms of each of the formula's temporal parts (the subformulas
    under its Boolean skeleton whose top operator is temporal)."""
    parts: list[set[str]] = []
    stack = [formula]
    while stack:
        f = stack.pop()
        if isinstance(f, _BOOLEAN):
            stack.extend(ast.children(f))
        elif isinstance(f, _TEMPORAL) and ast.atoms(f):  # (a part without atoms reads trace lengths)
            parts.append({a.key for a in ast.atoms(f)})
    return parts


def _connected(parts: list[set[str]]) -> list[set[str]]:
    """The parts' atoms grouped by the atoms they share (connected components)."""
    groups: list[set[str]] = []
    for atoms in parts:
        joined = [g for g in groups if g & atoms]
        merged = set(atoms).union(*joined)
        groups = [g for g in groups if not g & atoms] + [merged]
    return groups


def alternation(formula: ast.Formula) -> int:
    """The most operators on one path down the NNF `formula` alternating
    between until-like (U, F) and release-like (R, W, G), others skipped:
    p1 U (p2 R (p3 U p4)) has 3, G F a 2, a U (b U c) 1."""
    longest: dict[ast.Formula, tuple[int, int]] = {}  # f -> (from an until-like, from a release-like)
    stack = [formula]
    while stack:
        f = stack[-1]
        if f in longest:
            stack.pop()
            continue
        kids = ast.children(f)
        missing = [c for c in kids if c not in longest]
        if missing:
            stack.extend(missing)
            continue
        stack.pop()
        least = max((longest[c][0] for c in kids), default=0)
        greatest = max((longest[c][1] for c in kids), default=0)
        if isinstance(f, _LEAST):
            least = 1 + greatest
        elif isinstance(f, _GREATEST):
            greatest = 1 + least
        longest[f] = (least, greatest)
    return max(longest[formula])
