"""ltlf2dfa's and MONA's automata for `ltlf_bench.py` and the other LTLf
benchmarks: read off ltlf2dfa's DOT or MONA's output, simulated on traces,
their states counted."""

from __future__ import annotations

import re
from dataclasses import dataclass


@dataclass
class Auto:
    """A complete DFA read off ltlf2dfa's DOT or MONA's output."""
    start: int
    accepting: set
    rows: dict            # state -> list of (predicate(letter) -> bool, target)
    signature: dict       # state -> hashable; equal iff equal transition functions
    source: str           # "dot" or "mona"

    def run(self, trace):
        state = self.start
        for letter in trace:
            for pred, target in self.rows.get(state, ()):
                if pred(letter):
                    state = target
                    break
            else:
                raise ValueError(f"no transition from {state} on {sorted(letter)}")
        return state in self.accepting

    def reachable(self, roots):
        seen, stack = set(roots), list(roots)
        while stack:
            for _, t in self.rows.get(stack.pop(), ()):
                if t not in seen:
                    seen.add(t)
                    stack.append(t)
        return seen

    def counts(self):
        """(states as drawn, minimal complete DFA size over non-empty traces).

        The automaton is MONA's minimal DFA of L' (ltlf2dfa's language, where
        the empty trace counts), started after MONA's state 0.  Over non-empty
        traces the language is L = L' minus the empty trace.  The residuals of
        L after non-empty words are those of L' (the states S reachable by a
        non-empty word, pairwise distinct by minimality); the residual of L at
        the empty word is L itself.  So |min DFA(L)| = |S| + [L not a residual
        of S].  If the start state rejects, L = L' and the answer is the drawn
        size.  Otherwise a state q in S has residual L iff q rejects and q has
        exactly the start state's transitions (same successor on each letter,
        by minimality), which is a comparison of MONA's canonical BDD paths.
        """
        drawn = self.reachable([self.start])
        if self.start not in self.accepting:
            return len(drawn), len(drawn)
        after = self.reachable({t for _, t in self.rows.get(self.start, ())})
        sig = self.signature[self.start]
        twin = any(q not in self.accepting and self.signature.get(q) == sig for q in after)
        return len(drawn), len(after) + (0 if twin else 1)


_TOKEN = re.compile(r"\s*(?:([A-Za-z_][A-Za-z0-9_]*)|(.))")


def compile_guard(text):
    """A sympy guard as ltlf2dfa prints it (`~a & b | c`, `true`, lower-cased)
    -> predicate over a letter (set of true atoms)."""
    tokens = [m.group(1) or m.group(2) for m in _TOKEN.finditer(text) if (m.group(1) or m.group(2))]
    pos = 0

    def peek():
        return tokens[pos] if pos < len(tokens) else None

    def take(expected=None):
        nonlocal pos
        tok = peek()
        if expected is not None and tok != expected:
            raise ValueError(f"guard {text!r}: expected {expected!r}, got {tok!r}")
        pos += 1
        return tok

    def disj():
        parts = [conj()]
        while peek() == "|":
            take()
            parts.append(conj())
        return parts[0] if len(parts) == 1 else (lambda s, p=parts: any(q(s) for q in p))

    def conj():
        parts = [unary()]
        while peek() == "&":
            take()
            parts.append(unary())
        return parts[0] if len(parts) == 1 else (lambda s, p=parts: all(q(s) for q in p))

    def unary():
        if peek() == "~":
            take()
            inner = unary()
            return lambda s: not inner(s)
        return primary()

    def primary():
        tok = take()
        if tok == "(":
            inner = disj()
            take(")")
            return inner
        if tok == "true":
            return lambda s: True
        if tok == "false":
            return lambda s: False
        if tok is None or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", tok):
            raise ValueError(f"guard {text!r}: unexpected {tok!r}")
        if peek() == "(":  # sympy function form: xor, equivalent, implies, ite, not, and, or
            take("(")
            args = [disj()]
            while peek() == ",":
                take()
                args.append(disj())
            take(")")
            fn = {
                "xor": lambda v: sum(v) % 2 == 1,
                "equivalent": lambda v: all(v) or not any(v),
                "implies": lambda v: (not v[0]) or v[1],
                "ite": lambda v: v[1] if v[0] else v[2],
                "not": lambda v: not v[0],
                "and": all, "or": any,
            }.get(tok)
            if fn is None:
                raise ValueError(f"guard {text!r}: unknown function {tok!r}")
            return lambda s, a=args, f=fn: f([q(s) for q in a])
        return lambda s, name=tok: name in s

    result = disj()
    if pos != len(tokens):
        raise ValueError(f"guard {text!r}: trailing {tokens[pos:]!r}")
    return result


def parse_l2d_dot(dot):
    start, accepting, rows, sig = None, set(), {}, {}
    for line in dot.splitlines():
        s = line.strip()
        if s.startswith("node [shape = doublecircle]"):
            accepting = {int(x) for x in re.findall(r"\d+", s.split("]", 1)[1])}
            continue
        m = re.fullmatch(r"init -> (\d+);", s)
        if m:
            start = int(m.group(1))
            continue
        m = re.fullmatch(r'(\d+) -> (\d+) \[label="(.*)"\];', s)
        if m:
            src, dst, guard = int(m.group(1)), int(m.group(2)), m.group(3)
            rows.setdefault(src, []).append((compile_guard(guard), dst))
            sig.setdefault(src, set()).add((guard, dst))
    if start is None:
        raise ValueError("no initial state in ltlf2dfa's DOT")
    return Auto(start, accepting, rows, {k: frozenset(v) for k, v in sig.items()}, "dot")


def _pattern_pred(variables, pattern):
    need = [(v, c == "1") for v, c in zip(variables, pattern) if c in "01"]
    return lambda s: all((v in s) == want for v, want in need)


def parse_mona(output):
    """MONA's `-w` automaton; the trace starts after state 0's dummy letter."""
    m = re.search(r"DFA for formula with free variables:[ \t]*(.*)", output)
    if not m:
        raise ValueError("no automaton in MONA's output")
    variables = [v.lower() for v in m.group(1).split()]
    m = re.search(r"Accepting states:[ \t]*(.*)", output)
    accepting = {int(x) for x in m.group(1).split()} if m else set()
    rows, sig = {}, {}
    for sm in re.finditer(r"^State (\d+): ([01X]*) -> state (\d+)", output, re.M):
        src, pattern, dst = int(sm.group(1)), sm.group(2), int(sm.group(3))
        rows.setdefault(src, []).append((_pattern_pred(variables, pattern), dst))
        sig.setdefault(src, []).append((pattern, dst))
    initial = int(re.search(r"Initial state:[ \t]*(\d+)", output).group(1))
    targets = {t for _, t in rows.get(initial, ())}
    if len(targets) != 1:
        raise ValueError(f"MONA's initial state branches on the dummy letter: {targets}")
    return Auto(targets.pop(), accepting, rows, {k: tuple(v) for k, v in sig.items()}, "mona")
