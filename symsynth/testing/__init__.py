"""The conformance suites of symsynth's plugins, installed with symsynth so
that a plugin's own repository can run them (they need pytest).

One line in a test file of the plugin's repository runs a suite, once per
plugin name given (pytest parametrized over the registered names)::

    from symsynth.testing import conformance

    TestMySolver = conformance("solver", "my-solver")

The kinds (docs/plugins.md):

- `planner` (`testing.planner`): inverse kinematics, contacts and roadmaps
  on small Panda scenes whose facts are re-derived without the planner;
- `primitive` (`testing.primitive`): a prehensile primitive grabs and drops
  a block; a displacement primitive's slides on the scene file it is meant
  for, given as `scene=` with the contact `contact=` (and optionally
  `slides=`, the (from, to) pairs expected, and `planners=`);
- `solver` (`testing.solver`): hand-solved games and the properties of a
  solution on generated ones (`testing.gamegen`);
- `human` (`testing.human`): a simulated human answers the turns of a game
  with what is offered, the same way for the same seed;
- `human-model` (`testing.human_model`): a human model of semantics §9
  gives exact, complete distributions; its "name" is the model as a scene
  writes it (`random(0.3)`).

symsynth's own tests run the built-ins and the example plugins of
`tests/plugins/` through exactly these lines.
"""

from __future__ import annotations

import importlib
from typing import Any

import pytest

#: kind -> the module and class of its suite.
SUITES = {"planner": ("symsynth.testing.planner", "PlannerConformance"),
          "primitive": ("symsynth.testing.primitive", "PrimitiveConformance"),
          "solver": ("symsynth.testing.solver", "SolverConformance"),
          "human": ("symsynth.testing.human", "HumanConformance"),
          "human-model": ("symsynth.testing.human_model", "HumanModelConformance")}


def conformance(kind: str, *names: str, **options: Any) -> type:
    """The suite of `kind` as a test class whose tests run once per plugin
    in `names` (registered names; ids are the names), with the suite's
    `options` (`OPTIONS` of its class) set.  Assign it to a module-level
    name starting with `Test` so pytest collects it."""
    if kind not in SUITES:
        raise ValueError(f"unknown kind of plugin {kind!r}; expected one of {', '.join(SUITES)}")
    if not names:
        raise ValueError(f"conformance({kind!r}): name at least one plugin")
    module, name = SUITES[kind]
    suite = getattr(importlib.import_module(module), name)
    unknown = set(options) - set(suite.OPTIONS)
    if unknown:
        raise ValueError(f"the {kind} suite has no option {', '.join(sorted(unknown))}; "
                         f"its options: {', '.join(suite.OPTIONS) or 'none'}")

    @pytest.fixture(params=names, ids=list(names))
    def plugin_name(self, request: Any) -> str:
        return request.param

    title = "".join(part.capitalize() for part in f"{kind} {' '.join(names)}".replace("-", " ").split())
    return type(f"Test{title}", (suite,), {"plugin_name": plugin_name, **options})


class Conformance:
    """The base of every suite: `self.name` is the plugin under test."""

    #: The options `conformance` accepts for this suite (class attributes).
    OPTIONS: tuple[str, ...] = ()
    name: str

    @pytest.fixture(autouse=True)
    def _plugin_under_test(self, plugin_name: str) -> None:
        self.name = plugin_name
