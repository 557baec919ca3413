"""Read a finite-trace TLSF 1.1 specification (SYNTCOMP's `tlsf-fin`) as
an LTLf formula and a partition of its signals.

The grammar is `grammars/tlsf.lark`.  The GLOBAL section is evaluated as
syfco evaluates it (`Writer/Eval.hs`): parameters and definitions are
numbers, sets, signals, buses or formulas, functions are expanded where
they are called, big operators (`&&[0 <= i < N] f`) are unrolled over the
values their first condition binds, a bus `b[n]` is the signals `b_0` ...
`b_{n-1}` (syfco's default delimiter).  Under `Finite` semantics `X` is
weak next and `X[!]` strong next.  The sections are combined as syfco's
`merge` combines them (docs/synthesis.md):

    INITIALLY -> (PRESET && ((G REQUIRE && ASSUME) -> (G ASSERT && GUARANTEE)))

with each section the conjunction of its formulas and an empty one left
out.  `Mealy` means the environment moves first in each step, `Moore` the
system (the agent).  Errors name the file, line and column.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import lark

from symsynth.logic import ast
from symsynth.logic.lalr import lalr_parser
from symsynth.synthesis.partition import Partition
from symsynth.synthesis.tlsf_eval import (Bus, Evaluator, Function, Signal, TLSFError, Unevaluated, conjunction,
                                          implication, position)

#: Sections of MAIN holding formulas, under each of their two names.
_SECTION = {"INITIALLY": "initially", "PRESET": "preset", "REQUIRE": "require", "REQUIREMENTS": "require",
            "ASSUME": "assume", "ASSUMPTIONS": "assume", "ASSERT": "assert", "INVARIANTS": "assert",
            "GUARANTEE": "guarantee", "GUARANTEES": "guarantee"}


@dataclass(frozen=True)
class Spec:
    """A TLSF specification read as LTLf synthesis."""

    formula: ast.Formula
    partition: Partition
    agent_first: bool  # Moore: the system moves first; Mealy: the environment
    title: str
    parameters: dict[str, int]


@functools.cache
def _parser() -> lark.Lark:
    """The LALR parser.  Its tables take lark about 0.3 s to build (1 s on a
    loaded machine; TLSF has some twenty levels of binding), so they are kept
    between runs (`lalr.py`)."""
    return lalr_parser("tlsf.lark", lexer="basic", propagate_positions=True, maybe_placeholders=False)


def parse_tlsf(text: str, *, source: str = "<tlsf>", parameters: dict[str, int] | None = None) -> Spec:
    """The specification in `text`; `parameters` overrides values of the
    GLOBAL PARAMETERS (a name the file does not declare is an error)."""
    try:
        tree = _parser().parse(text)
    except lark.UnexpectedInput as error:
        raise _syntax_error(text, source, error) from None
    try:
        return _Reader(source, parameters or {}).read(tree)
    except RecursionError:
        raise TLSFError(f"{source}: the specification nests its expressions too deep for symsynth to read "
                        "(operators inside operators, thousands deep)") from None


def read_tlsf(path: Path, text: str, parameters: dict[str, int] | None = None) -> Spec:
    return parse_tlsf(text, source=str(path), parameters=parameters)


class _Reader(Evaluator):
    """A whole specification: INFO, GLOBAL and MAIN."""

    def __init__(self, source: str, overrides: dict[str, int]):
        super().__init__(source)
        self.overrides = dict(overrides)


    def read(self, tree: lark.Tree) -> Spec:
        info = next((c for c in tree.children if isinstance(c, lark.Tree) and c.data == "info"), None)
        title, agent_first = self.info(info)
        declared: dict[str, int] = {}
        for part in tree.children:
            if isinstance(part, lark.Tree) and part.data == "global_":
                declared.update(self.global_(part))
        unknown = sorted(set(self.overrides) - set(declared))
        if unknown:
            known = ", ".join(sorted(declared)) or "none"
            raise TLSFError(f"{self.source}: no parameter {', '.join(unknown)} in its GLOBAL PARAMETERS "
                            f"(it declares: {known})")
        main = tree.children[-1]
        inputs, outputs, sections = self.main(main)
        formula = _merge(sections)
        parameters = {name: self.number(self.lookup(name, {}, None), None) for name in declared}
        return Spec(formula, Partition(tuple(inputs), tuple(outputs)), agent_first, title, parameters)

    def info(self, info: lark.Tree | None) -> tuple[str, bool]:
        title, semantics = "", None
        for item in info.children if info is not None else ():
            key = item.children[0]
            assert isinstance(key, lark.Token)
            if key.type == "TITLE":
                title = str(item.children[1])[1:-1]
            elif key.type == "SEMANTICS":
                semantics = item
        if semantics is None:
            raise TLSFError(f"{self.source}: no 'SEMANTICS: Mealy,Finite' (or 'Moore,Finite') in its INFO "
                            "section: symsynth reads finite-trace TLSF")
        words = {str(w).lower() for w in semantics.children[1:]}
        if "finite" not in words or "strict" in words or len(words & {"mealy", "moore"}) != 1:
            found = ",".join(str(w) for w in semantics.children[1:])
            raise self.error(semantics, f"SEMANTICS: {found}: symsynth reads finite-trace TLSF; expected "
                                        "'Mealy,Finite' or 'Moore,Finite'")
        return title, "moore" in words

    def global_(self, tree: lark.Tree) -> dict[str, int]:
        declared = {}
        for block in tree.children:
            for binding in block.children:
                name = str(binding.children[0])
                if name in self.globals:
                    raise self.error(binding, f"'{name}' is defined twice")
                if binding.data == "function":
                    *params, bodies = _split_function(binding)
                    self.globals[name] = Function(tuple(params), bodies)
                else:
                    bodies = tuple(binding.children[1:])
                    if block.data == "parameters":
                        declared[name] = 0
                        if name in self.overrides:
                            self.globals[name] = self.overrides[name]
                            continue
                    self.globals[name] = Unevaluated(bodies)
        return declared

    def main(self, main: lark.Tree) -> tuple[list[str], list[str], dict[str, list[ast.Formula]]]:
        signals: dict[str, list[str]] = {"input": [], "output": []}
        sections: dict[str, list[ast.Formula]] = {k: [] for k in set(_SECTION.values())}
        seen: dict[str, lark.Tree] = {}
        for section in main.children:
            if section.data != "signals":
                continue
            kind = "input" if section.children[0] == "INPUTS" else "output"
            for signal in section.children[1:]:
                self.declare(signal, kind, signals[kind], seen)
        for section in main.children:
            if section.data == "formulas":
                key = _SECTION[str(section.children[0])]
                for expr in section.children[1:]:
                    sections[key].append(self.formula(self.eval(expr, {}), expr))
        return signals["input"], signals["output"], sections

    def declare(self, signal: lark.Tree, kind: str, names: list[str], seen: dict[str, lark.Tree]) -> None:
        name = str(signal.children[0])
        if name in self.globals:
            raise self.error(signal, f"signal '{name}' has the name of a GLOBAL definition")
        if signal.data == "single":
            value: Signal | Bus = Signal(name, kind)
            atoms = [name]
        else:
            size = self.number(self.eval(signal.children[1], {}), signal.children[1])
            if size < 0:
                raise self.error(signal, f"bus '{name}' has {size} signals; expected a size of 0 or more")
            value = Bus(name, size, kind)
            atoms = [value.signal(i) for i in range(size)]
        for atom in dict.fromkeys([name, *atoms]):
            if atom in seen:
                line, _ = position(seen[atom])
                raise self.error(signal, f"signal '{atom}' is declared twice (also at line {line}; a bus "
                                         f"b[n] names its signals b_0 ... b_(n-1))")
            seen[atom] = signal
        self.globals[name] = value
        names.extend(atoms)

    # evaluation


def _merge(sections: dict[str, list[ast.Formula]]) -> ast.Formula:
    """syfco's `merge` (Writer/Utils.hs): INITIALLY -> (PRESET && ((G
    REQUIRE && ASSUME) -> (G ASSERT && GUARANTEE)))."""
    def always(items):
        return [] if not items else [ast.Always(conjunction(items))]
    assumed = conjunction(always(sections["require"]) + sections["assume"])
    guaranteed = conjunction(always(sections["assert"]) + sections["guarantee"])
    body = conjunction(sections["preset"] + [implication(assumed, guaranteed)])
    return implication(conjunction(sections["initially"]), body)


def _split_function(binding: lark.Tree):
    children = binding.children[1:]
    params = [str(c) for c in children if isinstance(c, lark.Token)]
    bodies = tuple(c for c in children if isinstance(c, lark.Tree))
    return (*params, bodies)



_NAMES = {"NAME": "an identifier", "NUMBER": "a number", "SEMICOLON": "';'", "RBRACE": "'}'", "LBRACE": "'{'",
          "LPAR": "'('", "RPAR": "')'", "LSQB": "'['", "RSQB": "']'", "EQUAL": "'='", "COLON": "':'",
          "COMMA": "','", "STRING": "a string", "$END": "the end of the file"}


def _syntax_error(text: str, source: str, error: lark.UnexpectedInput) -> TLSFError:
    line, column = getattr(error, "line", 0), getattr(error, "column", 0)
    if isinstance(error, lark.UnexpectedCharacters):
        found = f"unexpected character {text[error.pos_in_stream or 0]!r}"
    else:
        token = getattr(error, "token", None)
        found = "unexpected end of the file" if token is None or token.type == "$END" else f"unexpected {str(token)!r}"
        if token is None or token.type == "$END":
            end = len(text.rstrip())
            line, column = text.count("\n", 0, end) + 1, end - text.rfind("\n", 0, end)
    terminals = set(getattr(error, "expected", ()) or ())
    expected = sorted({_NAMES.get(t, t if t.isalpha() else t.lower().replace("_", " ")) for t in terminals})
    if {"NAME", "NOT"} <= terminals:
        tail = "; expected a formula or an expression"
    elif len(expected) > 8 and "SEMICOLON" in terminals:
        tail = "; expected an operator, ';' or '}'"
    else:
        tail = f"; expected {', '.join(expected)}" if expected else ""
    lines = text.splitlines()
    shown = f"\n    {lines[line - 1]}\n    {' ' * (column - 1)}^" if 0 < line <= len(lines) else ""
    return TLSFError(f"{source}:{line}:{column}: syntax error: {found}{tail}{shown}")
