"""The physical world (`execution/physics.py`, `simulate --world physics`):
grasps held by the fingers, drops that settle, pushes that move the object
only by contact, and a bad slide caught by the simulator.

What is checked is read from PyBullet apart from the code under test:
object positions from `getBasePositionAndOrientation`, contacts from
`getContactPoints`, masses from `getDynamicsInfo`; targets are the scene's
own poses.  Small sizes: 60-vertex roadmaps, a few hundred steps a motion.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from symsynth.cli import main
from symsynth.errors import InputError
from symsynth.execution import hand_motions, physics
from symsynth.execution.observe import POSITION
from symsynth.execution.physics import ARRIVED, PASSING, PhysicsWorld, Randomization
from symsynth.execution.reach import reach
from symsynth.execution.world_choice import default_world
from symsynth.execution.simulate import MAX_VISITS
from symsynth.execution.trial import slide_trial, slide_trials
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.registry import planner_class
from symsynth.primitive_registry import displacement
from symsynth.scene import load_scene, scene_from_data
from symsynth.scene.geometry import Pose

DATA = Path(__file__).parent / "data"

BLOCK = """
name: grasp
robot: {}
obstacles:
  table: {box: [1.0, 1.2, 0.04], xyz: [0.35, 0.0, -0.04], physics: {friction: 0.6}}
objects:
  b: {tags: [block], box: [0.04, 0.04, 0.06], at: l1, physics: {mass: 0.07}}
locations:
  l1: {xyz: [0.5, 0.0, 0.0]}
  l2: {xyz: [0.5, 0.15, 0.0]}
grasps:
  top: {xyz: [0.0, 0.0, 0.1434], rpy: [3.14159265, 0.0, 0.0], approach: 0.07}
planner: {name: ompl-fcl, roadmap_size: 60}
task: F(at(b, l2))
"""


@pytest.fixture(scope="module")
def block():
    scene = scene_from_data(yaml.safe_load(BLOCK))
    return scene, planner_class("ompl-fcl")(scene)


def base_xyz(world, name):
    """Where PyBullet has the object's bottom face centre (its frame)."""
    xyz, _ = world.client.getBasePositionAndOrientation(world.bodies[name])
    return xyz[0], xyz[1], xyz[2] - world.geometry.shapes[name].size[2] / 2


def at_anchor(scene, planner, place, **options):
    """A physical world with the robot on the top grasp's anchor over `place`, settled."""
    world = PhysicsWorld(scene, **options)
    g = scene.geometry
    world.set_config(planner.inverse_kinematics(g.places[place] @ g.grasps["top"].pre_image(), g.robot.home))
    world.settle()
    return world


def test_the_scene_s_physics_block_sets_mass_and_friction(block):
    scene, _ = block
    world = PhysicsWorld(scene)
    try:
        info = world.client.getDynamicsInfo(world.bodies["b"], -1)
        assert info[0] == pytest.approx(0.07) and info[1] == pytest.approx(0.5)  # mass given, friction default
        table = next(body for body, name in world.obstacles.items() if name == "table")
        assert world.client.getDynamicsInfo(table, -1)[1] == pytest.approx(0.6)
    finally:
        world.close()


@pytest.mark.parametrize("change, message", [
    (lambda d: d["objects"]["b"].update(physics={"mass": 0}), "objects.b.physics.mass"),
    (lambda d: d["objects"]["b"].update(physics={"weight": 1}), "objects.b.physics"),
    (lambda d: d["obstacles"]["table"].update(physics={"mass": 3}), "obstacles.table.physics"),
    (lambda d: d["objects"]["b"].update(physics={"friction": -0.1}), "objects.b.physics.friction"),
])
def test_a_bad_physics_block_is_named(change, message):
    data = yaml.safe_load(BLOCK)
    change(data)
    with pytest.raises(InputError, match=message.replace(".", r"\.")):
        scene_from_data(data)


def test_a_grasp_lifts_the_object_with_the_fingers_and_the_constraint_keeps_it_in_place(block):
    """Closed on the block, both fingers touch it and it rises with the hand
    (the approach's 7 cm), with the firming constraint or without it
    (`firm=False`): the fingers lift it.  Carried 15 cm to l2's anchor, the
    block held by the constraint is within 1 mm of where the grasp puts it
    in the hand (read from PyBullet); held by the fingers' friction alone it
    slips more than half the observation's 1 cm (PyBullet's friction grasp;
    6.5 mm, 1.4 cm when a path stopped at once), so a drop would set it off
    its place by that much: what the constraint is there for
    (docs/simulation.md)."""
    scene, planner = block
    g = scene.geometry
    for firm in (True, False):
        world = at_anchor(scene, planner, "l1", firm=firm)
        try:
            approaches = hand_motions.Approaches(planner)
            hand_motions.grab(world, approaches, "b", "top")
            assert world.held == "b"
            assert all(world.client.getContactPoints(world.robot, world.bodies["b"], j, -1) for j in world.fingers)
            assert base_xyz(world, "b")[2] == pytest.approx(0.07, abs=0.01)
            assert (world._constraint is not None) == firm
            world.follow(approaches.path(world.config, world.ee_pose(),
                                         g.places["l2"] @ g.grasps["top"].pre_image(), "carry"))
            state = world.client.getLinkState(world.robot, world.ee_link, computeForwardKinematics=True)
            in_hand = (Pose(tuple(state[4]), tuple(state[5])) @ g.grasps["top"].pose.inverse()).xyz
            slip = math.dist(base_xyz(world, "b"), in_hand)
            assert slip < 0.001 if firm else slip > POSITION / 2
        finally:
            world.close()


def counted_approaches(planner):
    """`hand_motions.Approaches` over `planner`, and the list of the poses
    it solves inverse kinematics for."""
    solved = []

    class Counting:
        def inverse_kinematics(self, pose, seed):
            solved.append(pose)
            return planner.inverse_kinematics(pose, seed)

    return hand_motions.Approaches(Counting()), solved


def test_an_object_a_few_millimetres_off_its_place_is_approached_with_one_solution(block):
    """`Approaches.near`: the place's approach (solved once) bent toward
    the grasp pose on the object where it really stands, 5 mm and 0.03 rad
    off: one inverse kinematics solution, and the hand (forward kinematics
    in PyBullet) goes straight from the anchor to the grasp pose on the
    moved object, each configuration within 1 mm of its point on that
    segment, the last on the grasp pose."""
    scene, planner = block
    g = scene.geometry
    grasp, place = g.grasps["top"], g.places["l1"]
    moved = Pose((0.503, -0.004, 0.0), (0.0, 0.0, math.sin(0.015), math.cos(0.015)))
    approaches, solved = counted_approaches(planner)
    world = at_anchor(scene, planner, "l1")
    try:
        approaches.path(world.config, place @ grasp.pre_image(), place @ grasp.pose, "down")
        solved.clear()
        down = approaches.near(world.config, place, moved, grasp, "down")
        assert len(solved) == 1 and len(down) == hand_motions.APPROACH_STEPS + 1
        start, end = (place @ grasp.pre_image()).xyz, (moved @ grasp.pose).xyz
        for i, config in enumerate(down):
            world.set_config(config)
            t = i / (len(down) - 1)
            assert math.dist(world.ee_pose().xyz, [a + (b - a) * t for a, b in zip(start, end)]) < 1e-3
        assert world.ee_pose().angle_to(moved @ grasp.pose) < 0.01
    finally:
        world.close()


def test_newton_steps_reach_a_grasp_pose_a_few_millimetres_off(block):
    """`reach` from the place's approach's end to the grasp pose on the block
    moved 5 mm and turned 0.03 rad: the hand (PyBullet's forward
    kinematics) on the pose to 1e-6 m, the joints within 1 mrad of the
    planner's own solution from the same seed; a pose 2 m off is not
    reached (None), and the robot stands where it stood."""
    scene, planner = block
    g = scene.geometry
    grasp, place = g.grasps["top"], g.places["l1"]
    world = at_anchor(scene, planner, "l1")
    try:
        end = hand_motions.Approaches(planner).path(world.config, place @ grasp.pre_image(), place @ grasp.pose,
                                                    "down")[-1]
        hand = Pose((0.503, -0.004, 0.0), (0.0, 0.0, math.sin(0.015), math.cos(0.015))) @ grasp.pose
        stood = world.config
        found = reach(world, end, hand)
        assert found is not None and world.config == stood
        assert np.max(np.abs(np.subtract(found, planner.inverse_kinematics(hand, end)))) < 1e-3
        world.set_config(found)
        assert math.dist(world.ee_pose().xyz, hand.xyz) < 1e-6 and world.ee_pose().angle_to(hand) < 1e-5
        assert reach(world, end, Pose((2.5, 0.0, 0.1)) @ grasp.pose) is None
    finally:
        world.close()


def test_a_physical_grab_of_a_moved_object_solves_no_inverse_kinematics(block):
    """The block put 4 mm off its place: the grab bends the place's approach
    by `reach`, not by the planner's inverse kinematics (no pose solved
    once the place's approach is), and the fingers hold it."""
    scene, planner = block
    g = scene.geometry
    grasp, place = g.grasps["top"], g.places["l1"]
    approaches, solved = counted_approaches(planner)
    world = at_anchor(scene, planner, "l1")
    try:
        world.place("b", Pose((0.503, -0.003, 0.0)))
        approaches.path(world.config, place @ grasp.pre_image(), place @ grasp.pose, "down")
        solved.clear()
        hand_motions.grab(world, approaches, "b", "top")
        assert solved == [] and world.held == "b"
    finally:
        world.close()


def test_an_object_that_has_not_moved_from_its_place_is_approached_as_planned(block):
    """An object 0.05 mm off its place (the grasp pose within `SAME_HAND`,
    0.1 mm and 1 mrad): `Approaches.near` gives the place's approach itself
    and solves nothing."""
    scene, planner = block
    g = scene.geometry
    grasp, place = g.grasps["top"], g.places["l1"]
    approaches, solved = counted_approaches(planner)
    home = tuple(g.robot.home)
    nominal = approaches.path(home, place @ grasp.pre_image(), place @ grasp.pose, "down")
    solved.clear()
    moved = Pose((0.50004, 0.00003, 0.0), (0.0, 0.0, 0.0, 1.0))
    assert approaches.near(home, place, moved, grasp, "down") == nominal and solved == []


def test_a_leg_goes_at_the_full_velocity_limit_only_where_it_is_clear(block, monkeypatch):
    """A leg that swings the arm 1.2 rad about its base from the anchor over
    the block: with `clear`, its pieces where the fingers are within `CLEAR`
    of the block (the first ones; `CLEAR` set to 5 cm here, which the
    fingers at the anchor are within) and its last piece go at half the
    velocity limit, the pieces between at the full limit (joined: a piece
    at each speed in turn, longer than `CLEAR_STRIDE`), so it takes fewer
    steps than without `clear` (where a whole leg, or a path's last, went
    at half the limit)."""
    monkeypatch.setattr(physics, "CLEAR", 0.05)
    scene, planner = block
    worlds = [at_anchor(scene, planner, "l1") for _ in range(2)]
    try:
        start = np.asarray(worlds[0].config)
        path = [tuple(start), tuple(start + np.eye(len(start))[0] * 1.2)]
        configs, _, _, far = worlds[0]._clear_pieces(np.asarray(path), [False], [0.0])
        assert not far[0] and any(far) and not far[-1]
        assert all(a != b for a, b in zip(far, far[1:]))  # a piece at each speed, in turn
        assert np.allclose(configs[-1], path[-1]) and 1.2 / len(far) > physics.CLEAR_STRIDE
        taken = []
        for world, clear in zip(worlds, (True, False)):
            before = world.steps
            world.follow(path, clear=clear)
            taken.append(world.steps - before)
        assert taken[0] < 0.8 * taken[1]
    finally:
        for world in worlds:
            world.close()


def held_after_a_nudge(world, goal, passing):
    """The steps `follow` holds the robot on `goal` (a one-configuration
    path) after its first joint was put 10 mrad off it."""
    state = world.client.getJointState(world.robot, world.joints[0])
    world.client.resetJointState(world.robot, world.joints[0], state[0] + 0.01)
    before = world.steps
    world.follow([goal], passing=passing)
    return world.steps - before


def test_a_path_s_end_is_held_loosely_only_with_the_hand_empty_and_touching_nothing(block):
    """With `passing`, an empty hand 10 mrad off its path's end is not held
    (it is within `PASSING`); without, it is held until every joint is
    within `ARRIVED`.  The hand holding the block is held to `ARRIVED` with
    `passing` too (what a drop depends on)."""
    scene, planner = block
    g = scene.geometry
    worlds = [at_anchor(scene, planner, "l2") for _ in range(2)]
    try:
        goal = worlds[0].config
        taken = [held_after_a_nudge(world, goal, passing) for world, passing in zip(worlds, (True, False))]
        assert taken[0] == 0 < taken[1]
        assert ARRIVED < worlds[0].tracking_error(goal) <= PASSING
        assert worlds[1].tracking_error(goal) <= ARRIVED
        world = at_anchor(scene, planner, "l1")
        worlds.append(world)
        approaches = hand_motions.Approaches(planner)
        hand_motions.grab(world, approaches, "b", "top")
        assert world.held == "b"
        carry = approaches.path(world.config, world.ee_pose(), g.places["l2"] @ g.grasps["top"].pre_image(), "carry")
        world.follow(carry, passing=True)
        assert held_after_a_nudge(world, carry[-1], True) > 0
        assert world.tracking_error(carry[-1]) <= ARRIVED
    finally:
        for world in worlds:
            world.close()


def test_a_path_s_last_leg_slows_to_rest():
    """The targets of a path's last leg go the whole leg, never back, and
    slow to rest: the speed falls evenly to 0 over `STOP_STEPS`, and each
    step goes as far as its mean speed says."""
    for n in (1, 3, 4, 10, 100):
        fractions, rates = physics._stopping(n)
        assert fractions[-1] == pytest.approx(1.0) and rates[-1] == 0.0
        assert np.all(np.diff(fractions) > 0) and np.all(np.diff(rates) <= 0)
        assert len(fractions) == math.ceil(n + min(physics.STOP_STEPS, 2 * n) / 2)
        steps = np.diff(np.concatenate([[0.0], fractions]))
        mean = (np.concatenate([[1.0], rates[:-1]]) + rates) / 2  # the leg starts at its speed
        assert steps == pytest.approx(mean / n, abs=1e-12)


def test_an_arm_slowed_to_rest_needs_no_hold(block, monkeypatch):
    """Swung 0.6 rad about its base, the arm whose last leg slows to rest
    ends within `ARRIVED` of the path with no step held; stopped at once
    (every leg steady) it overshoots and is held longer than the slowing
    took, so the path takes more steps."""
    scene, planner = block
    taken = []
    for stopping in (physics._stopping, physics._steady):
        monkeypatch.setattr(physics, "_stopping", stopping)
        world = at_anchor(scene, planner, "l2")
        try:
            start = np.asarray(world.config)
            path = [tuple(start), tuple(start + np.eye(len(start))[0] * 0.6)]
            before = world.steps
            world.follow(path)
            taken.append(world.steps - before)
            assert world.tracking_error(path[-1]) <= ARRIVED
        finally:
            world.close()
    legs = math.ceil(0.6 / world._speeds[0] / physics.TIME_STEP)
    assert taken[0] == legs + physics.STOP_STEPS // 2 < taken[1]


def test_fingers_that_close_on_nothing_make_no_constraint(block):
    """The hand closes at l1's grasp pose while the block stands at l2: no
    finger touches it, nothing is firmed, the block stays on the table."""
    scene, planner = block
    world = at_anchor(scene, planner, "l1")
    try:
        world.place("b", scene.geometry.places["l2"])
        g = scene.geometry
        down = hand_motions.Approaches(planner).path(world.config, g.places["l1"] @ g.grasps["top"].pre_image(),
                                                   g.places["l1"] @ g.grasps["top"].pose, "down")
        world.follow(down)
        assert not world.close_hand("b", "top")
        assert world.held is None and world._constraint is None
        world.follow(down[::-1])
        assert math.dist(base_xyz(world, "b"), g.places["l2"].xyz) < 1e-3
    finally:
        world.close()


def test_a_drop_releases_the_object_and_it_settles_within_the_tolerance(block):
    """Grabbed at l1, carried to l2's anchor, dropped: the constraint is
    gone, the hand empty, and the block rests on l2 (within observe's 1 cm),
    upright, its speed zero."""
    scene, planner = block
    world = at_anchor(scene, planner, "l1")
    try:
        approaches = hand_motions.Approaches(planner)
        hand_motions.grab(world, approaches, "b", "top")
        g = scene.geometry
        world.follow(approaches.path(world.config, world.ee_pose(), g.places["l2"] @ g.grasps["top"].pre_image(),
                                     "carry"))
        hand_motions.drop(world, approaches, "l2")
        assert world.held is None and world._constraint is None
        assert world.client.getNumConstraints() == 0
        assert math.dist(base_xyz(world, "b"), g.places["l2"].xyz) <= POSITION
        _, quat = world.client.getBasePositionAndOrientation(world.bodies["b"])
        assert Pose((0, 0, 0), tuple(quat)).angle_to(Pose()) < 0.05
        assert max(map(abs, world.client.getBaseVelocity(world.bodies["b"])[0])) < 0.01
    finally:
        world.close()


def test_a_human_puts_an_object_only_where_it_stands(block):
    """A second block on the first stands; 6 cm above it (in the air) or
    3 cm beside its centre (its own centre 1 cm past the edge) it would fall
    or tip, so it does not stand; on the table it stands.  With the second
    block on the first, the first cannot be taken away.  Asking moves
    nothing: the blocks are where they were, to the float."""
    scene, _ = block
    data = yaml.safe_load(BLOCK)
    data["objects"]["c"] = {"tags": ["block"], "box": [0.04, 0.04, 0.06], "at": "l2"}
    world = PhysicsWorld(scene_from_data(data))
    try:
        before = {name: base_xyz(world, name) for name in ("b", "c")}
        x, y, _ = before["b"]
        assert world.stands("c", Pose((x, y, 0.06)))
        assert not world.stands("c", Pose((x, y, 0.12)))
        assert not world.stands("c", Pose((x, y + 0.03, 0.06)))
        assert world.stands("c", Pose((x, y - 0.15, 0.0)))
        world.place("c", Pose((x, y, 0.06)))
        stacked = {name: base_xyz(world, name) for name in ("b", "c")}
        assert not world.stands("b", Pose((x, y + 0.15, 0.0)))  # c stands on b
        assert world.stands("c", Pose((x, y + 0.15, 0.0)))
        assert {name: base_xyz(world, name) for name in ("b", "c")} == stacked
    finally:
        world.close()


def test_an_object_at_rest_sleeps_and_an_object_put_somewhere_wakes(block):
    """After 2.5 s at rest the block sleeps: a velocity set on it from
    outside (which wakes nothing) does not move it.  Put 5 cm above its
    place, it is awake and falls back onto the table; a human's move into
    the air is seen not to stand."""
    scene, _ = block
    world = PhysicsWorld(scene)
    try:
        body, place = world.bodies["b"], scene.geometry.places["l1"]
        for _ in range(600):
            world.step()
        before = base_xyz(world, "b")
        world.client.resetBaseVelocity(body, [0.1, 0.0, 0.0], [0.0, 0.0, 0.0])
        for _ in range(24):
            world.step()
        assert math.dist(base_xyz(world, "b"), before) < 1e-4
        for _ in range(600):
            world.step()
        assert not world.stands("b", place @ Pose((0.0, 0.0, 0.05)))
        for _ in range(600):
            world.step()
        world.place("b", place @ Pose((0.0, 0.0, 0.05)))
        assert abs(base_xyz(world, "b")[2]) < 1e-3
    finally:
        world.close()


@pytest.fixture(scope="module")
def push_rule():
    data = yaml.safe_load((DATA / "push-small.yaml").read_text())
    scene = scene_from_data(data, source=DATA / "push-small.yaml")
    planner = planner_class("ompl-fcl")(scene)
    (rule,) = displacement("push").slides(scene, planner, "behind", anchor_configs(planner, scene))
    return scene, rule


def test_a_push_moves_the_box_only_while_the_hand_touches_it(push_rule):
    """Every step of the slide is watched (PyBullet's contact points between
    robot and box): the box travels l1 -> l2 (18 cm) at steps when the hand
    touches it (or did within 0.1 s), next to nothing otherwise, and ends
    within the tolerance of l2; randomized worlds too."""
    scene, rule = push_rule
    for seed in (0, 1):
        out = slide_trial(scene, "box", "behind", rule.start, rule.goal, rule.path,
                          randomization=Randomization(friction=0.2, mass=0.2, pose=0.005), seed=seed)
        assert out.pushed >= 0.17 and out.untouched < 0.002, out
        assert out.success and out.error <= POSITION and out.jump < 0.005


class Teleport:
    """A displacement plugin that sets the object on its target, as the
    kinematic simulator does: the watch must see it."""

    name, kind, fixed_cost = "teleport", "displacement", 2.0

    def execute(self, world, move, path):
        world.set_config(path[-1])
        world.place(move.obj, world.geometry.places[move.location])
        return hand_motions.Primitive(tuple(path), frozenset())


def test_an_object_set_on_its_target_is_seen_moving_untouched(push_rule):
    scene, rule = push_rule
    out = slide_trial(scene, "box", "behind", rule.start, rule.goal, rule.path, primitive=Teleport())
    assert out.success  # where it should be ...
    assert out.untouched > 0.17 and out.pushed < 0.01 and out.jump > 0.17  # ... but nothing pushed it there


def bad_push_scene(tmp_path):
    """push-small with its contact moved 22 cm aside: the hand passes beside the box."""
    data = yaml.safe_load((DATA / "push-small.yaml").read_text())
    data["contacts"]["behind"]["xyz"] = [-0.155, 0.22, 0.12]
    data["contacts"]["behind"]["absent_at"] = ["e1"]  # the arm cannot reach that far aside there
    data["planner"]["roadmap_size"] = 60
    path = tmp_path / "push-beside.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_a_slide_beside_the_box_is_a_state_divergence_in_physics_only(tmp_path, monkeypatch, capsys):
    """The kinematic world carries the box along whatever the hand does; in
    the physical world it stays on l1, and simulate reports a `state`
    divergence 18 cm from l2 (|l1 - l2|), and the run does not complete."""
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    scene = bad_push_scene(tmp_path)
    assert main(["simulate", "--world", "kinematic", str(scene), "--json", "--method", "sg"]) == 0
    kinematic = json.loads(capsys.readouterr().out)["runs"][0]
    assert kinematic["completed"] and kinematic["world"] == "kinematic" and kinematic["divergences"] == []
    assert main(["simulate", str(scene), "--json", "--method", "sg", "--world", "physics",
                 "--randomize", "friction=0.1,pose=0.002"]) == 1
    out = json.loads(capsys.readouterr().out)
    (run,) = out["runs"]
    assert out["world"] == "physics" and out["randomize"] == "friction=0.1,mass=0,pose=0.002"
    assert run["world"] == "physics" and not run["completed"] and run["reason"].startswith("stuck")
    slides = [d for d in run["divergences"] if d["kind"] == "state" and d["distance"] > POSITION]
    assert len(slides) == MAX_VISITS  # the strategy tried again from the observed state, until stuck
    for state in slides:
        assert run["trace"][state["step"] - 1]["action"] == "slide(box,behind,l2)"
        assert state["distance"] == pytest.approx(0.18, abs=0.005)
    assert run["placement_error"] == pytest.approx(0.18, abs=0.005)
    assert run["seconds"] > 0 and run["cost_bound"] is not None and run["cost"] > 0


def test_the_good_push_completes_in_physics(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("SYMSYNTH_CACHE", str(tmp_path / "cache"))
    data = yaml.safe_load((DATA / "push-small.yaml").read_text())
    data["planner"]["roadmap_size"] = 60
    scene = tmp_path / "push.yaml"
    scene.write_text(yaml.safe_dump(data))
    assert main(["simulate", str(scene), "--json", "--method", "sg"]) == 0  # physics by default
    (run,) = json.loads(capsys.readouterr().out)["runs"]
    assert run["world"] == "physics" and run["completed"] and run["divergences"] == [] and run["placement_error"] <= POSITION


@pytest.mark.parametrize("text, message", [
    ("friction=1.5", "relative range in [0, 1)"), ("size=0.1", "KEY one of friction, mass, pose"),
    ("pose=-1", "distance >= 0"), ("mass=x", "must be a number"),
])
def test_bad_randomizations_are_refused(text, message):
    with pytest.raises(InputError, match=message.replace("[", r"\[").replace(")", r"\)")):
        Randomization.parse(text)
    assert Randomization.parse("friction=0.2, mass=0.1,pose=0.005") == Randomization(0.2, 0.1, 0.005)


def test_randomize_needs_the_physical_world(capsys):
    assert main(["simulate", str(DATA / "push-small.yaml"), "--world", "kinematic", "--randomize", "mass=0.1"]) == 2
    assert "add --world physics" in capsys.readouterr().err


def test_the_default_world_is_physics_unless_the_fingers_cannot_close_on_an_object():
    """scenes/arch.yaml's lintel is 14 cm (its box's y) across the fingers
    of its top grasp (the hand's y is the world's y there), the Panda's
    fingers open 2 x 4 cm (their URDF limits 0 to 0.04): kinematic, and
    why; with the grasp turned about z (arch-physical.yaml), and push-small
    (its box wider than the hand's `opening`, never held), physics."""
    arch = load_scene(Path(__file__).parents[1] / "scenes" / "arch.yaml")
    assert default_world(arch) == ("kinematic", ["b is 14 cm across the fingers of grasp top, which open 8 cm"])
    assert default_world(load_scene(Path(__file__).parents[1] / "scenes" / "arch-physical.yaml")) == ("physics", [])
    assert default_world(load_scene(DATA / "push-small.yaml")) == ("physics", [])


def test_randomized_worlds_differ_by_seed_and_repeat_by_seed(block):
    scene, _ = block
    draws = []
    for seed in (3, 3, 4):
        world = PhysicsWorld(scene, randomization=Randomization(0.2, 0.2, 0.005), seed=seed)
        try:
            draws.append((world.client.getDynamicsInfo(world.bodies["b"], -1)[:2], world.poses["b"].xyz))
        finally:
            world.close()
    assert draws[0] == draws[1] and draws[0] != draws[2]
    (mass, friction), xyz = draws[2]
    assert 0.07 * 0.8 <= mass <= 0.07 * 1.2 and 0.5 * 0.8 <= friction <= 0.5 * 1.2
    assert max(abs(xyz[0] - 0.5), abs(xyz[1])) <= 0.005


def test_the_built_in_push_passes_the_physical_conformance_clause(push_rule):
    """A plugin's slide, executed in physics, moves the object to its target
    within the tolerance in at least 9 of 10 randomized trials, and moves it
    only by contact; the teleporting plugin reaches its target as often but
    is caught by what moved untouched."""
    scene, rule = push_rule
    randomization = Randomization(friction=0.2, mass=0.2, pose=0.005)
    outcomes = slide_trials(scene, "box", "behind", rule.start, rule.goal, rule.path, 10,
                            randomization=randomization)
    assert sum(o.success for o in outcomes) >= 9
    assert all(o.untouched < 0.005 and o.jump < 0.005 for o in outcomes)
    cheat = slide_trials(scene, "box", "behind", rule.start, rule.goal, rule.path, 2, primitive=Teleport(),
                         randomization=randomization)
    assert all(o.success for o in cheat) and not any(o.untouched < 0.005 and o.jump < 0.005 for o in cheat)
