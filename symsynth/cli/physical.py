"""The physical side of `symsynth costmap`: `verify --physics` (every
transfer and slide rule tried in the physical world, `execution.rule_trials`)
and `--min-success` (a costmap without the rules that fail there)."""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Mapping
from typing import Any

from symsynth.cli import options
from symsynth.cli.progress import bar
from symsynth.errors import InputError
from symsynth.execution.observe import place_at
from symsynth.execution.rule_trials import Rate, Subject, rates, state_placement, subjects
from symsynth.game.abstraction import costmap_of, initial_state, legal_robot_moves, motion_rule, slide_rule
from symsynth.planning.protocol import Planner
from symsynth.scene.costmap import Costmap
from symsynth.scene.model import ELSE, Scene, geometry_of

#: The worst subjects named under the table.
WORST = 5
#: Randomization of `--min-success` and `verify --physics` when none is given.
DEFAULT_RANDOMIZE = "friction=0.2,mass=0.2,pose=0.005"
#: The success rate below which `verify --physics` exits with status 1.
VERIFY_MINIMUM = 0.9


def add_options(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("in the physical world (docs/costmaps.md)")
    group.add_argument("--physics", action="store_true",
                       help="with verify: try every transfer and slide rule's evidence in the physical world "
                            "(--trials times, randomized) and print each rule's success rate")
    group.add_argument("--trials", type=options.at_least_one, metavar="N",
                       help="physical trials per rule, seeds S..S+N-1 (default 10)")
    group.add_argument("--trial-seed", type=options.count, metavar="S", default=0,
                       help="the first physical trial's seed (default 0); --costmap-seed is the roadmaps'")
    group.add_argument("--randomize", type=options.randomization, metavar="friction=R,mass=R,pose=M",
                       help=f"the trials' worlds drawn by their seeds (default {DEFAULT_RANDOMIZE}; "
                            "friction=0 for none)")
    group.add_argument("--play", action="store_true",
                       help="with verify --physics: only the rules the principal play uses, each tried from "
                            "the play's state (the other objects where the play has them)")
    group.add_argument("--min-success", type=options.fraction("a success rate"), metavar="P",
                       help="leave out of the costmap the transfer and slide rules that succeed less often "
                            "than P in --trials physical trials")


def _randomization(args: argparse.Namespace):
    """--randomize, or the default the help names."""
    return options.randomization(DEFAULT_RANDOMIZE) if args.randomize is None else args.randomize


def check(args: argparse.Namespace, verify: bool) -> None:
    """Options that belong together, before anything is computed."""
    if not verify and args.physics:
        raise InputError("--physics: only with costmap verify FILE --scene SCENE (to leave out of a costmap the "
                         "rules that fail in the world as it is built: --min-success P)")
    if not verify and args.play:
        raise InputError("--play: only with costmap verify --physics")
    if args.physics if verify else args.min_success is not None:
        return
    used = [o for o, v in (("--trials", args.trials), ("--randomize", args.randomize),
                           ("--play", args.play or None), ("--min-success", args.min_success)) if v is not None]
    if used:
        raise InputError(f"{', '.join(used)}: only with "
                         + ("costmap verify --physics" if verify else "--min-success P (or costmap verify --physics)"))


def play_subjects(scene: Scene, steps: Any) -> Chosen:
    """The transfer and slide rules a play's robot steps use, each with the
    placement of the state it starts from."""
    costmap = costmap_of(scene)
    every = {(s.kind, s.key, s.index, s.obj): s for s in subjects(scene, costmap)}
    found: Chosen = []
    v = initial_state(scene)
    # the held object: the place it was grabbed at, the paths followed since, the place it is over
    carried: tuple[str, tuple, str] | None = None
    for step in steps:
        if step.who == "robot":
            move = next((m for m in legal_robot_moves(scene, v) if m.action == step.action), None)
            if move is not None and move.kind == "grab":
                rest = _resting_place(scene, move.obj, move.location)
                carried = None if rest is None else (rest, (), rest)
            if move is not None and move.kind in ("transfer", "slide"):
                used = _used(scene, costmap, v, move, every)
                if move.kind == "transfer" and carried is not None:
                    rest, lead, here = carried
                    on = [s for s in used if s.start == here]
                    if lead:  # carried on from an earlier transfer: tried from the grab
                        used = [dataclasses.replace(s, rest=rest, lead=lead) if s.start == here else s
                                for s in used]
                    carried = (rest, lead + (on[0].rule.path or ()), on[0].goal) if on else None
                for subject in used:
                    if all(subject != s for s, _ in found):
                        found.append((subject, state_placement(scene, v)))
        v = step.state
    return found


def _resting_place(scene: Scene, obj: str, location: str) -> str | None:
    """The place where a grab takes `obj` standing at `location`: the
    location, or, at Else, the Else sample its scene pose lies on (None
    when that is none)."""
    if location != ELSE:
        return location
    pose = geometry_of(scene).initial.get(obj)
    return None if pose is None else place_at(scene, pose)


def _used(scene: Scene, costmap: Costmap, v: Any, move: Any, every: Mapping) -> list[Subject]:
    if move.kind == "slide":
        rule = slide_rule(scene, v, move)
        key = (move.grasp, v.at[move.serves], move.location)
        rules = costmap.slide_rules(*key)
        return [every[("slide", key, rules.index(rule), move.obj)]] if rule in rules else []
    used = []
    for s in move.starts:
        for t in move.goals:
            rule = motion_rule(scene, v, move, s, t)
            rules = costmap.rules(move.mode, s, t)
            if rule is not None and rule in rules and ("transfer", (move.mode, s, t), rules.index(rule),
                                                       move.obj) in every:
                used.append(every[("transfer", (move.mode, s, t), rules.index(rule), move.obj)])
    return used


Chosen = list[tuple[Subject, Mapping[str, str] | None]]  # each with the other objects' places (None: the scene's)


def tried(scene: Scene, planner: Planner, chosen: Chosen,
          args: argparse.Namespace) -> list[Rate]:
    """Every chosen subject tried `args.trials` times (progress bar)."""
    trials = args.trials or 10
    randomization = _randomization(args)
    found: list[Rate] = []
    with bar(total=len(chosen) * trials, desc="physical trials", unit="trial") as progress:
        for subject, placement in chosen:
            found += rates(scene, planner, [subject], trials, randomization=randomization, seed=args.trial_seed,
                           placement=placement,
                           progress=progress.update)
    return found


def report(found: list[Rate], args: argparse.Namespace, source: str, minimum: float | None = None) -> None:
    """The table of success rates (or JSON), the worst named."""
    randomization = _randomization(args)
    if args.json:
        print(json.dumps({"costmap": source, "trials": args.trials or 10, "seed": args.trial_seed,
                          "randomize": str(randomization), "play": bool(args.play),
                          "rules": [r.to_json() for r in found]}, indent=2))
        return
    width = max((len(r.subject.label) for r in found), default=4)
    print(f"{'rule':<{width}}  success  grabs  worst error")
    for r in found:
        grabs = "" if r.grabs is None else f"{r.grabs}/{len(r.trials)}"
        print(f"{r.subject.label:<{width}}  {r.successes:>3}/{len(r.trials):<3}  {grabs:>5}  "
              f"{_cm(r.worst_error)}")
    worst = sorted((r for r in found if r.successes < len(r.trials)), key=lambda r: r.rate)[:WORST]
    for r in worst:
        print(f"worst      {r.subject.label}: {r.rate:.0%} ({'; '.join(r.reasons[:2])})")
    total = sum(r.successes for r in found), sum(len(r.trials) for r in found)
    print(f"physics    {len(found)} rules of {source} tried, {total[0]}/{total[1]} trials succeeded "
          f"(randomize {randomization}, seeds {args.trial_seed}..{(args.trial_seed) + (args.trials or 10) - 1})"
          + ("" if minimum is None else f"; {sum(r.rate < minimum for r in found)} below {minimum:g}"))


def _cm(error: float) -> str:
    return "-" if error == float("inf") else f"{error * 100:.2f} cm"


def without_failing(costmap: Costmap, found: list[Rate], minimum: float) -> Costmap:
    """`costmap` without the rules any of whose subjects succeeded less
    often than `minimum`."""
    failing: dict[tuple[str, tuple[str, str, str]], set[int]] = {}
    for r in found:
        if r.rate < minimum:
            failing.setdefault((r.subject.kind, r.subject.key), set()).add(r.subject.index)

    def kept(kind: str, entries: Mapping) -> dict:
        out = {}
        for key, rules in entries.items():
            left = tuple(rule for i, rule in enumerate(rules) if i not in failing.get((kind, key), set()))
            if left:
                out[key] = left
        return out

    return dataclasses.replace(costmap, motions=kept("transfer", costmap.motions), slides=kept("slide", costmap.slides))


def verify(scene: Scene, planner: Planner, source: str, args: argparse.Namespace) -> int:
    """`costmap verify --physics`: exit status 1 when a rule succeeds less
    often than --min-success (default `VERIFY_MINIMUM`)."""
    chosen: Chosen
    if args.play:
        from symsynth.problem import solve, with_task

        solution = solve(with_task(scene, None, "--task", args.scene))
        if solution.cost_bound is None:
            raise InputError(f"{args.scene}: the robot has no winning strategy, so no principal play to try")
        chosen = play_subjects(scene, solution.principal_play)
    else:
        chosen = [(s, None) for s in subjects(scene, costmap_of(scene))]
    minimum = VERIFY_MINIMUM if args.min_success is None else args.min_success
    found = tried(scene, planner, chosen, args)
    report(found, args, source, minimum)
    return 1 if any(r.rate < minimum for r in found) else 0


def filtered(scene: Scene, planner: Planner, args: argparse.Namespace) -> tuple[Costmap, list[Rate]]:
    """`costmap SCENE --min-success P`: the scene's costmap without the
    rules below P (the scene carries its costmap)."""
    costmap = costmap_of(scene)
    everything: Chosen = [(s, None) for s in subjects(scene, costmap)]
    found = tried(scene, planner, everything, args)
    return without_failing(costmap, found, args.min_success), found


def summary(found: list[Rate], args: argparse.Namespace, before: Costmap, after: Costmap) -> dict[str, Any]:
    """What `--min-success` did, for the JSON summary."""
    randomization = _randomization(args)
    return {"min_success": args.min_success, "trials": args.trials or 10, "seed": args.trial_seed,
            "randomize": str(randomization), "tried": len(found),
            "removed": sum(1 for _ in before.all_rules()) - sum(1 for _ in after.all_rules()),
            "below": [r.to_json() for r in found if r.rate < args.min_success]}


def summary_line(done: Mapping[str, Any]) -> str:
    below = ", ".join(f"{r['kind']} {' '.join(r['key'])} #{r['rule']} ({r['object']}: {r['rate']:.0%})"
                      for r in done["below"][:WORST])
    return (f"physics    {done['tried']} rules tried, {done['trials']} trials each ({done['randomize']}): "
            f"{done['removed']} rules below {done['min_success']:g} left out" + (f": {below}" if below else ""))
