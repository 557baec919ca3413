"""Structured files (YAML, JSON) read with limits, remembering where values came from.

`load_with_lines(text)` returns the plain data (dicts, lists, scalars, as
`yaml.safe_load` would) and a map from key paths (`("objects", "w1", "at")`)
to 1-based line numbers, so validation errors can name file and line.
`read_json(path, what, error)` is the same door for JSON files.

Every file a user hands symsynth goes through one of these, and both refuse,
with the limit named, what would otherwise hang, exhaust memory or end in a
traceback downstream:

- a file larger than `MAX_BYTES`;
- nesting deeper than `MAX_DEPTH` lists and mappings (every pass over the
  data may then recurse safely; the bundled files nest 6 deep);
- more than `MAX_VALUES` values once YAML's aliases are expanded (a file
  of a few hundred bytes whose aliases nest ten levels expands to billions);
- a key given twice in one mapping (YAML and JSON keep the last one
  silently: `human:` twice would solve another game than the one the
  reader sees first); YAML's merge keys (`<<: *base`) may still be
  overridden, as YAML means them to be.

The limits are checked before anything is built, in one pass without
recursion: on the YAML parser's event stream, and on the JSON text (its
brackets outside strings) before the decoder, which recurses, sees it.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Hashable
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
import yaml

from symsynth.errors import InputError, read_text

KeyPath = tuple[Any, ...]

#: Larger files are refused: a costmap of the bundled scenes with evidence
#: paths at 150 roadmap vertices is about 2 MB.
MAX_BYTES = 64 << 20
#: Lists and mappings nested deeper than this are refused.
MAX_DEPTH = 64
#: Values (scalars, lists, mappings) after aliases are expanded.  YAML is
#: parsed in Python at about 50,000 values a second, so a file at the limit
#: reads in a few seconds; the bundled scenes hold at most 206 values, human
#: scripts four per move.  (Costmaps and strategy files are JSON: without
#: aliases, their size is bounded by `MAX_BYTES`.)
MAX_VALUES = 100_000


class LimitError(yaml.YAMLError):
    """A structured file beyond one of the limits, at a line."""

    def __init__(self, problem: str, mark: yaml.Mark | None):
        super().__init__(problem)
        self.problem = problem
        self.problem_mark = mark


def check_limits(text: str) -> None:
    """Depth and expanded size of a YAML text, from its events (no recursion).

    Each node's expanded size is 1 plus its children's, and its height is 1
    plus its children's largest for a list or mapping (0 for a scalar); an
    alias stands for the whole node it names, so the total size is what
    building the data would create, and an alias's depth plus its node's
    height is how deep the built data nests there."""
    anchored: dict[str, tuple[int, int]] = {}  # anchor -> (expanded size, height)
    stack: list[list] = []  # open collections: [size so far, largest height of a child, anchor]
    total = 0
    for event in yaml.parse(text, Loader=yaml.SafeLoader):
        if isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent)):
            if len(stack) >= MAX_DEPTH:
                raise LimitError(f"lists and mappings nested more than {MAX_DEPTH} deep", event.start_mark)
            stack.append([1, 0, event.anchor])
            total += 1
            continue
        if isinstance(event, (yaml.SequenceEndEvent, yaml.MappingEndEvent)):
            size, below, anchor = stack.pop()
            height = below + 1
        elif isinstance(event, yaml.ScalarEvent):
            size, height, anchor = 1, 0, event.anchor
            total += 1
        elif isinstance(event, yaml.AliasEvent):
            (size, height), anchor = anchored.get(event.anchor, (1, 0)), None
            total += size
            if len(stack) + height > MAX_DEPTH:
                raise LimitError(f"lists and mappings nested more than {MAX_DEPTH} deep once aliases are "
                                 "expanded", event.start_mark)
        else:
            continue
        if total > MAX_VALUES:
            raise LimitError(f"more than {MAX_VALUES:,} values once aliases are expanded", event.start_mark)
        if anchor is not None:
            anchored[anchor] = size, height
        if stack:
            stack[-1][0] += size
            stack[-1][1] = max(stack[-1][1], height)


def load_with_lines(text: str) -> tuple[Any, dict[KeyPath, int]]:
    check_limits(text)
    node = yaml.compose(text, Loader=yaml.SafeLoader)
    lines: dict[KeyPath, int] = {}
    if node is None:
        return None, lines
    constructor = yaml.SafeLoader("")
    _check_keys(node, constructor)
    return _build(node, (), lines, constructor), lines


_MERGE = "tag:yaml.org,2002:merge"


def _check_keys(root: yaml.Node, constructor: yaml.SafeLoader) -> None:
    """Every mapping's keys are names, each given once (merge keys `<<:`
    aside), checked once per node as written, before `_build` merges
    mappings (which adds the merged keys to the node); in document order,
    without recursion."""
    stack: list[tuple[yaml.Node, KeyPath]] = [(root, ())]
    checked: set[int] = set()  # id of every node checked: an alias names a node checked already
    while stack:
        node, path = stack.pop()
        if id(node) in checked:
            continue
        checked.add(id(node))
        children: list[tuple[yaml.Node, KeyPath]] = []
        if isinstance(node, yaml.MappingNode):
            own: dict[Any, yaml.Node] = {}
            for key_node, value_node in node.value:
                if key_node.tag == _MERGE:
                    children.append((value_node, path))
                    continue
                key = _construct(key_node, constructor)
                if not isinstance(key, Hashable):
                    raise yaml.constructor.ConstructorError(
                        None, None, "a key must be a name, not a list or mapping", key_node.start_mark)
                if key in own:
                    where = ".".join(map(str, path + (key,)))
                    raise yaml.constructor.ConstructorError(
                        None, None, f"{where} is given twice (first at line {own[key].start_mark.line + 1}); "
                        "keep one", key_node.start_mark)
                own[key] = key_node
                children.append((value_node, path + (key,)))
        elif isinstance(node, yaml.SequenceNode):
            children = [(item, path + (i,)) for i, item in enumerate(node.value)]
        stack.extend(reversed(children))


def _build(node: yaml.Node, path: KeyPath, lines: dict[KeyPath, int], constructor) -> Any:
    """The data of `node`; recursion is bounded by `MAX_DEPTH`, aliases
    expanded (`check_limits`)."""
    lines[path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        constructor.flatten_mapping(node)  # `<<: *base` merge keys, as safe_load does
        result = {}
        for key_node, value_node in node.value:
            key = _construct(key_node, constructor)
            result[key] = _build(value_node, path + (key,), lines, constructor)
            lines[path + (key,)] = key_node.start_mark.line + 1
        return result
    if isinstance(node, yaml.SequenceNode):
        return [_build(item, path + (i,), lines, constructor) for i, item in enumerate(node.value)]
    return _construct(node, constructor)


def _construct(node: yaml.Node, constructor: yaml.SafeLoader) -> Any:
    """`safe_load`'s value of `node`; one Python cannot hold (`2020-13-45`
    read as a date) is a `ConstructorError`
    at its line instead of Python's `ValueError`."""
    if node.tag == "tag:yaml.org,2002:int" and len(node.value) > LONG_INTEGER:
        return _long_integer(node)  # as read_json does
    try:
        return constructor.construct_object(node, deep=True)
    except ValueError as problem:
        if not isinstance(node, yaml.ScalarNode):  # a key that is a list or mapping
            raise yaml.constructor.ConstructorError(
                None, None, f"a value in this key cannot be read ({problem})", node.start_mark) from None
        kind = _KINDS.get(node.tag, node.tag.rsplit(":", 1)[-1])
        raise yaml.constructor.ConstructorError(
            None, None, f"{node.value[:40]!r} is read as {kind} and is not one ({problem}); "
            "quote it if it is text", node.start_mark) from None


_KINDS = {"tag:yaml.org,2002:timestamp": "a date"}


#: Integers of at most this many characters are read exactly, as Python ints
#: (a cost of 9007199254740993 stays itself; 10^300 is past any cost).
LONG_INTEGER = 300


def _above(text: str) -> float:
    """A longer integer, as the float just above it (inf past 1e308), so that
    checks of finiteness see it and a cost is never read below itself."""
    value = float(text)
    return math.nextafter(value, math.inf) if math.isfinite(value) else value


def _long_integer(node: yaml.ScalarNode) -> float:
    """An integer of more than `LONG_INTEGER` characters (`_above`)."""
    try:
        return _above(node.value.replace("_", ""))
    except ValueError:
        raise yaml.constructor.ConstructorError(
            None, None, f"an integer of {len(node.value)} characters is more than symsynth reads",
            node.start_mark) from None


def line_of(lines: dict[KeyPath, int], path: KeyPath) -> int | None:
    """The line of `path`, or of its nearest ancestor that has one."""
    path = tuple(path)
    while path not in lines and path:
        path = path[:-1]
    return lines.get(path)


def read_yaml(path: str | Path, what: str,
              error: type[InputError] = InputError) -> tuple[Any, dict[KeyPath, int]]:
    """`load_with_lines` of the file `path`; unreadable text, invalid YAML or
    a limit passed raises `error` naming the file, the line and `what` it is."""
    text = read_text(Path(path), what, error, MAX_BYTES)
    try:
        return load_with_lines(text)
    except yaml.YAMLError as problem:
        mark = getattr(problem, "problem_mark", None)
        where = f"{path}:{mark.line + 1}" if mark else str(path)
        raise error(f"{where}: not valid YAML: {getattr(problem, 'problem', problem)}") from None


def read_json(path: str | Path, what: str, error: type[InputError] = InputError) -> Any:
    """The data of the JSON file `path`, within the limits above; invalid
    JSON, a key given twice or a limit passed raises `error` naming the
    file, the line and `what` it is.  Nesting is measured on the text before
    it is decoded (`json_depth`), so the decoder never recurses deeper than
    `MAX_DEPTH`."""
    text = read_text(Path(path), what, error, MAX_BYTES)
    if json_depth(text) > MAX_DEPTH:
        _refuse_json(text, path, error, f"lists and objects nested more than {MAX_DEPTH} deep")
    try:
        return json.loads(text, object_pairs_hook=_unique_pairs, parse_int=_integer)
    except json.JSONDecodeError as problem:
        raise error(f"{path}:{problem.lineno}:{problem.colno}: not JSON: {problem.msg}") from None
    except _GivenTwice:
        _refuse_json(text, path, error, "a key is given twice in one object; keep one")


class _GivenTwice(Exception):
    """A key given twice in one JSON object (`_refuse_json` says where)."""


def _unique_pairs(items: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object's dict, unless one of its keys is given twice."""
    result = dict(items)
    if len(result) < len(items):
        raise _GivenTwice
    return result


#: A JSON string (a quote, then escapes or anything but quotes and backslashes).
_JSON_STRING = r'"[^"\\]*(?:\\.[^"\\]*)*"'
_JSON_TOKEN = re.compile(_JSON_STRING + r"|[\[\]{}:,]", re.DOTALL)
_STRINGS = re.compile(_JSON_STRING, re.DOTALL)
_NOT_BRACKETS = bytes(set(range(256)) - set(b"[]{}"))
_NESTING = np.zeros(256, dtype=np.int8)  # +1 per opening, -1 per closing bracket, by ASCII code
_NESTING[[ord("["), ord("{")]], _NESTING[[ord("]"), ord("}")]] = 1, -1


def json_depth(text: str) -> int:
    """How deep lists and objects nest in the JSON `text`: the largest
    running sum of +1 per `[` or `{` and -1 per `]` or `}` outside strings.
    For valid JSON it is the nesting of the data; for invalid JSON it is
    exact up to the first mistake, as far as a decoder reads."""
    brackets = _STRINGS.sub("", text).encode().translate(None, _NOT_BRACKETS)
    steps = _NESTING[np.frombuffer(brackets, dtype=np.uint8)]
    return int(np.cumsum(steps, dtype=np.int32).max(initial=0))  # max_i sum_{j <= i} steps_j


def _refuse_json(text: str, path: str | Path, error: type[InputError], found: str) -> NoReturn:
    """Raise `error` for the first key given twice in one object or the first
    list or object nested deeper than `MAX_DEPTH` in the JSON `text`, with
    its line and key path; the text is walked token by token, without
    recursion.  It runs once `read_json` has `found` one of them, which
    the message names should the walk not place it."""
    levels: list[list] = []  # open lists and objects: [keys seen {key: line} (None in a list), key or index]
    line, seen_to, expect_key = 1, 0, False
    for token in _JSON_TOKEN.finditer(text):
        line += text.count("\n", seen_to, token.start())
        seen_to, kind = token.start(), token[0][0]
        if kind in "[{":
            if len(levels) == MAX_DEPTH:
                raise error(f"{path}:{line}: not valid JSON: lists and objects nested more than {MAX_DEPTH} deep")
            levels.append([{} if kind == "{" else None, 0])
            expect_key = kind == "{"
        elif kind in "]}" and levels:
            levels.pop()
            expect_key = False
        elif kind == "," and levels:
            if levels[-1][0] is None:
                levels[-1][1] += 1
            expect_key = levels[-1][0] is not None
        elif kind == ":":
            expect_key = False
        elif kind == '"' and expect_key:
            key, keys = _json_key(token[0]), levels[-1][0]
            if key in keys:
                where = ".".join([*(str(level[1]) for level in levels[:-1]), key])
                raise error(f"{path}:{line}: not valid JSON: {where} is given twice "
                            f"(first at line {keys[key]}); keep one")
            keys[key], levels[-1][1], expect_key = line, key, False
    raise error(f"{path}: not valid JSON: {found}")


def _json_key(token: str) -> str:
    """The key a JSON string token stands for (as written, if its escapes are not JSON's)."""
    try:
        return json.loads(token)
    except json.JSONDecodeError:
        return token[1:-1]


def _integer(text: str) -> int | float:
    """A JSON integer, exact up to `LONG_INTEGER` characters; a longer one as
    the float just above it (`_above`), so that Python's limit on long
    integer strings is never reached."""
    return int(text) if len(text) <= LONG_INTEGER else _above(text)
