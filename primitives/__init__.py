"""symsynth's built-in motion primitives, registered through the entry-point
group `symsynth.primitives` like any third-party plugin (pyproject.toml):
`grab` and `drop` (prehensile), `push` and `pull` (displacement)."""
