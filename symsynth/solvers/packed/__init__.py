"""The compiled solver's game in integers (`solvers.compiled` drives it).

- `tables`: the scene, costmap, task and symmetry as integer arrays, and a
  position packed into one 64-bit integer;
- `kernels`: the machine-code (numba) functions that generate the moves,
  explore batches of positions and solve them layer by layer;
- `explore`: the loop over layers and batches that drives the exploring
  kernels, and reports progress;
- `graph`: the explored and solved nodes read back, for strategies and plays;
- `search`, `lower`: the AND-OR search's kernels (`solvers.andor`) and the
  lower bound's tables they read.

The kernels are one module because numba's disk cache is invalidated by the
source of the module a kernel lives in only: a kernel calling into another
module would keep its cached machine code after that module changed.
`search` is the exception (it calls the move kernels): it is compiled
together with them by `andor.prepare`, and carries `kernels`' SHA-256 in
`COMPILED_WITH`, so that a change to `kernels` must change `search` too
(tests/test_numba_cache.py).
"""
