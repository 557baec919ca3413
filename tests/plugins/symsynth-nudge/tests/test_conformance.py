"""The plugin's own tests: symsynth's primitive suite, in one line."""

from pathlib import Path

from symsynth.testing import conformance

TestNudge = conformance("primitive", "nudge", scene=Path(__file__).parent / "nudge-small.yaml", contact="behind",
                        slides={("l1", "l3")}, physical=False)
# physical=False: nudge slides sideways from a contact behind the box, which
# only the kinematic world can do (in the physical one the hand passes
# beside the box: 0 of 10 trials); a kinematic example of the plugin door.
