"""LTLf: the abstract syntax, its parser and printer, and its reference semantics."""

from symsynth.logic.ast import Formula, atoms
from symsynth.logic.parser import parse_ltlf
from symsynth.logic.printer import to_string
from symsynth.logic.semantics import holds

__all__ = ["Formula", "atoms", "parse_ltlf", "to_string", "holds"]
