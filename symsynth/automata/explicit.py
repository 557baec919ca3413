"""The explicit form of a DFA: integer states, guard formulas as text.

This is what `symsynth dfa --json` prints and `--dot` draws; tools outside
symsynth can read it without BDDs.  Guards are propositional formulas over
the atoms in the LTLf syntax (`!`, `&`, `|`, `true`, `false`, parentheses).
"""

from __future__ import annotations

import functools
import json
from collections.abc import Collection, Iterable
from dataclasses import dataclass

from symsynth.logic import ast
from symsynth.logic.parser import parse_ltlf
from symsynth.logic.semantics import holds

JSON_FORMAT = "symsynth.dfa/1"


@dataclass(frozen=True)
class ExplicitDFA:
    """A complete DFA; `transitions` are `(source, guard, target)` triples.

    The guards leaving one state are disjoint and cover every letter.  The
    initial state is never accepting (traces are non-empty).
    """

    atoms: tuple[str, ...]
    initial: int
    accepting: frozenset[int]
    transitions: tuple[tuple[int, str, int], ...]
    num_states: int

    @functools.cached_property
    def _parsed(self) -> dict[int, list[tuple[ast.Formula, int]]]:
        out: dict[int, list[tuple[ast.Formula, int]]] = {s: [] for s in range(self.num_states)}
        for source, guard, target in self.transitions:
            out[source].append((parse_ltlf(guard, source="<guard>"), target))
        return out

    def step(self, state: int, letter: Collection[str]) -> int:
        """The successor of `state` on `letter` (the set of atoms that hold)."""
        for guard, target in self._parsed[state]:
            if holds(guard, [letter]):
                return target
        raise ValueError(f"state {state} has no transition on {sorted(letter)}: DFA incomplete")

    def accepts(self, trace: Iterable[Collection[str]]) -> bool:
        state, empty = self.initial, True
        for letter in trace:
            state, empty = self.step(state, letter), False
        return not empty and state in self.accepting

    def to_json(self) -> dict:
        return {
            "format": JSON_FORMAT,
            "atoms": list(self.atoms),
            "initial": self.initial,
            "accepting": sorted(self.accepting),
            "transitions": [{"from": s, "to": t, "guard": g} for s, g, t in self.transitions],
        }

    def dumps(self) -> str:
        return json.dumps(self.to_json(), indent=2)

    def to_dot(self, title: str = "") -> str:
        """Graphviz text: accepting states doubly circled, one edge per guard."""
        lines = ["digraph dfa {", "  rankdir=LR;", '  node [shape=circle, fontname="Helvetica"];',
                 '  edge [fontname="Helvetica", fontsize=10];']
        if title:
            lines.append(f'  label={json.dumps(title)}; labelloc=t;')
        lines.append('  init [shape=point, label=""];')
        for s in range(self.num_states):
            shape = "doublecircle" if s in self.accepting else "circle"
            lines.append(f"  {s} [shape={shape}];")
        lines.append(f"  init -> {self.initial};")
        for s, guard, t in self.transitions:
            lines.append(f"  {s} -> {t} [label={json.dumps(guard)}];")
        lines.append("}")
        return "\n".join(lines) + "\n"
