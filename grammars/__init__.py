"""Grammar files (`*.lark`), shipped inside the wheel as `symsynth.grammars`."""
