"""numba's disk cache keys a kernel on the source of its own module only.
A kernel that calls a kernel of another module has that callee compiled into
its cached machine code, which then outlives a change to the callee's module.
So every such caller module names the callee modules' SHA-256 in
`COMPILED_WITH`: a change to a callee fails this test until the caller is
edited, and the edit invalidates the caller's cache."""

from __future__ import annotations

import ast
import hashlib
import importlib
from pathlib import Path

import symsynth

PACKAGE = Path(symsynth.__file__).parent


def kernel_modules() -> dict[str, Path]:
    """Module name -> file, for every module that defines a numba kernel."""
    found = {}
    for path in PACKAGE.rglob("*.py"):
        if "@njit" in path.read_text():
            found[".".join(("symsynth", *path.relative_to(PACKAGE).with_suffix("").parts))] = path
    return found


def callees(path: Path, kernels: dict[str, Path]) -> set[str]:
    """The other kernel modules `path` imports names from."""
    tree = ast.parse(path.read_text())
    return {node.module for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and node.module in kernels and kernels[node.module] != path}


def test_kernel_modules_that_call_into_others_carry_their_hashes():
    kernels = kernel_modules()
    assert "symsynth.solvers.packed.kernels" in kernels and "symsynth.solvers.packed.search" in kernels
    checked = 0
    for name, path in sorted(kernels.items()):
        wanted = callees(path, kernels)
        if not wanted:
            continue
        stamps = getattr(importlib.import_module(name), "COMPILED_WITH", None)
        assert stamps is not None, f"{name} calls kernels of {sorted(wanted)} and has no COMPILED_WITH"
        for callee in wanted:
            file = kernels[callee]
            digest = hashlib.sha256(file.read_bytes()).hexdigest()[:16]
            assert stamps.get(file.name) == digest, (
                f"{file.name} changed: set COMPILED_WITH[{file.name!r}] = {digest!r} in {path.name}, "
                "so that numba compiles its kernels again")
            checked += 1
    assert checked >= 2  # search -> packed kernels, steps -> objectives kernels
