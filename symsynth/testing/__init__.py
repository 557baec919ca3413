"""Conformance suites a plugin's authors run against their plugin (pytest
test classes to subclass, installed with symsynth so a third party can
import them)."""
