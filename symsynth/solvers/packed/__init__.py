"""The compiled solver's game in integers (`solvers.compiled` drives it).

- `tables`: the scene, costmap, task and symmetry as integer arrays, and a
  position packed into one 64-bit integer;
- `kernels`: the machine-code (numba) functions that generate the moves,
  explore batches of positions and solve them layer by layer;
- `explore`: the loop over layers and batches that drives the exploring
  kernels, and reports progress;
- `graph`: the explored and solved nodes read back, for strategies and plays;
- `search`, `lower`: the AND-OR search's kernels (`solvers.andor`) and the
  lower bound's tables they read;
- `replies`: the replanning bound's kernels (`solvers.replan_budget`): the
  human's replies on a plan, checked in bulk against budgets.

The kernels are one module because numba's disk cache is invalidated by the
source of the module a kernel lives in only: a kernel calling into another
module would keep its cached machine code after that module changed.
`search` and `replies` are the exceptions (they call the move kernels): they are compiled
together with them by `andor.prepare`, and carry their callees' SHA-256 in
`COMPILED_WITH`, so that a change to `kernels` must change them too
(tests/test_numba_cache.py).
"""
