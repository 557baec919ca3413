"""The `.part` file of the LTLf synthesis datasets and SYNTCOMP:

    .inputs: a b c      (the environment's variables)
    .outputs: x y       (the agent's)

Each keyword once, on a line of its own; names separated by spaces; blank
lines and `#` comments ignored.  A variable in both lists is an error.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from symsynth.errors import InputError, read_text

_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class Partition:
    inputs: tuple[str, ...]  # the environment's
    outputs: tuple[str, ...]  # the agent's


#: Bytes of a partition file read at most (the datasets' largest: 5 kB).
MAX_BYTES = 1_000_000


def read_partition(path: str | Path) -> Partition:
    """The partition in the file `path`: a regular file (a named pipe would
    block until a writer comes) of at most MAX_BYTES."""
    text = read_text(Path(path), "partition file", limit=MAX_BYTES, regular=True)
    found: dict[str, tuple[int, list[str]]] = {}
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        key, colon, rest = line.partition(":")
        key = key.strip()
        if not colon or key not in (".inputs", ".outputs"):
            raise InputError(f"{path}:{number}: expected '.inputs: NAMES' or '.outputs: NAMES', found {raw.strip()!r}")
        if key in found:
            raise InputError(f"{path}:{number}: {key} is given twice (first at line {found[key][0]})")
        names = rest.split()
        for name in names:
            if not _NAME.match(name):
                raise InputError(f"{path}:{number}: {name!r} is not a variable name")
        if len(set(names)) != len(names):
            twice = sorted({n for n in names if names.count(n) > 1})
            raise InputError(f"{path}:{number}: {', '.join(twice)} listed twice in {key}")
        found[key] = (number, names)
    if not found:
        raise InputError(f"{path}: empty: expected '.inputs:' and '.outputs:' lines")
    inputs = found.get(".inputs", (0, []))[1]
    outputs = found.get(".outputs", (0, []))[1]
    both = sorted(set(inputs) & set(outputs))
    if both:
        (first, key), (second, other) = sorted((found[k][0], k) for k in (".inputs", ".outputs"))
        raise InputError(f"{path}:{second}: {', '.join(both)} in both .inputs and .outputs ({other} here, {key} "
                         f"at line {first}); a variable belongs to one player")
    return Partition(tuple(inputs), tuple(outputs))
