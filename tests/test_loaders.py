"""Every structured file goes through one reader with limits
(symsynth/scene/yamlpos.py): duplicate keys, alias bombs, deep nesting,
huge numbers and huge files are clear errors naming file and line, and the
bundled files still read exactly as yaml/json read them."""

from __future__ import annotations

import json
import os
import time

import pytest
import yaml

from support.paper import SCENES
from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.execution.human import read_script
from symsynth.game.strategy import read_strategy
from symsynth.scene import load_scene
from symsynth.scene import yamlpos
from symsynth.scene.yamlpos import read_json, read_yaml

TOY = (SCENES / "toy.yaml").read_text()


def scene_file(tmp_path, text, costmap=None):
    (tmp_path / "toy.costmap.json").write_text(costmap or (SCENES / "toy.costmap.json").read_text())
    path = tmp_path / "toy.yaml"
    path.write_text(text)
    return path


def refused(capsys, argv, *expected):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    for text in expected:
        assert text in err, err
    return err


def line_number(text, start):
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(start))


@pytest.mark.parametrize("old, new, key", [
    ("human: {k: 1}", "human: {k: 1}\nhuman: {k: 0}", "human"),
    ('task: "F(at(black, l3))"', 'task: "F(at(black, l3))"\ntask: "F(at(black, l2))"', "task"),
    ("b: {tags: [block, black], at: l1}", "b: {tags: [block, black], at: l1, at: l2}", "objects.b.at"),
])
def test_a_key_given_twice_is_refused_with_both_lines(tmp_path, capsys, old, new, key):
    """The last one won silently: with `human` twice the toy was solved with
    k = 0 (E_p 17) where the reader sees k = 1 (50)."""
    assert old in TOY
    text = TOY.replace(old, new)
    path = scene_file(tmp_path, text)
    first = next(i for i, line in enumerate(text.splitlines(), 1) if new.splitlines()[0] in line)
    second = first if "\n" not in new else first + 1
    refused(capsys, ["solve", str(path)], f"toy.yaml:{second}: not valid YAML: {key} is given twice "
                                          f"(first at line {first})")


def test_merge_keys_may_still_be_overridden(tmp_path):
    text = "base: &base {x: 1, y: 2}\nitem:\n  <<: *base\n  y: 3\n"
    path = tmp_path / "m.yaml"
    path.write_text(text)
    data, _ = read_yaml(path, "test")
    assert data["item"] == {"x": 1, "y": 3} == yaml.safe_load(text)["item"]


def test_an_alias_of_a_mapping_with_merge_keys_reads_as_yaml_reads_it(tmp_path):
    """The second visit of an aliased mapping saw its merged keys as its own: `other.y is given twice`."""
    text = "base: &b {x: 1, y: 2}\nitem: &i\n  <<: *b\n  y: 3\nother: *i\nmore: [*i, {<<: *i, x: 0}]\n"
    path = tmp_path / "m.yaml"
    path.write_text(text)
    assert read_yaml(path, "test")[0] == yaml.safe_load(text)


def test_a_key_given_twice_in_an_aliased_mapping_is_named_where_it_is_written(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_text("base: &b\n  x: 1\n  x: 2\nitem: *b\n")
    with pytest.raises(InputError, match=r"m\.yaml:3: not valid YAML: base\.x is given twice \(first at line 2\)"):
        read_yaml(path, "test")


def test_aliases_that_nest_deeper_than_the_limit_are_refused(tmp_path, capsys):
    """Each alias below 30 levels of its own: 70 of them nest 2,100 deep once expanded, though no
    part of the 5 KB file nests more than 31 deep (a RecursionError traceback)."""
    lines = ["a0: &a0 x"] + [f"a{i}: &a{i} " + "[" * 30 + f"*a{i - 1}" + "]" * 30 for i in range(1, 70)]
    path = tmp_path / "chain.yaml"
    path.write_text("\n".join(lines) + "\n")
    refused(capsys, ["solve", str(path)], "chain.yaml:4:",
            f"lists and mappings nested more than {yamlpos.MAX_DEPTH} deep once aliases are expanded")


def test_aliases_that_nest_up_to_the_limit_are_read(tmp_path):
    """The top mapping, 31 levels of a1 and 32 of a2: 64 in all."""
    text = "a0: &a0 x\na1: &a1 " + "[" * 31 + "*a0" + "]" * 31 + "\na2: " + "[" * 32 + "*a1" + "]" * 32 + "\n"
    path = tmp_path / "chain.yaml"
    path.write_text(text)
    assert read_yaml(path, "test")[0] == yaml.safe_load(text)


def laughs(levels=8):
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    for i in range(1, levels):
        lines.append(f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]")
    return "\n".join(lines) + "\n"


def test_an_alias_bomb_is_refused_at_once(tmp_path, capsys):
    """A file of 452 bytes whose aliases expand to 10^8 values (the issue's 294-byte one: 7 levels) took
    5.7 GB and was killed; as a human script it was a MemoryError."""
    path = tmp_path / "bomb.yaml"
    path.write_text(laughs())
    assert len(path.read_bytes()) < 500
    clock = time.perf_counter()
    refused(capsys, ["solve", str(path)], "bomb.yaml:", f"more than {yamlpos.MAX_VALUES:,} values once aliases are expanded")
    with pytest.raises(InputError, match="once aliases are expanded"):
        read_script(path, load_scene(SCENES / "toy.yaml"))
    assert time.perf_counter() - clock < 10  # a bound against hanging, not a speed target


def test_a_long_yaml_file_is_refused_at_once(tmp_path, capsys):
    """YAML is parsed in Python at about 50,000 values a second, three passes: 2,000,000 values
    (8 MB, far below the size limit) took minutes before the old limit of 5,000,000 values did not
    stop them.  The bundled scenes hold at most 206 values."""
    assert max(sum(1 for event in yaml.parse(path.read_text()) if isinstance(event, VALUE_EVENTS))
               for path in SCENES.glob("*.yaml")) * 400 < yamlpos.MAX_VALUES
    path = tmp_path / "long.yaml"
    path.write_text("moves:\n" + "  - 1\n" * 2_000_000)
    clock = time.perf_counter()
    refused(capsys, ["solve", str(path)], f"more than {yamlpos.MAX_VALUES:,} values")
    assert time.perf_counter() - clock < 20  # a bound against hanging, not a speed target


VALUE_EVENTS = (yaml.ScalarEvent, yaml.SequenceStartEvent, yaml.MappingStartEvent, yaml.AliasEvent)


def test_aliases_within_the_limit_are_expanded(tmp_path):
    path = tmp_path / "ok.yaml"
    path.write_text(laughs(3))
    data, _ = read_yaml(path, "test")
    assert data == yaml.safe_load(laughs(3))


@pytest.mark.parametrize("depth", [yamlpos.MAX_DEPTH + 1, 5_000, 100_000])
def test_deep_nesting_is_refused(tmp_path, capsys, depth):
    path = tmp_path / "deep.yaml"
    path.write_text("name: " + "[" * depth + "]" * depth + "\n")
    refused(capsys, ["solve", str(path)], "deep.yaml:1:", f"nested more than {yamlpos.MAX_DEPTH} deep")
    costmap = tmp_path / "deep.json"
    costmap.write_text("[" * depth + "]" * depth)
    refused(capsys, ["solve", str(SCENES / "toy.yaml"), "--costmap", str(costmap)],
            f"nested more than {yamlpos.MAX_DEPTH} deep")


def test_nesting_at_the_limit_is_read(tmp_path):
    depth = yamlpos.MAX_DEPTH - 1  # the top mapping is one level
    path = tmp_path / "deep.yaml"
    path.write_text("x: " + "[" * depth + "]" * depth + "\n")
    assert read_yaml(path, "test")[0] == yaml.safe_load(path.read_text())


COSTMAP = (SCENES / "toy.costmap.json").read_text()


@pytest.mark.parametrize("old, new, key", [
    ('"format": "symsynth.costmap/1"', '"format": "symsynth.costmap/1",\n"format": "symsynth.costmap/1"',
     "format"),
    ('"rules": [{"free": [], "cost": 4}]},\n', '"rules": [{"free": [], "cost": 4,\n"cost": 1}]},\n',
     "motions.0.rules.0.cost"),
    ('"to": "l1/top"', '"to": "l1/top", "to": "l2/top"', "motions.0.to"),
])
def test_a_key_given_twice_in_json_is_refused_with_both_lines(tmp_path, capsys, old, new, key):
    """A costmap's key given twice was refused without saying where; json keeps the last one."""
    text = COSTMAP.replace(old, new, 1)
    assert text != COSTMAP
    first = line_number(COSTMAP, COSTMAP[:COSTMAP.index(old)].rsplit("\n", 1)[-1])
    second = first + new.count("\n") - old.count("\n")
    path = tmp_path / "c.json"
    path.write_text(text)
    refused(capsys, ["solve", str(SCENES / "toy.yaml"), "--costmap", str(path)],
            f"c.json:{second}: not valid JSON: {key} is given twice (first at line {first}); keep one")


def test_a_key_given_twice_in_a_strategy_file_is_refused(tmp_path):
    path = tmp_path / "s.json"
    path.write_text('{"format": "symsynth.strategy/1",\n "objects": ["b"],\n "positions": [{"q": [0],\n'
                    '  "h": 0, "q": [1]}]}')
    with pytest.raises(InputError, match=r"s\.json:4: not valid JSON: positions\.0\.q is given twice "
                                         r"\(first at line 3\); keep one"):
        read_strategy(path)


def test_brackets_and_quotes_within_json_strings_are_no_nesting(tmp_path):
    text = json.dumps({"a": "[" * 100 + '\\"{' * 100, "b\"[": [[1]], "c": "]" * 100 + "[" * 100})
    path = tmp_path / "s.json"
    path.write_text(text)
    assert read_json(path, "test") == json.loads(text)
    assert yamlpos.json_depth(text) == 3


def test_json_nesting_at_the_limit_is_read(tmp_path):
    depth = yamlpos.MAX_DEPTH - 1
    path = tmp_path / "deep.json"
    path.write_text('{"x": ' + "[" * depth + "]" * depth + "}")
    assert read_json(path, "test") == json.loads(path.read_text())


@pytest.mark.parametrize("depth", [yamlpos.MAX_DEPTH + 1, 100_000])
def test_deep_json_is_refused_at_its_line(tmp_path, depth):
    """The decoder is never handed deeper nesting: 100,000 levels were a RecursionError inside json."""
    path = tmp_path / "deep.json"
    path.write_text('{"a": 1,\n "b": [' + "[" * depth + "]" * depth + "]}")
    with pytest.raises(InputError, match=rf"deep\.json:2: not valid JSON: lists and objects nested more "
                                         rf"than {yamlpos.MAX_DEPTH} deep"):
        read_json(path, "test")


@pytest.mark.parametrize("digits", [400, 5_000])
def test_huge_integers_are_numbers_out_of_range(tmp_path, capsys, digits):
    """A 400-digit cost was an OverflowError traceback; 5,000 digits passed
    Python's limit on integer strings (ValueError)."""
    path = scene_file(tmp_path, TOY.replace("grab: 5", "grab: " + "9" * digits))
    refused(capsys, ["solve", str(path)], f"toy.yaml:{line_number(TOY, 'primitives')}: primitives.grab: "
                                          "expected a finite number")
    costmap = (SCENES / "toy.costmap.json").read_text().replace('"cost": 4}', '"cost": ' + "9" * digits + "}", 1)
    path = tmp_path / "c.json"
    path.write_text(costmap)
    refused(capsys, ["solve", str(SCENES / "toy.yaml"), "--costmap", str(path)], "cost: expected a finite number")


@pytest.mark.parametrize("new, below, expected", [
    ("name: 2020-13-45", 0, "not valid YAML: '2020-13-45' is read as a date and is not one (month must be in "
                            "1..12); quote it if it is text"),
    ("name: toy\n? [2020-02-30]\n: 1", 1, "not valid YAML: a value in this key cannot be read"),
    ("name: toy\n? " + "9" * 5_000 + "\n: 1", 0, "(inf was unexpected)"),  # at the top mapping's line
])
def test_values_python_cannot_hold_are_named_at_their_line(tmp_path, capsys, new, below, expected):
    """A date that is none (`2020-13-45`, as YAML reads it unquoted) or an integer key of 5,000 digits
    were ValueError tracebacks."""
    path = scene_file(tmp_path, TOY.replace("name: toy", new))
    refused(capsys, ["solve", str(path)], f"toy.yaml:{line_number(TOY, 'name: toy') + below}: ", expected)


def test_a_file_beyond_the_size_limit_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(yamlpos, "MAX_BYTES", 100)
    refused(capsys, ["solve", str(SCENES / "toy.yaml")], f"scene {SCENES / 'toy.yaml'} is",
            "bytes: larger than the 100 symsynth reads")


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.yaml")), ids=lambda path: path.name)
def test_bundled_scenes_read_as_yaml_reads_them(path):
    data, lines = read_yaml(path, "scene")
    assert data == yaml.safe_load(path.read_text())
    text = path.read_text()
    for key in data:  # each top-level key at the line it is written on
        assert lines[(key,)] == line_number(text, f"{key}:")


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.json")), ids=lambda path: path.name)
def test_bundled_costmaps_read_as_json_reads_them(path):
    assert read_json(path, "costmap") == json.loads(path.read_text())


@pytest.mark.parametrize("argv", [["solve", "/dev/zero"],
                                  ["solve", str(SCENES / "toy.yaml"), "--costmap", "/dev/zero"]])
def test_a_file_without_a_size_is_read_no_further_than_the_limit(capsys, monkeypatch, argv):
    """A device or pipe has no size to check beforehand: /dev/zero was read until memory ran out
    (a MemoryError traceback, or the machine's memory)."""
    monkeypatch.setattr(yamlpos, "MAX_BYTES", 3000)  # toy.yaml has 2,184
    refused(capsys, argv, "/dev/zero is more than 3,000 bytes: larger than the 3,000 symsynth reads")


def test_a_pipe_within_the_limit_is_read(tmp_path):
    """Reading no further than the limit keeps what a device or pipe holds."""
    read, write = os.pipe()
    os.write(write, TOY.encode())
    os.close(write)
    with os.fdopen(read) as pipe:
        assert read_yaml(f"/dev/fd/{pipe.fileno()}", "scene")[0] == yaml.safe_load(TOY)


def test_line_ends_are_read_as_before(tmp_path):
    """Windows and old Mac line ends count as one line each, in YAML and JSON."""
    for end in ["\r\n", "\r"]:
        path = tmp_path / "crlf.yaml"
        path.write_bytes(TOY.replace("\n", end).encode())
        data, lines = read_yaml(path, "scene")
        assert data == yaml.safe_load(TOY)
        assert lines[("human",)] == line_number(TOY, "human")
