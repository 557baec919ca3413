"""The plugin's own tests: symsynth's solver suite, in one line."""

from symsynth.testing import conformance

TestPlain = conformance("solver", "plain")
