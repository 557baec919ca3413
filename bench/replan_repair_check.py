"""Checks bench/replan_repair.py's D+ against measured rises of V_0 over one human move,
case by case (bench/results/game-notes.md, "A repair bound D+ from the costmap").

    python bench/replan_repair_check.py exact N M [SEED]
        every human move of the k = 3 game (bench/replan_bound.rises, the explicit solver):
        per case, the largest rise against the case's bound
    python bench/replan_repair_check.py sample N M SEED WALKS
        WALKS random plays of the k = 3 game from the start (robot and human moves drawn
        uniformly, the human moving with probability 1/2); at every human turn with a move
        left, every human move: V_0 before and after by the AND-OR search with k = 0 from
        that state (exact: it proves lower = upper), then the same per-case table
    python bench/replan_repair_check.py random N M SEED COUNT
        COUNT well-formed states drawn at random (`random_state`), every human move from each,
        V_0 as for `sample`
    python bench/replan_repair_check.py swap N M [SEED]
        the C4d-swap positions of `swaps`, built to be bad, and their rises
    python bench/replan_repair_check.py spare N M SEED COUNT
        symsynth/solvers/rise.py's bounds: COUNT random states with a spare place available,
        every human move from each; per class of `rise.move_class` the largest rise (over
        V_0^Z before for C5's classes, over V_0 before for the others) against its bound
    python bench/replan_repair_check.py oracle N M [SEED]
        the k = 0 AND-OR values against the explicit solver's on every move `exact` sees
"""

from __future__ import annotations

import random
import sys
import time
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from gamefamily import pattern_scene  # noqa: E402
from replan_bound import rises  # noqa: E402
from replan_repair import SOUND, d_plus  # noqa: E402
from symsynth.game.abstraction import (State, human_moves, initial_state, legal_human_moves,  # noqa: E402
                                       robot_moves)
from symsynth.scene.model import ELSE, HAND  # noqa: E402

# which of replan_repair's cases cover a move, by where o was, where it went and the hand
COVER = {
    ("L", "Else", "aimed at o"): ("C1",),
    ("Else", "Else", "aimed at o"): ("C3",),
    ("L", "L", "Else"): ("C4a",), ("L", "L", "aimed at o"): ("C4a",),
    ("L", "L", "aimed at other"): ("C4b", "C4d", "C4d swap"),
    ("L", "L", "holding at L"): ("C4c",),
    ("L", "L", "holding at Else"): ("C4d", "C4d swap"),
}


def case(scene, v, action) -> tuple[str, str, str]:
    o, t = action[len("move("):-1].split(",")
    x = v.at[scene.object_names.index(o)]
    if v.held() is not None:
        hand = "holding at Else" if v.ee == ELSE else "holding at L"
    elif v.ee == ELSE:
        hand = "Else"
    else:
        hand = "aimed at o" if v.ee[0] == o else "aimed at other"
    return ("Else" if x == ELSE else "L", "Else" if t == ELSE else "L", hand)


def cover(key) -> tuple[str, ...]:
    if key in COVER:
        return COVER[key]
    if key[:2] == ("L", "Else"):
        return ("C2",)
    if key[:2] == ("Else", "Else"):
        return ()  # nothing changes: the rise is 0
    return ("C5 (conditional)",)


def table(scene, moves) -> bool:
    """Print the per-case comparison; whether every rise is within its case's bound."""
    bound, found = d_plus(scene)
    worst = defaultdict(lambda: (None, None))
    for v, a, base, after in moves:
        key = case(scene, v, a)
        if worst[key][0] is None or after - base > worst[key][0]:
            worst[key] = (after - base, (v, a, base, after))
    ok = True
    print(f"D+ = {bound}; largest rise measured {max((w[0] for w in worst.values()), default=None)}")
    for key in sorted(worst):
        rise, where = worst[key]
        names = cover(key)
        limit = max((found[c][0] for c in names), default=0)
        sound = all(c in SOUND for c in names)
        ok = ok and (rise <= limit if sound else True)
        flag = "" if rise <= limit else ("  ABOVE (conditional case)" if not sound else "  ABOVE")
        print(f"  o from {key[0]:4} to {key[1]:4} hand {key[2]:15} rise {rise:4}  bound {limit:4} "
              f"({'/'.join(names) or '-'}){flag}")
    return ok


class Oracle:
    """V_0 of any state: the AND-OR search with k = 0 from it, one memo for all questions."""

    def __init__(self, scene):
        from symsynth.game.solution import task_formula
        from symsynth.solvers import andor
        from symsynth.solvers.packed.lower import BoundTables
        from symsynth.solvers.packed.tables import Tables

        andor.prepare()
        formula = task_formula(scene, None)
        self.andor = andor
        self.tables = Tables(scene, formula, 1.0, None, 0)
        self.memo = andor.Memo(self.tables, BoundTables(self.tables, formula), 0)

    def __call__(self, v) -> int | None:
        tb = self.tables
        x = tb.pack(v)
        q = tb.step(tb.dfa_index[tb.dfa.initial], x)
        if tb.accepting[q]:
            return 0
        lower, upper, _ = self.andor._search(self.memo, self.memo.node(self.memo.key2(tb.canon(x), q, 0)), None)
        if lower is not None:
            raise RuntimeError(f"the k = 0 search did not prove V_0 of {v}")
        return upper


def sampled(scene, seed: int, walks: int, k: int = 3, steps: int = 30):
    """(v, move, V_0 before, V_0 after) for every human move at the human turns of random
    plays (at most `steps` robot moves each, ended by the win or the human's last move)."""
    rng, oracle, out = random.Random(seed), Oracle(scene), []
    for _ in range(walks):
        v, h = initial_state(scene), k
        for _ in range(steps):
            base = oracle(v)
            if base == 0:
                break
            replies = human_moves(scene, v)
            out += [(v, a, base, oracle(w)) for a, w in replies]
            if replies and rng.random() < 0.5:
                v, h = rng.choice(replies)[1], h - 1
                if h == 0:
                    break
            v = rng.choice(robot_moves(scene, v))[1]
    return out


def random_state(scene, rng):
    """A well-formed state drawn at random: each object at Else (probability 1/4), in the
    hand (one at most, probability 1/4 for a state) or at a free location; the hand aimed
    at a random object or at Else, or, holding, aligned with a free location or at Else."""
    names, places = scene.object_names, list(scene.locations)
    rng.shuffle(places)
    at = [ELSE if rng.random() < 0.25 else places.pop() for _ in names]
    if rng.random() < 0.25:
        i = rng.randrange(len(names))
        if at[i] != ELSE:
            places.append(at[i])
        at[i] = HAND
        ee = ELSE if rng.random() < 0.5 else rng.choice(places)
        return State(tuple(at), scene.grasps[0], ee)
    aims = [ELSE] + [(o, g) for o in names for g in scene.preimages]
    return State(tuple(at), None, rng.choice(aims))


def drawn(scene, seed: int, count: int):
    """(v, move, V_0 before, V_0 after) for every human move from `count` random states."""
    rng, oracle, out = random.Random(seed), Oracle(scene), []
    for _ in range(count):
        v = random_state(scene, rng)
        base = oracle(v)
        if base == 0:
            continue
        out += [(v, a, base, oracle(w)) for a, w in human_moves(scene, v)]
    return out


def goals(scene) -> dict[str, str]:
    """Each object's goal in the pattern task F(at(c1, l1) & ...)."""
    import re

    from symsynth.game.solution import task_formula

    pairs = re.findall(r"args=\('(\w+)', '(\w+)'\)", repr(task_formula(scene, None)))
    return {o: l for o, spec in zip(scene.object_names, scene.objects) for tag, l in pairs if tag in spec.tags}


def swaps(scene):
    """C4d-swap positions built to be bad: for every pair (o, o_h), o on its goal x, o_h held
    at Else with its goal t, the other objects on the n - 2 places where the swap plan costs
    most (replan_repair's worst set for (x, t)); the human moves o onto t.  Yields (rise,
    the swap plan's bound there, o, o_h, x, t)."""
    import itertools

    from replan_repair import Tables, swap_worst

    tb, oracle, goal, g = Tables(scene), Oracle(scene), goals(scene), scene.grasps[0]
    names = scene.object_names
    for o, oh in itertools.permutations(names, 2):
        x, t = goal[o], goal[oh]
        bound, (spots, _) = swap_worst(tb, f"{o}/{g}", f"{oh}/{g}", g, g, x, t)
        spots, at = list(spots), {o: x, oh: HAND}
        for p in names:  # the others: on their goals where those are among the spots
            if p not in at and goal[p] in spots:
                at[p] = goal[p]
                spots.remove(goal[p])
        for p in names:
            at.setdefault(p, spots.pop() if spots else ELSE)
        v = State(tuple(at[p] for p in names), g, ELSE)
        w = State(tuple(t if p == o else at[p] for p in names), g, ELSE)
        yield oracle(w) - oracle(v), bound, o, oh, x, t


def spare_rises(scene, seed: int, count: int) -> bool:
    """Print, per class of `rise.move_class`, the largest rise at `count` random states with a
    spare place available against the class's bound; whether every rise is within it."""
    from symsynth.game.solution import task_formula
    from symsynth.solvers.rise import C5_CLASSES, available_spares, move_class, rise_bounds, without_drops_at

    rises = rise_bounds(scene, task_formula(scene, None))
    rng, oracle, spared = random.Random(seed), Oracle(scene), Oracle(without_drops_at(scene, rises.spares))
    worst: dict = {}
    drawn = 0
    while drawn < count:
        v = random_state(scene, rng)
        base = oracle(v)
        if base == 0 or not available_spares(rises, v):
            continue
        drawn += 1
        base_z = spared(v)
        for move in legal_human_moves(scene, v):
            name = move_class(scene, rises.spares, v, move)
            if name is not None:
                rise = oracle(move.after) - (base_z if name in C5_CLASSES else base)
                worst[name] = max(worst.get(name, rise), rise)
    print(f"spare places {rises.spares}: D+ {rises.other}, C5^Z {rises.c5}")
    for name, bound in rises.classes:
        rise = worst.get(name)
        print(f"  {name:36} rise {rise!s:5} bound {bound:4}{'  ABOVE' if rise is not None and rise > bound else ''}")
    return all(rise <= rises.of(name) for name, rise in worst.items())


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    mode, n, m = argv[0], int(argv[1]), int(argv[2])
    seed = int(argv[3]) if len(argv) > 3 else 0
    scene = pattern_scene(n, m, 3, seed)
    clock = time.time()
    if mode == "exact":
        Ep, V0, positions, moves, missing = rises(scene, 3)
        print(f"{n} x {m} seed {seed}: E_p {Ep}, V_0(start) {V0}, {len(moves)} moves ({missing} without a value)")
        ok = table(scene, moves)
    elif mode == "random":
        moves = drawn(scene, seed, int(argv[4]))
        print(f"{n} x {m} seed {seed}: {len(moves)} moves at {len({mv[0] for mv in moves})} random states")
        ok = table(scene, moves)
    elif mode == "swap":
        found = sorted(swaps(scene), reverse=True)
        for row in found[:5]:
            print("rise {} (swap bound there {}): {} on its goal {}, holding {} whose goal is {}".format(
                row[0], row[1], row[2], row[4], row[3], row[5]))
        ok = all(rise <= d_plus(scene)[0] for rise, *_ in found)
    elif mode == "spare":
        ok = spare_rises(scene, seed, int(argv[4]))
    elif mode == "sample":
        moves = sampled(scene, seed, int(argv[4]))
        print(f"{n} x {m} seed {seed}: {len(moves)} moves at {len({mv[0] for mv in moves})} positions")
        ok = table(scene, moves)
    else:
        _, _, _, moves, _ = rises(scene, 3)
        oracle = Oracle(scene)
        wrong = [mv for mv in moves if oracle(mv[0]) != mv[2]]
        print(f"{len(moves)} moves, {len(wrong)} with a base value the AND-OR search does not repeat")
        ok = not wrong
    print(f"{time.time() - clock:.1f} s, {'within' if ok else 'NOT within'} the sound cases' bounds")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
