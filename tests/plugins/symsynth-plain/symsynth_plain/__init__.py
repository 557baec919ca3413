"""`plain`: symsynth's explicit solver on every position of the game, with
no symmetry reduction (slower on scenes with interchangeable objects; the
same E_p)."""

from symsynth.solvers.explicit import solve_explicit


def solve_plain(scene, formula=None, *, k=None, budget=None, resolution=1.0):
    return solve_explicit(scene, formula, k=k, budget=budget, resolution=resolution, symmetric=False)
