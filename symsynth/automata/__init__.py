"""LTLf to minimal DFA: explicit per-conjunct progression, symbolic product,
symbolic minimization.  The result is a `SymbolicDFA` over `dd` BDDs."""

from symsynth.automata.compile import compile_ltlf
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.symbolic import SymbolicDFA

__all__ = ["compile_ltlf", "ExplicitDFA", "SymbolicDFA"]
