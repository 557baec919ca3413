"""`symsynth costmap`: compute a physical scene's conditional costmap, or verify one."""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.cli import options, physical
from symsynth.cli.options import check_writable
from symsynth.errors import InputError
from symsynth.game.abstraction import costmap_of
from symsynth.planning.build import Obtained, obtain_costmap
from symsynth.planning.registry import DEFAULT, planner_class, planner_names, planner_version
from symsynth.planning.verify import building_planner, verify_costmap
from symsynth.scene import load_scene
from symsynth.scene.model import Scene
from symsynth.scene.costmap import Costmap, write_costmap

DESCRIPTION = f"""\
Compute the conditional costmap of a physical scene (one with a robot):

  symsynth costmap SCENE [--method sg|recursive] [--planner NAME] [--costmap-seed S] [-o FILE]

Anchors come from inverse kinematics; each mode (hand empty, or holding an
object with a grasp) gets a roadmap against the static obstacles; every
roadmap edge is checked once against the location obstacles; then every
motion is a graph search.  'sg' (the paper's Alg. 2) assumes objects at all
other places and gives one rule per motion; 'recursive' (Alg. 3) gives
"if these places are free, it costs c" rules.  Each rule keeps its evidence
path, and the file records who built it (key 'planner': the planner, its
version, method, seed and roadmap settings).  The result is cached (keyed
by the scene's geometry, method, planner and seed; same seed, same file),
so 'symsynth solve SCENE' reuses it.  The roadmaps of the modes are built
in parallel: on local processes (--jobs, default one per core), or with
--executor ray on a Ray cluster (--address to join one; none starts a local
instance); the file is the same either way.

  symsynth costmap verify FILE --scene SCENE [--planner NAME]

re-checks every rule's evidence path at a 4x finer check step than it was
built with (or than the scene's setting, if that is finer) against the static obstacles and the location obstacles the
rule assumes, its cost, and that it starts and ends at its anchors.
Anchors are the planner's inverse kinematics solutions, so the paths are
checked with the planner that built the costmap, which the file records
(key 'planner'): --planner is needed only for a file without that record
(written by hand or by an older symsynth), and another planner than the
recorded one is refused, since every path would miss its anchors.
Exit status 1 if a path fails (a bug in a planner or the algorithms).

  symsynth costmap verify FILE --scene SCENE --physics [--trials N] [--randomize ...] [--seed S] [--play]

tries every transfer and slide rule in the physical world instead, N times
(seeds S..S+N-1): grab held and lifted, carried along the evidence path,
dropped and settled within 1 cm of the target; a slide ending within 1 cm,
moved only by contact.  The other objects stand where the scene (--play: the
principal play's state) puts them, except where the rule needs a place free.
A table of success rates, the worst named; exit status 1 when a rule
succeeds less often than --min-success (default 0.9).

  symsynth costmap SCENE --min-success P [--trials N] -o FILE

writes the costmap without the rules that succeed less often than P in
the physical world (docs/costmaps.md).

Planners: {', '.join(planner_names()) or 'none installed'} (entry points 'symsynth.planners';
default {DEFAULT})."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("costmap", help=COMMANDS["costmap"], description=DESCRIPTION,
                                   usage="symsynth costmap SCENE [options]\n"
                                         "       symsynth costmap verify FILE --scene SCENE [--planner NAME]",
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("target", nargs="+", metavar="SCENE | verify FILE",
                        help="a physical scene file, or 'verify' and a costmap file")
    parser.add_argument("--scene", type=Path, help="with verify: the scene the costmap belongs to")
    parser.add_argument("-o", "--output", type=options.output_file, metavar="FILE",
                        help="also write the costmap to FILE")
    parser.add_argument("--json", action="store_true", help="print a summary as JSON")
    options.add_executor(parser, "roadmaps built at once (default: one per core)")
    options.add_costmap_options(parser, planner_help=options.PLANNER_HELP[:-1]
                                + "; with verify: the one the costmap records)")
    physical.add_options(parser)
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.target[0] == "verify":
        if len(args.target) != 2 or args.scene is None:
            raise InputError("usage: symsynth costmap verify FILE --scene SCENE")
        physical.check(args, verify=True)
        return _verify(Path(args.target[1]), args)
    if len(args.target) != 1:
        raise InputError(f"expected one scene file, found {len(args.target)} arguments "
                         f"({' '.join(args.target)}); to check a costmap: symsynth costmap verify FILE --scene SCENE")
    scene = load_scene(Path(args.target[0]))
    if scene.geometry is None:
        raise InputError(f"{args.target[0]}: an abstract scene (no 'robot' key): its costmap is given, "
                         "not computed")
    physical.check(args, verify=False)
    if args.min_success is not None and args.output is None:
        raise InputError("--min-success writes the costmap without the failing rules to -o FILE (the cache keeps "
                         "the planner's own): add -o FILE, then solve with --costmap FILE")
    if args.output is not None:  # before the planning, which takes a while
        check_writable(args.output, "costmap file", inputs=(Path(args.target[0]),))
    executor = None if args.executor == "local" and args.jobs is None else options.executor(args)
    request = options.costmap_request(args)
    got = obtain_costmap(scene, request.method, request.planner, request.seed, use_cache=request.use_cache,
                         executor=executor)
    costmap, found = got.costmap, None
    if args.min_success is not None:
        costmap, found = physical.filtered(dataclasses.replace(scene, costmap=costmap),
                                           planner_class(got.planner)(scene), args)
    if args.output is not None:
        write_costmap(costmap, args.output)
    summary = _summary(scene, got, costmap, args.output or got.path)
    done = None if found is None else physical.summary(found, args, got.costmap, costmap)
    if done is not None:
        summary["physics"] = done
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        _print(scene, got, summary, done)
    return 0


def _summary(scene: Scene, got: Obtained, costmap: Costmap, written: Path | None) -> dict:
    """What `costmap` computed, as `--json` prints it."""
    summary = {
        "scene": scene.name, "method": got.method, "planner": got.planner, "seed": got.seed,
        "cached": got.cached, "file": None if written is None else str(written),
        "motions": len(costmap.motions), "slides": len(costmap.slides),
        "rules": sum(1 for _ in costmap.all_rules()), "absent": sorted(got.costmap.absent),
    }
    if got.stats is not None:
        summary |= {"seconds": {k: round(v, 3) for k, v in got.stats.seconds.items()},
                    "wall_seconds": round(got.stats.wall, 3),
                    "cpu_seconds": round(sum(got.stats.seconds.values()), 3), "workers": got.stats.workers,
                    "roadmaps": got.stats.roadmaps, "vertices": got.stats.vertices,
                    "edges": got.stats.edges}
    return summary


def _print(scene: Scene, got: Obtained, summary: dict, done: dict | None) -> None:
    """The summary, as a person reads it."""
    origin = "reused from the cache" if got.cached else "computed"
    slides = f"{summary['slides']} slide{'s' * (summary['slides'] != 1)}, " if summary["slides"] else ""
    print(f"costmap    {scene.name}: {summary['motions']} motions, {slides}{summary['rules']} rules "
          f"({got.method}, planner {got.planner}, seed {got.seed}; {origin})")
    if got.costmap.absent:
        print(f"absent     {', '.join(sorted(got.costmap.absent))} (declared by the scene: no robot configuration)")
    if got.stats is not None:
        s = got.stats
        phases = ", ".join(f"{k} {v:.2f}" for k, v in s.seconds.items())
        print(f"roadmaps   {s.roadmaps} ({s.vertices} vertices, {s.edges} edges)")
        print(f"seconds    {s.wall:.2f} on the clock; per phase, summed over {s.workers} "
              f"process{'es' * (s.workers != 1)}: {phases}")
    if done is not None:
        print(physical.summary_line(done))
    print(f"file       {summary['file'] or 'none written (--no-cache without -o FILE)'}")


def _verify(path: Path, args: argparse.Namespace) -> int:
    scene = load_scene(args.scene, costmap=path)  # the costmap checked against the scene, as solve does
    if scene.geometry is None:
        raise InputError(f"{args.scene}: an abstract scene (no 'robot' key) has nothing to verify against")
    costmap = costmap_of(scene)  # loaded from `path`
    name = building_planner(costmap, args.planner, str(path))
    built = costmap.provenance
    if built is not None and built.version is not None and planner_version(name) not in (None, built.version):
        print(f"note       {path} was built by {name} {built.version}, {name} {planner_version(name)} is "
              "installed: if its inverse kinematics changed since, the paths miss their anchors")
    planner = planner_class(name)(scene)
    # 4x finer than the paths were checked when built, and than the scene asks: never coarser than the
    # scene's own setting, whatever the file records
    step = scene.geometry.planner.check_step
    if built is not None and built.check_step is not None:
        step = min(step, built.check_step)
    step /= 4
    if args.physics:
        return physical.verify(scene, planner, str(path), args)
    checked, failures = verify_costmap(costmap, scene, planner, step)
    for failure in failures[:20]:
        print(f"FAIL {failure}")
    if len(failures) > 20:
        print(f"... and {len(failures) - 20} more")
    verdict = "all evidence paths hold" if not failures else f"{len(failures)} failed"
    print(f"verified   {checked} rules of {path} with planner {name} at check step "
          f"{step:g} rad: {verdict}")
    return 1 if failures else 0
