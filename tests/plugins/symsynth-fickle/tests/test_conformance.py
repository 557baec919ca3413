"""The plugin's own tests: symsynth's human suite, in one line."""

from symsynth.testing import conformance

TestFickle = conformance("human", "fickle")
