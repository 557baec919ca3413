"""Computed costmaps, cached by what determines them.

The key is a hash of the scene's geometry and names (not its task, `k` or
the objects' initial places, which the costmap does not depend on), the
bytes of the robot's URDF and of mesh files, the method, the planner, its
seed and symsynth's version.  Same key, same file: a hit is reused as is
(`build.obtain_costmap` writes the provenance its key implies into a file
of an older version, and computes again one whose recorded provenance
differs from what this run would record, e.g. another version of the
planner plugin: a third-party plugin's version is not in the key).
The cache lives in `$SYMSYNTH_CACHE`, else `$XDG_CACHE_HOME/symsynth`, else
`~/.cache/symsynth`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
from pathlib import Path

from symsynth import __version__
from symsynth.errors import InputError
from symsynth.scene.costmap import Costmap, CostmapError, load_costmap, write_costmap
from symsynth.scene.model import Scene

#: Bumped whenever the way costmaps are computed changes, so that no cached
#: costmap of an older revision is reused.
FORMAT_REVISION = 2


def cache_dir() -> Path:
    if os.environ.get("SYMSYNTH_CACHE"):
        return Path(os.environ["SYMSYNTH_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "symsynth"


def cache_key(scene: Scene, method: str, planner: str, seed: int) -> str:
    geometry = dataclasses.replace(scene.geometry, initial={},
                                   planner=dataclasses.replace(scene.geometry.planner, name="", seed=0))
    digest = hashlib.sha256()
    for part in (__version__, str(FORMAT_REVISION), method, planner, str(seed), repr(scene.object_names),
                 repr(sorted((o.name, sorted(o.tags)) for o in scene.objects)),
                 repr(scene.locations), repr(scene.else_samples), repr(scene.grasps), repr(geometry)):
        digest.update(part.encode() + b"\0")
    files = [scene.geometry.robot.urdf] + [s.mesh for s in scene.geometry.shapes.values() if s.mesh] \
        + [b.shape.mesh for b in scene.geometry.obstacles if b.shape.mesh]
    for path in files:
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()[:24]


def cache_path(scene: Scene, method: str, planner: str, seed: int) -> Path:
    return cache_dir() / f"{scene.name}-{method}-{planner}-s{seed}-{cache_key(scene, method, planner, seed)}.json"


def cached(path: Path) -> Costmap | None:
    """The costmap stored at `path`, or None: absent, or unreadable (then it
    is computed again and overwritten rather than standing in the way)."""
    if not path.is_file():
        return None
    try:
        return load_costmap(path)
    except CostmapError:
        return None


def store(costmap: Costmap, path: Path) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_suffix(".partial")
        write_costmap(costmap, partial)
        partial.replace(path)  # atomic: a crash never leaves half a file under the key
    except OSError as error:
        raise InputError(f"cannot write the costmap cache {path}: {error.strerror}; set SYMSYNTH_CACHE "
                         "to a writable folder, or pass --no-cache (with -o FILE to keep the result)") from None
