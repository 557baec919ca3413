"""`symsynth show`: a picture of a physical scene, to author scenes by looking."""

from __future__ import annotations

import argparse
from pathlib import Path

from symsynth.cli import COMMANDS
from symsynth.cli import options
from symsynth.cli.options import check_writable
from symsynth.errors import InputError
from symsynth.scene import load_scene

DESCRIPTION = """\
Render a physical scene headless (PyBullet's TinyRenderer, no display
needed): the robot at home, the static obstacles in grey, every object at
its initial place, the locations of interest marked green and the Else
samples orange, each labelled with its name in a white box, and each object
with its name in a dark box (--no-labels: none); a label moves round its
point rather than cover another label."""


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("show", help=COMMANDS["show"], description=DESCRIPTION,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene", type=Path, help="a physical scene file (YAML, with a robot)")
    parser.add_argument("-o", "--output", type=options.output_file, metavar="FILE", default=None,
                        help="the picture to write (PNG; default: SCENE with .png)")
    parser.add_argument("--size", type=options.size, default=(800, 600), metavar="WxH",
                        help="image size in pixels (default: 800x600)")
    parser.add_argument("--no-labels", action="store_true", help="leave the place and object names out")
    parser.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from symsynth.execution.render import render_scene

    scene = load_scene(args.scene)
    if scene.geometry is None:
        raise InputError(f"{args.scene}: an abstract scene (no 'robot' key) has nothing to show")
    output = args.output or args.scene.with_suffix(".png")
    check_writable(output, "picture", inputs=(args.scene,))
    width, height = args.size
    render_scene(scene, output, width=width, height=height, labels=not args.no_labels)
    print(f"wrote {output} ({width}x{height}, {len(scene.locations)} locations, "
          f"{len(scene.else_samples)} Else samples)")
    return 0
