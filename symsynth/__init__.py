"""symsynth: symbolic reactive synthesis for robot manipulation.

The package is layered the way the problem is:

- `symsynth.logic`    LTLf syntax, parser, printer and reference semantics;
- `symsynth.automata` LTLf -> minimal symbolic DFA over BDDs (`dd.cudd`);
- `symsynth.cli`      the `symsynth` command.
"""

__version__ = "0.1.0"
