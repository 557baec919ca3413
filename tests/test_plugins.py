"""The entry-point registries (`symsynth.plugins`): symsynth's planners,
primitives, solvers and humans are found through the same groups a
third-party plugin registers in (pyproject.toml), and an unknown name is
an error that lists the installed ones."""

from __future__ import annotations

import os
import sys
from importlib.metadata import entry_points

import pytest

from symsynth import plugins
from symsynth.errors import InputError
from symsynth.execution.human import HUMANS, HumanContext, human_needs
from symsynth.solvers.explicit import solve_explicit
from symsynth.solvers import SOLVERS
from symsynth.planning.registry import planner_names


#: symsynth's own plugins; an installed third-party one comes on top of them.
BUILT_IN_SOLVERS = ("auto", "compiled", "explicit", "forward", "symbolic")
BUILT_IN_HUMANS = ("none", "random", "adversarial")


def test_the_built_ins_are_registered_by_entry_point():
    assert {n: plugins.found("symsynth.solvers")[n].value for n in BUILT_IN_SOLVERS} == {
        "explicit": "symsynth.solvers.explicit:solve_explicit", "forward": "symsynth.solvers.forward:solve_forward",
        "symbolic": "symsynth.solvers.symbolic:solve_symbolic", "auto": "symsynth.solvers.auto:solve_auto",
        "compiled": "symsynth.solvers.compiled:solve_compiled"}
    assert SOLVERS["explicit"] is solve_explicit
    assert set(HUMANS) >= set(BUILT_IN_HUMANS)
    assert set(planner_names()) >= {"ompl-fcl", "pybullet"}
    assert set(plugins.found("symsynth.primitives")) >= {"grab", "drop", "push", "pull"}


def test_a_registry_is_a_mapping_and_names_what_is_installed():
    installed = sorted(ep.name for ep in entry_points(group="symsynth.solvers"))
    assert set(installed) >= set(BUILT_IN_SOLVERS)
    assert "symbolic" in SOLVERS and "simplex" not in SOLVERS and len(SOLVERS) == len(installed)
    assert list(SOLVERS) == installed
    with pytest.raises(KeyError):
        SOLVERS["simplex"]
    with pytest.raises(InputError) as error:
        SOLVERS.get_or_fail("simplex")
    assert str(error.value) == f"unknown solver 'simplex'; installed solvers: {', '.join(installed)}"


def test_registered_humans_are_made_from_a_context():
    context = HumanContext(seed=3, probability=1.0, budget=lambda position: None)
    humans = {name: HUMANS[name](context) for name in BUILT_IN_HUMANS}
    assert {name: human.name for name, human in humans.items()} == {
        "none": "none", "random": "random", "adversarial": "adversarial"}


def _distribution(folder, name, group, entry):
    info = folder / f"{name}-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(f"[{group}]\n{entry}\n")


def test_lookups_see_a_folder_put_on_the_path_and_a_package_installed_into_it(tmp_path, monkeypatch):
    """Lookups are kept (a scan of the installed packages per lookup cost
    the suite seconds), but not past a change: a folder new on sys.path,
    then a second package written into that folder (its modification time
    moves on; set forward here so the test does not hang on the clock's
    grain)."""
    group = "symsynth.test-only"
    assert plugins.found(group) == {}
    _distribution(tmp_path, "first_plugin", group, "one = json:dumps")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert {n: ep.value for n, ep in plugins.found(group).items()} == {"one": "json:dumps"}
    before = tmp_path.stat().st_mtime_ns
    _distribution(tmp_path, "second_plugin", group, "two = json:loads")
    os.utime(tmp_path, ns=(before + 10**9, before + 10**9))
    assert {n: ep.value for n, ep in plugins.found(group).items()} == {"one": "json:dumps", "two": "json:loads"}
    found = plugins.found(group)
    found.clear()  # a caller's copy: the kept lookup is not changed through it
    assert set(plugins.found(group)) == {"one", "two"}


def test_a_human_declares_what_it_needs_of_a_run():
    """Budgets are computed for a human that says it needs them (its
    factory's `needs`), not for one named adversarial."""
    assert human_needs("adversarial") == {"budgets"}
    assert human_needs("none") == human_needs("random") == frozenset()


@pytest.mark.parametrize("needs, message", [
    ("{'minds'}", "human plugin 'telepath' needs minds, which symsynth does not provide; known needs: budgets"),
    ("'budgets'", "human plugin 'telepath': 'needs' must be a set of names from budgets, found 'budgets'"),
])
def test_a_need_symsynth_does_not_know_is_the_plugins_error(tmp_path, monkeypatch, needs, message):
    (tmp_path / "telepath.py").write_text(f"def make(context):\n    return None\nmake.needs = {needs}\n")
    _distribution(tmp_path, "telepath", "symsynth.humans", "telepath = telepath:make")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "telepath", raising=False)  # this case's module, not the last one's
    with pytest.raises(InputError) as error:
        human_needs("telepath")
    assert str(error.value) == message
