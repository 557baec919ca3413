"""LTLf formulas for `ltlf_bench.py`: a small tuple AST printed for symsynth
and ltlf2dfa, the families it generates, random traces and an independent
position-indexed evaluator (the oracle)."""

from __future__ import annotations

import random


# ("ap", name) ("true",) ("false",) ("last",)
# (op, f) for op in ! X WX F G
# (op, f, g) for op in & | -> <-> U R

UNARY = ("!", "X", "WX", "F", "G")
BINARY = ("&", "|", "->", "<->", "U", "R")


def ap(name):
    return ("ap", name)


def text_of(node, top=True):
    """Text read identically by symsynth and ltlf2dfa.

    Unary operators bind tightest in both grammars; every binary
    subformula is parenthesized, so precedence and associativity (which
    differ: ltlf2dfa chains U/R to the left, symsynth to the right) never
    matter.  `X` is strong next in both (symsynth's default convention).
    """
    op = node[0]
    if op == "ap":
        return node[1]
    if op in ("true", "false", "last"):
        return op
    if op in UNARY:
        arg = text_of(node[1], top=False)
        if node[1][0] in BINARY and not arg.startswith("("):
            arg = f"({arg})"
        return f"!{arg}" if op == "!" else f"{op} {arg}"
    # & and | are associative in both grammars: print chains flat
    left = text_of(node[1], top=op in ("&", "|") and node[1][0] == op)
    right = text_of(node[2], top=False)
    s = f"{left} {op} {right}"
    return s if top else f"({s})"


sym_text = text_of   # symsynth grammar (grammars/ltlf.lark)
l2d_text = text_of   # ltlf2dfa grammar (ltlf2dfa/parser/ltlf.lark): lower-case atoms only


def atoms_of(node, out=None):
    out = {} if out is None else out
    if node[0] == "ap":
        out.setdefault(node[1], None)
    for child in node[1:]:
        if isinstance(child, tuple):
            atoms_of(child, out)
    return list(out)


def temporal_depth(node):
    kids = [temporal_depth(c) for c in node[1:] if isinstance(c, tuple)]
    here = 1 if node[0] in ("X", "WX", "F", "G", "U", "R") else 0
    return here + max(kids, default=0)


def oracle(node, trace):
    """Truth of `node` at position 0 of the non-empty `trace` (LTLf semantics,
    De Giacomo & Vardi 2013), by one backward pass per subformula."""
    return _values(node, trace)[0]


def _values(node, trace):
    n, op = len(trace), node[0]
    if op == "ap":
        return [node[1] in letter for letter in trace]
    if op == "true":
        return [True] * n
    if op == "false":
        return [False] * n
    if op == "last":
        return [i == n - 1 for i in range(n)]
    f = _values(node[1], trace)
    if op == "!":
        return [not v for v in f]
    if op == "X":
        return [i + 1 < n and f[i + 1] for i in range(n)]
    if op == "WX":
        return [i + 1 >= n or f[i + 1] for i in range(n)]
    if op in ("F", "G"):
        out, acc = [False] * n, op == "G"
        for i in range(n - 1, -1, -1):
            acc = (f[i] or acc) if op == "F" else (f[i] and acc)
            out[i] = acc
        return out
    g = _values(node[2], trace)
    if op == "&":
        return [x and y for x, y in zip(f, g)]
    if op == "|":
        return [x or y for x, y in zip(f, g)]
    if op == "->":
        return [(not x) or y for x, y in zip(f, g)]
    if op == "<->":
        return [x == y for x, y in zip(f, g)]
    out, acc = [False] * n, op == "R"
    for i in range(n - 1, -1, -1):
        if op == "U":
            acc = g[i] or (f[i] and acc)
        else:  # f R g: g holds up to and including the first f, or forever
            acc = g[i] and (f[i] or acc)
        out[i] = acc
    return out


def conj_formula(n):
    node = None
    for i in range(1, n + 1):
        part = ("G", ("->", ap(f"a{i}"), ("F", ap(f"b{i}"))))
        node = part if node is None else ("&", node, part)
    return node


def seq_formula(n):
    node = ap(f"a{n}")
    for i in range(n - 1, 0, -1):
        node = ("&", ap(f"a{i}"), ("X", ("F", node)))
    return ("F", node)


_UNARY_W = [("!", 2), ("X", 2), ("WX", 1), ("F", 3), ("G", 3)]
_BINARY_W = [("&", 3), ("|", 3), ("->", 2), ("<->", 1), ("U", 3), ("R", 2)]


def _pick(rng, weighted):
    total = sum(w for _, w in weighted)
    r = rng.uniform(0, total)
    for item, w in weighted:
        r -= w
        if r <= 0:
            return item
    return weighted[-1][0]


def random_formula(rng, size, atoms):
    """A formula with exactly `size` nodes."""
    if size <= 1:
        r = rng.random()
        if r < 0.05:
            return ("true",)
        if r < 0.09:
            return ("false",)
        if r < 0.15:
            return ("last",)
        return ap(rng.choice(atoms))
    if size == 2 or rng.random() < 0.4:
        return (_pick(rng, _UNARY_W), random_formula(rng, size - 1, atoms))
    left = rng.randint(1, size - 2)
    return (_pick(rng, _BINARY_W), random_formula(rng, left, atoms),
            random_formula(rng, size - 1 - left, atoms))


def random_family(count, seed, max_size=13):
    rng = random.Random(seed)
    atoms = ["a", "b", "c", "d"]
    seen, out = set(), []
    while len(out) < count:
        node = random_formula(rng, rng.randint(2, max_size), atoms)
        key = text_of(node)
        if key not in seen:
            seen.add(key)
            out.append(node)
    return out


def make_traces(rng, atoms, depth, count):
    """Random non-empty traces; every single-letter trace first when few."""
    traces = []
    if 2 ** len(atoms) <= 16:
        for bits in range(2 ** len(atoms)):
            traces.append([frozenset(a for k, a in enumerate(atoms) if bits >> k & 1)])
    lmax = min(24, max(6, 2 * depth + 3))
    while len(traces) < count:
        length = rng.randint(1, lmax)
        p = rng.choice((0.15, 0.5, 0.85))
        traces.append([frozenset(a for a in atoms if rng.random() < p) for _ in range(length)])
    return traces[:count]
