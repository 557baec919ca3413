"""YAML loading that remembers where every value came from.

`load_with_lines(text)` returns the plain data (dicts, lists, scalars, as
`yaml.safe_load` would) and a map from key paths (`("objects", "w1", "at")`)
to 1-based line numbers, so validation errors can name file and line.
"""

from __future__ import annotations

from collections.abc import Hashable
from pathlib import Path
from typing import Any

import yaml

from symsynth.errors import InputError, read_text

KeyPath = tuple[Any, ...]


def load_with_lines(text: str) -> tuple[Any, dict[KeyPath, int]]:
    node = yaml.compose(text, Loader=yaml.SafeLoader)
    lines: dict[KeyPath, int] = {}
    if node is None:
        return None, lines
    constructor = yaml.SafeLoader("")
    return _build(node, (), lines, constructor), lines


def _build(node: yaml.Node, path: KeyPath, lines: dict[KeyPath, int], constructor) -> Any:
    lines[path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        constructor.flatten_mapping(node)  # `<<: *base` merge keys, as safe_load does
        result = {}
        for key_node, value_node in node.value:
            key = constructor.construct_object(key_node, deep=True)
            if not isinstance(key, Hashable):
                raise yaml.constructor.ConstructorError(
                    None, None, "a key must be a name, not a list or mapping", key_node.start_mark)
            result[key] = _build(value_node, path + (key,), lines, constructor)
            lines[path + (key,)] = key_node.start_mark.line + 1
        return result
    if isinstance(node, yaml.SequenceNode):
        return [_build(item, path + (i,), lines, constructor) for i, item in enumerate(node.value)]
    return constructor.construct_object(node, deep=True)


def line_of(lines: dict[KeyPath, int], path: KeyPath) -> int | None:
    """The line of `path`, or of its nearest ancestor that has one."""
    path = tuple(path)
    while path not in lines and path:
        path = path[:-1]
    return lines.get(path)


def read_yaml(path: str | Path, what: str,
              error: type[InputError] = InputError) -> tuple[Any, dict[KeyPath, int]]:
    """`load_with_lines` of the file `path`; unreadable text or invalid YAML
    raises `error` naming the file, the line and `what` it is."""
    text = read_text(Path(path), what, error)
    try:
        return load_with_lines(text)
    except yaml.YAMLError as problem:
        mark = getattr(problem, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark else str(path)
        raise error(f"{where}: not valid YAML: {getattr(problem, 'problem', problem)}") from None
