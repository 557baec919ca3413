"""LTLf synthesis on standard inputs (`symsynth synth`): a formula, a
partition of its variables between environment and agent, and a symbolic
reachability game on the formula's minimal DFA."""

from symsynth.synthesis.game import Realizability, solve_realizability
from symsynth.synthesis.partition import Partition, read_partition

__all__ = ["Partition", "Realizability", "read_partition", "solve_realizability"]
