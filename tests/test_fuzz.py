"""Hostile input, generated: random bytes, structures mutated from the bundled
scenes, costmaps and strategy files, and random LTLf token sequences, each
fed to the command line in-process under a time bound.

The only outcomes allowed are a correct answer or a clear error: exit 2
with a message on stderr and no traceback (an exception escaping `main` is
a bug, and so is a case that runs past the time bound).  Where `solve`
answers, the answer is checked against the explicit solver on the same
input, so a mutation that slips through validation and changes the value
is caught too.

CI runs a few hundred cases, derandomized (the same cases every run);
`SYMSYNTH_FUZZ=N` runs N cases per target with fresh randomness.  Every
failure this suite finds becomes a named test (`tests/test_hostile.py`).
"""

from __future__ import annotations

import copy
import json
import os
import signal
from contextlib import contextmanager
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from support.paper import SCENES
from support.planar import PlanarPlanner, gap_scene
from symsynth.cli import main
from symsynth.errors import InputError, SymsynthWarning
from symsynth.planning.build import obtain_costmap
from symsynth.solvers import SOLVERS
from symsynth.scene import load_scene

FUZZ = int(os.environ.get("SYMSYNTH_FUZZ", "0"))
#: Seconds one case may take before it counts as a hang.
TIME_BOUND = 30


def cases(ci: int):
    """Hypothesis settings: `ci` derandomized cases, or SYMSYNTH_FUZZ random ones."""
    return settings(max_examples=FUZZ or ci, derandomize=not FUZZ, deadline=None, database=None,
                    suppress_health_check=list(HealthCheck))


class Hang(Exception):
    pass


@contextmanager
def time_bound(seconds: int = TIME_BOUND):
    def alarm(signum, frame):
        raise Hang(f"no answer within {seconds} s")
    old = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def run_cli(capsys, argv: list[str], allowed=(0, 2)) -> tuple[int, str, str]:
    """`symsynth ARGV` in-process: its exit code, stdout and stderr, checked
    to be an allowed code and, for 2, one clear message."""
    capsys.readouterr()
    with time_bound():
        code = main(argv)
    out, err = capsys.readouterr()
    assert code in allowed, (argv, code, err[-2000:])
    assert "Traceback" not in err, err[-2000:]
    if code == 2:
        assert err.startswith("symsynth") or err.startswith("usage:"), err[-2000:]
    return code, out, err


# -- values a mutation puts in ---------------------------------------------------

NAMES = st.sampled_from(["b", "w", "l1", "l2", "l3", "e1", "top", "Else", "Hand", "home", "empty",
                         "black", "white", "block", "", "../x", "a" * 300, "-", "b/top", "l1/top"])
NUMBERS = st.one_of(st.integers(-10, 10**6), st.sampled_from([0, -1, 10**400, 2**63, 1e308, -1e-300]),
                    st.floats(allow_nan=True, allow_infinity=True))
LEAVES = st.one_of(st.none(), st.booleans(), NUMBERS, NAMES, st.text(max_size=20))
VALUES = st.recursive(LEAVES, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                      st.dictionaries(NAMES, inner, max_size=4)),
                      max_leaves=10)


def paths(data, prefix=()):
    """Every key path in a JSON-like structure (the root included)."""
    yield prefix
    if isinstance(data, dict):
        for key, value in data.items():
            yield from paths(value, prefix + (key,))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            yield from paths(value, prefix + (i,))


@st.composite
def mutated(draw, original):
    """`original` with 1 to 3 random edits: a value replaced, a key or item
    deleted, a key added, a list item duplicated."""
    data = copy.deepcopy(original)
    for _ in range(draw(st.integers(1, 3))):
        places = list(paths(data))
        path = draw(st.sampled_from(places))
        if not path:
            if draw(st.integers(0, 9)) == 0:
                data = draw(VALUES)
            continue
        parent = data
        for key in path[:-1]:
            parent = parent[key]
        key = path[-1]
        edit = draw(st.sampled_from(["replace", "delete", "add", "duplicate"]))
        if edit == "replace":
            parent[key] = draw(VALUES)
        elif edit == "delete":
            del parent[key]
        elif edit == "add" and isinstance(parent[key], dict):
            parent[key][draw(NAMES)] = draw(VALUES)
        elif edit == "duplicate" and isinstance(parent[key], list) and parent[key]:
            parent[key].append(copy.deepcopy(parent[key][0]))
        else:
            parent[key] = draw(VALUES)
    return data


def dump(data) -> str:
    """YAML or JSON text of `data` (floats YAML cannot say as themselves kept)."""
    try:
        return yaml.safe_dump(data, allow_unicode=True)
    except yaml.YAMLError:
        return json.dumps(data)


TOY = yaml.safe_load((SCENES / "toy.yaml").read_text())
ARCH = yaml.safe_load((SCENES / "arch-abstract.yaml").read_text())
TOY_COSTMAP = json.loads((SCENES / "toy.costmap.json").read_text())


def scene_folder(tmp: Path) -> Path:
    for name in ("toy.costmap.json", "arch-abstract.costmap.json"):
        (tmp / name).write_text((SCENES / name).read_text())
    return tmp


def agrees_with_explicit(path: Path, out: str) -> None:
    """`solve --json`'s value equals the explicit solver's on the same scene."""
    answer = json.loads(out)
    scene = load_scene(path)
    with time_bound():
        explicit = SOLVERS["explicit"](scene, scene.task)
    assert answer["cost_bound"] == explicit.cost_bound, (answer["cost_bound"], explicit.cost_bound)


# -- the targets ---------------------------------------------------------------------

@cases(40)
@given(data=st.binary(max_size=400))
def test_random_bytes_as_a_scene(tmp_path_factory, capsys, data):
    path = tmp_path_factory.mktemp("bytes") / "scene.yaml"
    path.write_bytes(data)
    run_cli(capsys, ["solve", str(path)])


@cases(80)
@given(data=st.one_of(mutated(TOY), mutated(ARCH)))
def test_mutated_abstract_scenes(tmp_path_factory, capsys, data):
    path = scene_folder(tmp_path_factory.mktemp("scene")) / "scene.yaml"
    path.write_text(dump(data))
    code, out, _ = run_cli(capsys, ["solve", str(path), "--json", "--k", "1"])
    if code == 0:
        answer = json.loads(out)
        scene = load_scene(path)
        with time_bound():
            explicit = SOLVERS["explicit"](scene, scene.task, k=1)
        assert answer["cost_bound"] == explicit.cost_bound


@cases(60)
@given(data=mutated(TOY_COSTMAP))
def test_mutated_costmaps(tmp_path_factory, capsys, data):
    path = tmp_path_factory.mktemp("costmap") / "c.json"
    path.write_text(json.dumps(data))
    code, out, _ = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), "--costmap", str(path), "--json"])
    if code == 0:
        scene = load_scene(SCENES / "toy.yaml", costmap=path)
        with time_bound():
            explicit = SOLVERS["explicit"](scene, scene.task)
        assert json.loads(out)["cost_bound"] == explicit.cost_bound


TOKENS = ["F", "G", "X", "WX", "!", "&", "|", "->", "<->", "U", "R", "W", "(", ")", "true", "false",
          "last", "at(black, l3)", "at(white, l2)", "holding(b)", "occupied(l1)", "free(l2)", "at(b, Else)",
          "at(zz, l1)", "-", "(", "))", ",", "X[!]", "#", "\u00e9", "\n"]


@cases(80)
@given(tokens=st.lists(st.sampled_from(TOKENS), min_size=1, max_size=25))
def test_random_formulas(capsys, tokens):
    formula = " ".join(tokens)
    run_cli(capsys, ["dfa", "--", formula])
    code, out, _ = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), f"--task={formula}", "--json",
                                    "--k", "0"])
    if code == 0:
        scene = load_scene(SCENES / "toy.yaml")
        with time_bound():
            explicit = SOLVERS["explicit"](scene, formula, k=0)
        assert json.loads(out)["cost_bound"] == explicit.cost_bound


SYNTH_TOKENS = ["F", "G", "X", "X[!]", "WX", "!", "&&", "||", "->", "<->", "U", "R", "(", ")", "true",
                "false", "a", "b", "c", "d", "at(a, l)", "", "\u00e9", "\n", ";", "p_1"]
PART_LINES = [".inputs: a", ".outputs: b", ".inputs: a b", ".outputs: c d", ".inputs:", ".outputs:",
              ".inputs: a\t c", "inputs: a", ".outputs b", ".inputs: a a", ".outputs: a", ".other: x",
              "# a comment", "", "   ", ".inputs: \u00e9", ".outputs: p_1 at(a, l)", "\x00"]


@cases(60)
@given(tokens=st.lists(st.sampled_from(SYNTH_TOKENS), min_size=0, max_size=20),
       part=st.lists(st.sampled_from(PART_LINES), min_size=0, max_size=5),
       flags=st.lists(st.sampled_from(["--env-first", "--agent-first", "--next=weak", "--next=strong",
                                       "--strategy=bdd", "--strategy=machine"]), max_size=2))
def test_synth_on_random_specs_and_partitions(tmp_path_factory, capsys, tokens, part, flags):
    """`synth` on random formulas and partition files: a verdict (SYNTCOMP's
    10 or 20) or a clear message (2), never a traceback."""
    folder = tmp_path_factory.mktemp("synth")
    (folder / "s.ltlf").write_text(" ".join(tokens))
    (folder / "s.part").write_text("\n".join(part))
    code, out, _ = run_cli(capsys, ["synth", str(folder / "s.ltlf"), "--part", str(folder / "s.part"),
                                    *flags, "-o", str(folder / "out.json")], allowed=(10, 20, 2))
    if code in (10, 20):
        assert out.splitlines()[0] == ("REALIZABLE" if code == 10 else "UNREALIZABLE")


@pytest.fixture(scope="module")
def toy_strategy(tmp_path_factory) -> dict:
    path = tmp_path_factory.mktemp("strategy") / "toy.strategy.json"
    assert main(["solve", str(SCENES / "toy.yaml"), "-o", str(path)]) == 0
    return json.loads(path.read_text())


@cases(40)
@given(data=st.data())
def test_mutated_strategy_files_are_read_or_refused(tmp_path_factory, capsys, toy_strategy, data):
    """Strategy files are read by simulate, on physical scenes only; here
    the reader and the certificate check (what simulate runs first) meet
    the toy's strategy file, mutated: refused with a message, or certified."""
    from symsynth.errors import SymsynthError
    from symsynth.game.strategy import certify, read_strategy

    mutant = data.draw(mutated(toy_strategy))
    path = tmp_path_factory.mktemp("strategy") / "s.json"
    path.write_text(json.dumps(mutant))
    scene = load_scene(SCENES / "toy.yaml")
    with time_bound():
        try:
            table = read_strategy(path)
            certify(scene, table)
        except SymsynthError as error:
            assert str(error)
            return
    # certified: what it claims holds against the explicit solver
    explicit = SOLVERS["explicit"](scene, table.task, k=table.k, resolution=table.resolution)
    assert table.units is None or explicit.units <= table.units


# -- what an independent fuzzer found (issue 33), one named case each ---------------------

def toy_with_costs(folder: Path, cost, *, grab=None, drop=None) -> Path:
    """The toy with every costmap rule costing `cost` and grab/drop `cost`
    (or `grab`, `drop`), written as the literal numbers given."""
    costmap = copy.deepcopy(TOY_COSTMAP)
    for motion in costmap["motions"]:
        for rule in motion["rules"]:
            rule["cost"] = cost
    (folder / "c.json").write_text(json.dumps(costmap))
    scene = dict(TOY, costmap="c.json",
                 primitives={"grab": cost if grab is None else grab, "drop": cost if drop is None else drop})
    path = folder / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))  # integers in full, 1e308 as 1.0e+308
    return path


BIG = 2 ** 53 + 1  # 9007199254740993: no float holds it


@pytest.mark.parametrize("solver", ["explicit", "symbolic", "forward"])
def test_integer_costs_past_2_53_are_exact(tmp_path, capsys, solver):
    """Every toy cost 2^53 + 1: with k = 0 the plan is transit, grab,
    transfer, drop (the toy's comment), so E_p = 4 (2^53 + 1) exactly; read
    as floats the costs were 2^53 and E_p 4 units too low."""
    path = toy_with_costs(tmp_path, BIG)
    _, out, _ = run_cli(capsys, ["solve", str(path), "--k", "0", "--json", "--solver", solver])
    answer = json.loads(out)
    assert answer["units"] == 4 * BIG
    assert answer["cost_bound"] == 4 * BIG


def test_a_budget_just_below_an_exact_large_value_is_not_met(tmp_path, capsys):
    """grab 2^53 + 1, drop 0, k = 0: E_p = 4 + (2^53 + 1) + 3 + 0 =
    9007199254741000; the budget 9007199254740999 is one unit short (it was
    called realizable when the grab was read as the float 2^53)."""
    path = toy_with_costs(tmp_path, 1, grab=BIG, drop=0)
    costmap = json.loads((tmp_path / "c.json").read_text())
    costmap["motions"] = TOY_COSTMAP["motions"]  # the toy's own motions: transit 4, transfer 3
    (tmp_path / "c.json").write_text(json.dumps(costmap))
    for budget, realizable in (("9007199254740999", False), ("9007199254741000", True)):
        _, out, _ = run_cli(capsys, ["solve", str(path), "--k", "0", "--json", "--budget", budget])
        answer = json.loads(out)
        assert (answer["cost_bound"], answer["realizable"]) == (9007199254741000, realizable)


def test_the_budget_is_read_as_the_exact_decimal_written(capsys):
    """The toy's E_p with k = 1 is 50 (its comment solves it by hand): a
    budget of 49.99999999999999999999 is below it, although the float
    nearest that decimal is 50.0."""
    _, out, _ = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), "--json", "--budget",
                                 "49.99999999999999999999"])
    assert json.loads(out)["realizable"] is False
    _, out, _ = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), "--budget", "49.99999999999999999999"])
    assert "not realizable within budget 49.99999999999999999999" in out


def test_an_e_p_beyond_the_float_range_is_exact(tmp_path, capsys):
    """Every cost 1e308: E_p is the number of actions the worst play needs
    (the same game with every cost 1) times 10^308, past a float's range
    (the explicit solver overflowed)."""
    _, out, _ = run_cli(capsys, ["solve", str(toy_with_costs(tmp_path, 1)), "--json", "--solver", "explicit"])
    actions = json.loads(out)["cost_bound"]
    huge = toy_with_costs(tmp_path, 1e308)
    _, out, _ = run_cli(capsys, ["solve", str(huge), "--json", "--solver", "explicit"])
    assert json.loads(out)["cost_bound"] == actions * 10 ** 308
    _, out, _ = run_cli(capsys, ["solve", str(huge), "--solver", "explicit"])
    assert f"E_p        {actions * 10 ** 308}" in out


def test_the_forward_search_is_not_led_around_a_cheap_cycle(tmp_path):
    """The toy with k = 1 and grab 10^6: the value needs three grabs, the
    lower bound sees one, and two transits between the objects (2 units
    each) form a cycle whose lo each failed question raised by its cost
    only: 1.5 million rounds before the answer.  Solving the generated
    graph's Bellman equations (`Search._tighten`) lifts the cycle at once."""
    scene = dict(TOY, primitives={"grab": 10 ** 6, "drop": 5})
    path = scene_folder(tmp_path) / "scene.yaml"
    path.write_text(yaml.safe_dump(scene))
    loaded = load_scene(path)
    with time_bound():
        found = SOLVERS["forward"](loaded, k=1)
    assert found.units == SOLVERS["explicit"](loaded, k=1).units == 3 * 10 ** 6 + 35
    assert found.stats["rounds"] < 1000


# -- findings of the independent fuzzer, kept as named cases ---------------------------------

@pytest.mark.parametrize("primitive, cost", [("grab", 1e25), ("drop", 1.7e308), ("grab", 2.0 ** 63)])
def test_compiled_refuses_an_action_cost_beyond_its_integers(tmp_path, capsys, primitive, cost):
    """A grab or drop cost beyond int64 once in units raised OverflowError in
    the compiled solver's tables, before its own refusal: now `--solver
    compiled` refuses with the reason (exit 2), and the explicit solver
    answers with the cost counted exactly (up to 1e25 here: its E_p beyond
    the float range is another finding, fixed apart)."""
    scene_folder(tmp_path)
    data = copy.deepcopy(TOY) | {"primitives": dict(TOY["primitives"]) | {primitive: cost}}
    (tmp_path / "toy.yaml").write_text(yaml.safe_dump(data))
    code, _, err = run_cli(capsys, ["solve", str(tmp_path / "toy.yaml"), "--solver", "compiled"])
    assert code == 2 and f"a move ({primitive}) costs" in err and "--solver explicit" in err
    if cost <= 1e25:
        with time_bound():
            exact = SOLVERS["explicit"](load_scene(tmp_path / "toy.yaml"))
        assert exact.units is not None and exact.units >= int(cost)  # the toy's plays all grab and drop


def test_compiled_refuses_64_places_and_auto_falls_back(capsys, tmp_path):
    """64 locations and Else samples overflowed the compiled solver's free
    places mask (`samples_mask`, a traceback): now it refuses with the
    reason, and `auto` hands the game on and answers the explicit value."""
    from support.games import make_scene

    locations = [f"l{i}" for i in range(1, 64)]
    motions = {("empty", start, "l1/top"): 3 for start in ["home"] + [f"{x}/top" for x in locations[1:] + ["e1"]]}
    scene = make_scene({"b": "l1"}, locations, motions | {("b/top", "l1/top", "l63/top"): 4},
                       else_samples=["e1"], task="F(at(b, l63))")
    with pytest.raises(InputError, match="at most 62 locations and Else samples; this scene has 64"):
        SOLVERS["compiled"](scene)
    with time_bound():
        fallback = SOLVERS["auto"](scene)
        exact = SOLVERS["explicit"](scene)
    assert fallback.stats["auto"] != "compiled" and "compiled refused it" in fallback.stats["auto_reason"]
    assert fallback.units == exact.units == 3 + 5 + 4 + 5


def test_a_cache_entry_edited_under_its_key_is_computed_again(tmp_path, monkeypatch):
    """Every cost x100 with the key kept: the checksum of the content no
    longer matches, so the entry is not trusted (issue 33's fuzzer)."""
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path))
    scene = gap_scene()
    first = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    data = json.loads(first.path.read_text())
    for motion in data["motions"]:
        for rule in motion["rules"]:
            rule["cost"] *= 100
    first.path.write_text(json.dumps(data))
    with pytest.warns(SymsynthWarning, match="is not used and is computed again: .*checksum"):
        again = obtain_costmap(scene, "sg", "planar", progress=False, planner_factory=PlanarPlanner)
    assert not again.cached and again.costmap == first.costmap


def test_no_output_is_written_over_an_input(tmp_path, capsys):
    """`-o scene.yaml` put the strategy in place of the scene; the scene's
    costmap file and --costmap's are inputs too.  Each stays as it was."""
    folder = scene_folder(tmp_path)
    scene = folder / "toy.yaml"
    scene.write_text((SCENES / "toy.yaml").read_text())
    for output, extra in ((scene, []), (folder / "toy.costmap.json", []),
                          (folder / "arch-abstract.costmap.json", ["--costmap", str(folder / "arch-abstract.costmap.json")])):
        before = output.read_text()
        code, _, err = run_cli(capsys, ["solve", str(scene), *extra, "-o", str(output)], allowed=(2,))
        assert "it is this command's input" in err and output.read_text() == before


def test_a_read_only_output_is_not_replaced(tmp_path, capsys):
    """The atomic write renames over the target, which a read-only file does
    not stop (the folder is writable): refused, the file unchanged."""
    output = tmp_path / "kept.json"
    output.write_text("mine")
    output.chmod(0o444)
    _, _, err = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), "-o", str(output)], allowed=(2,))
    assert "read-only" in err and output.read_text() == "mine"


def test_an_empty_output_name_is_refused_as_empty(capsys):
    """`-o ""` was reported as `.` (Path('') is the current folder)."""
    _, _, err = run_cli(capsys, ["solve", str(SCENES / "toy.yaml"), "-o", ""], allowed=(2,))
    assert "empty" in err and "write strategy file ." not in err


@pytest.mark.parametrize("role", ["scene", "costmap"])
def test_a_named_pipe_with_no_writer_is_refused_not_waited_on(tmp_path, capsys, role):
    """`open` of a FIFO nobody writes to blocks for ever: it is opened
    without waiting, and refused when nothing comes (a pipe that is being
    written is read: tests/test_loaders.py)."""
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    argv = ["solve", str(fifo)] if role == "scene" else ["solve", str(SCENES / "toy.yaml"), "--costmap", str(fifo)]
    _, _, err = run_cli(capsys, argv, allowed=(2,))
    assert f"{fifo} is a named pipe and nothing was written to it" in err


def test_a_scene_without_a_costmap_is_named_by_its_file(tmp_path, capsys):
    scene = {key: value for key, value in TOY.items() if key != "costmap"}
    path = tmp_path / "bare.yaml"
    path.write_text(yaml.safe_dump(scene))
    _, _, err = run_cli(capsys, ["solve", str(path)], allowed=(2,))
    assert f"{path}: scene 'toy' has no costmap" in err


def test_a_human_k_too_large_is_named_by_file_and_line(tmp_path, capsys):
    """The toy's value grows by 27 units a move, so a k past the layers
    solved one by one is refused: the message says where that k is written
    (the scene's human.k, or --k)."""
    path = scene_folder(tmp_path) / "scene.yaml"
    text = (SCENES / "toy.yaml").read_text().replace("human: {k: 1}", "human: {k: 100000}")
    path.write_text(text)
    line = text.splitlines().index("human: {k: 100000}") + 1
    _, _, err = run_cli(capsys, ["solve", str(path), "--solver", "explicit"], allowed=(2,))
    assert err.startswith(f"symsynth solve: {path}:{line}: human.k: k = 100000:")
    _, _, err = run_cli(capsys, ["solve", str(path), "--solver", "explicit", "--k", "300"], allowed=(2,))
    assert err.startswith("symsynth solve: --k: k = 300:")


@pytest.mark.parametrize("name", ["Else", "Hand", "home"])
def test_an_else_sample_may_not_take_a_reserved_name(tmp_path, capsys, name):
    """`else_samples: [Else]` was accepted: an anchor `Else/top`, and a
    sample named like the place it samples (or the hand, or the robot's
    home anchor).  Refused at its line, as such a location is."""
    path = scene_folder(tmp_path) / "scene.yaml"
    text = (SCENES / "toy.yaml").read_text().replace("else_samples: [e1]", f"else_samples: [{name}]")
    path.write_text(text)
    line = text.splitlines().index(f"else_samples: [{name}]") + 1
    _, _, err = run_cli(capsys, ["solve", str(path)], allowed=(2,))
    assert f"{path}:{line}: else_samples.0: '{name}' is reserved and cannot name an Else sample" in err


def test_a_scene_of_thousands_of_objects_is_refused_at_once(tmp_path):
    """5,000 objects ran with no progress and no end; a scene has at most
    MAX_OBJECTS (docs/input-limits.md), and the refusal says so."""
    from symsynth.errors import InputError
    from symsynth.scene.load import MAX_OBJECTS

    def with_objects(n: int) -> Path:
        objects = dict(TOY["objects"]) | {f"o{i}": {"tags": ["block"]} for i in range(n - len(TOY["objects"]))}
        path = scene_folder(tmp_path) / f"scene{n}.yaml"
        path.write_text(yaml.safe_dump(dict(TOY, objects=objects)))
        return path

    assert len(load_scene(with_objects(MAX_OBJECTS)).objects) == MAX_OBJECTS
    with pytest.raises(InputError, match=f"{MAX_OBJECTS + 1} objects: symsynth solves games of at most {MAX_OBJECTS}"):
        load_scene(with_objects(MAX_OBJECTS + 1))
