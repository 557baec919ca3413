"""LTLf to minimal DFA: explicit per-conjunct progression, symbolic product,
symbolic minimization.  The result is a `SymbolicDFA` over `dd` BDDs."""

from symsynth.automata.compiler import compile_ltlf
from symsynth.automata.explicit import ExplicitDFA
from symsynth.automata.symbolic import SymbolicDFA

#: How `compile_ltlf` numbers a DFA's states (the codes of its state bits).
#: Files that store DFA states (strategy files) record it; a reader refuses a
#: file whose numbering is not this one with that reason.  Bump it with any
#: change to the compiler that renumbers the states of some formula's DFA
#: (tests/test_dfa_numbering.py notices one).  1: per-conjunct progression;
#: 2: composition over the whole Boolean structure; 3: one-step invariants
#: built directly and explicit components encoded by a decision tree;
#: 4: deep until / release alternations by the backward construction.
NUMBERING = 4

__all__ = ["compile_ltlf", "ExplicitDFA", "NUMBERING", "SymbolicDFA"]
