"""How far the replanning bound V_0(start) + k D lies above E_p on the pattern
family (bench/results/game-notes.md, "The replanning bound measured"): D is the
largest rise of the no-human value V_0 over one human move, over every position
the k-game reaches (a superset of what the replanning strategy meets, so D is
at least the strategy's own).  Explores the whole game: 4 x 6 in seconds,
5 x 7 in about a minute.  `rises` is what bench/replan_repair.py checks its
bound D+ against.

    python bench/replan_bound.py N M K [SEED]
"""
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from symsynth.game.graph import GameGraph, Node  # noqa: E402
from symsynth.game.abstraction import initial_state  # noqa: E402
from symsynth.game.solution import task_formula  # noqa: E402
from symsynth.solvers.explicit import _dijkstra, START  # noqa: E402


def rises(scene, k):
    """(E_p, V_0(start), positions, moves): moves lists (v, move, V_0 before, V_0 after) for
    every human move at a human-turn position with a move left whose two k = 0 values the
    game holds (`missing` counts those it does not)."""
    game = GameGraph(scene, task_formula(scene, None), 1.0, symmetric=False)
    v0 = initial_state(scene)
    q0 = game.read(game.dfa.initial, v0)
    nodes, edges = game.explore(Node(v0, q0, k, False))
    value, _ = _dijkstra(nodes, edges)
    V = {(nd.v, nd.q, nd.h): value.get(i) for i, nd in enumerate(nodes) if nd is not None and nd.robot}
    moves, missing = [], 0
    for nd in nodes:
        if nd is None or nd.robot or nd.h == 0:
            continue
        base = V.get((nd.v, nd.q, 0))
        for a, succ, units, state in game.moves(nd):
            if succ is None or succ.h == nd.h:
                continue
            after = V.get((succ.v, succ.q, 0))
            if base is None or after is None:
                missing += 1
                continue
            moves.append((nd.v, a, base, after))
    V0start = V.get((v0, q0, 0))
    if V0start is None:  # the k = 0 value at the start, solved apart when the k-game did not reach it
        n0, e0 = game.explore(Node(v0, q0, 0, False))
        V0start = _dijkstra(n0, e0)[0].get(START)
    return value.get(START), V0start, len(nodes), moves, missing


def main():
    n, m, k = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
    scene = pattern_scene(n, m, k=k, seed=int(sys.argv[4]) if len(sys.argv) > 4 else 0)
    t = time.time()
    Ep, V0start, positions, moves, missing = rises(scene, k)
    print("positions", positions, "explore+solve", round(time.time() - t, 1), "s")
    D, worst = 0, None
    for v, a, base, after in moves:
        if after - base > D:
            D, worst = after - base, (v, a)
    print(f"E_p {Ep}  V_0(start) {V0start}  D {D} over {len(moves)} moves ({missing} without a value)")
    print(f"V_0 + k D = {V0start + k * D}  ratio to E_p {(V0start + k * D) / Ep:.3f}")
    print("worst move", worst[1] if worst else None)


if __name__ == "__main__":
    main()
