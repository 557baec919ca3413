"""The compiled solver's game in integers (`solvers.compiled` drives it).

- `tables`: the scene, costmap, task and symmetry as integer arrays, and a
  position packed into one 64-bit integer;
- `kernels`: the machine-code (numba) functions that generate the moves,
  explore the positions layer by layer and solve them;
- `graph`: the explored and solved nodes read back, for strategies and plays.

The kernels are one module because numba's disk cache is invalidated by the
source of the module a kernel lives in only: a kernel calling into another
module would keep its cached machine code after that module changed.
"""
