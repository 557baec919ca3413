"""The plugin's own tests: symsynth's primitive suite, in one line."""

from pathlib import Path

from symsynth.testing import conformance

TestNudge = conformance("primitive", "nudge", scene=Path(__file__).parent / "nudge-small.yaml", contact="behind",
                        slides={("l1", "l3")})
