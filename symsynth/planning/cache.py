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
import json
import os
import re
import warnings
from pathlib import Path

from symsynth import __version__
from symsynth.errors import InputError, SymsynthWarning
from symsynth.files import cache_dir, check_regular, write_atomic
from symsynth.scene.costmap import Costmap, CostmapError, costmap_from_data
from symsynth.scene.mesh import MAX_BYTES
from symsynth.scene.load import costmap_problems
from symsynth.scene.yamlpos import read_json
from symsynth.scene.model import Scene, geometry_of

#: Bumped whenever the way costmaps are computed changes, so that no cached
#: costmap of an older revision is reused.
FORMAT_REVISION = 7  # 3: the file holds its key (`KEY_FIELD`); 4: contacts, slides, grasp reach;
# 5: and a checksum of its content (`SUM_FIELD`); 6: transfers and slides from under a resting place
# require it free (`support.py`); 7: a contact's anchors seeded with its anchor at the nearest place
# (`anchors.py`)


def cache_key(scene: Scene, method: str, planner: str, seed: int) -> str:
    physical = geometry_of(scene)
    geometry = dataclasses.replace(physical, initial={}, planner=dataclasses.replace(physical.planner, name="", seed=0))
    digest = hashlib.sha256()
    for part in (__version__, str(FORMAT_REVISION), method, planner, str(seed), repr(scene.object_names),
                 repr(sorted((o.name, sorted(o.tags)) for o in scene.objects)),
                 repr(scene.locations), repr(scene.else_samples), repr(scene.grasps), repr(geometry)):
        digest.update(part.encode() + b"\0")
    if physical.absent:  # not in the geometry's repr (which older keys read)
        digest.update(repr(sorted(physical.absent)).encode() + b"\0")
    files = [physical.robot.urdf] + [s.mesh for s in physical.shapes.values() if s.mesh] \
        + [b.shape.mesh for b in physical.obstacles if b.shape.mesh]
    for path in files:
        check_regular(path, "robot or mesh file", limit=MAX_BYTES)
        digest.update(Path(path).read_bytes())
    return digest.hexdigest()[:24]


#: Characters a cache file name keeps from the scene's name; others become '_'.
_SAFE = re.compile(r"[^A-Za-z0-9_-]")


def cache_path(scene: Scene, method: str, planner: str, seed: int) -> Path:
    """The file for this key: a bounded, sanitised form of the scene's name
    (which is any string: `../../x`, 300 characters) and the key, always
    directly inside `cache_dir()`."""
    stem = _SAFE.sub("_", scene.name)[:48] or "scene"
    folder = cache_dir()
    path = folder / f"{stem}-{_SAFE.sub('_', method)}-{_SAFE.sub('_', planner)[:32]}-s{seed}-" \
                    f"{cache_key(scene, method, planner, seed)}.json"
    if path.parent != folder:  # cannot happen with the names above; never write elsewhere
        raise InputError(f"cache file {path} would not be in the cache folder {folder}")
    return path


def cached(path: Path, scene: Scene) -> Costmap | None:
    """The costmap stored at `path` for `scene`, or None when there is none.

    A file that is not what this key stored -- unreadable, not a costmap,
    written under another key (the key is inside the file), or naming
    modes, anchors or places the scene does not have -- is not used: a
    warning says why, and the costmap is computed again and overwritten."""
    if not path.is_file():
        return None
    try:
        data = read_json(path, "cached costmap", CostmapError)
        if not isinstance(data, dict) or data.get(KEY_FIELD) != path.stem.rsplit("-", 1)[-1]:
            raise CostmapError("it was not written under this key (another scene's costmap?)")
        if data.get(SUM_FIELD) != checksum(data):
            raise CostmapError("its content is not what was stored (edited or damaged since: the checksum "
                               f"{SUM_FIELD!r} does not match)")
        costmap = costmap_from_data(data, str(path))
        problems = costmap_problems(scene, costmap)
        if problems:
            raise CostmapError(f"it does not fit the scene: {problems[0]}")
    except CostmapError as error:
        warnings.warn(f"the cached costmap {path} is not used and is computed again: {error}", SymsynthWarning,
                      stacklevel=2)
        return None
    return costmap


#: The top-level key of a cache file that holds its cache key (readers of
#: the costmap format ignore keys they do not know).
KEY_FIELD = "cache_key"
#: The top-level key of a cache file that holds the SHA-256 of the rest of
#: its content (`checksum`).  A cache hit is trusted as it is, so a file
#: edited by hand (every cost x100, its key kept) or damaged on disk must
#: not pass for one: its content no longer matches.  It is no signature:
#: whoever edits the file on purpose can write the checksum anew.
SUM_FIELD = "content_sha256"


def checksum(data: dict) -> str:
    """The SHA-256 of a cache file's data without its checksum, over its
    canonical JSON (sorted keys): the same for what `store` writes and for
    what `read_json` reads back (numbers keep their value through JSON)."""
    rest = {key: value for key, value in data.items() if key != SUM_FIELD}
    return hashlib.sha256(json.dumps(rest, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def unwritable(path: Path) -> str | None:
    """Why the cache file `path` could not be written, checked before the
    costmap is computed (None when it can be)."""
    folder = path.parent
    existing = next((p for p in (folder, *folder.parents) if p.exists()), None)
    if existing is None or not existing.is_dir():
        return f"{existing or folder} is not a folder"
    if not os.access(existing, os.W_OK | os.X_OK):
        return f"{existing} is not writable"
    return None


def store(costmap: Costmap, path: Path) -> None:
    """Write `costmap` to the cache file `path`, whole or not at all, with
    its key inside."""
    data = costmap.to_json() | {KEY_FIELD: path.stem.rsplit("-", 1)[-1]}
    data[SUM_FIELD] = checksum(data)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(f"cannot write the costmap cache {path.parent}: {error.strerror}; set SYMSYNTH_CACHE "
                         "to a writable folder, or pass --no-cache (with -o FILE to keep the result)") from None
    write_atomic(path, json.dumps(data, indent=1) + "\n", "the costmap cache file")
