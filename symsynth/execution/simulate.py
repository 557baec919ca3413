"""Running a strategy in the world against a simulated human (paper Sec.
V-B, the continuous counterpart of its Theorem 8).

A run alternates turns as the game does (semantics §6), human first:

1. **Human turn.**  The human passes or moves one object (at most `k`
   moves).  The abstract state is then read from the world through γ
   (`observe.py`) and the DFA reads its letter.
2. **Robot turn.**  The strategy is asked for its action at the observed
   position (abstract state, DFA state, human moves left).  Transits and
   transfers follow an evidence path or a path planned at run time
   (`motion.py`); grab and drop are primitives (`hand_motions.py`).  The
   world is observed again and the DFA reads the new letter.

The run ends when the DFA accepts (completed), when the strategy has no
action for the observed position, or when an action cannot be carried out.

**What is measured.**  A motion costs `per_radian` x the radians its path
travels (the costmap's own metric, joint-space euclidean length); a
primitive costs the scene's fixed grab / drop cost.  Every robot step is
compared with the abstraction:

- `cost` (soundness): the measured cost exceeds the abstract cost of the
  action (semantics §5, the worst case over the states the abstract state stands
  for).  With every object on a place and the robot on an anchor this
  cannot happen unless the costmap or the solver is wrong;
- `evidence` (soundness): an evidence path whose rule held touched
  something in the world (the run falls back to planning);
- `state`: γ of the world after the step differs from the abstraction's
  successor state;
- `outside`: the step started where the abstraction has no motion (an
  object off every place, the robot off every anchor), so the abstract cost
  is no bound for it; an evidence path rejected then is `outside` too, as
  no rule's assumptions (which places are free) describe an object off
  every place;
- `contact`: a primitive's approach penetrated something other than the
  object the fingers close around.

The first two are soundness bugs; `Run.sound` is false when one occurred.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from symsynth.errors import SymsynthError
from symsynth.execution import motion as motions
from symsynth.execution import hand_motions
from symsynth.execution.human import Human, Option, Request, ScriptedHuman, Turn
from symsynth.execution.observe import close, distance, observe, place_at
from symsynth.execution.policy import Policy
from symsynth.execution.runs import SLACK, Divergence, Run, Step
from symsynth.execution.physics import FRAME_STEPS, SLIDE_FRAME_STEPS, PhysicsWorld, Randomization
from symsynth.execution.record import STRIDE, Recorder
from symsynth.execution.world import SimWorld
from symsynth.game.abstraction import (Move, State, action_name, anchors, costmap_of, legal_human_moves,
                                       legal_robot_moves, robot_action_names, slide_rule)
from symsynth.game.graph import GameGraph
from symsynth.game.solution import Position
from symsynth.game.strategy import format_position, format_state
from symsynth.logic import ast
from symsynth.planning.anchors import anchor_configs
from symsynth.planning.protocol import Mode, Planner
from symsynth.primitive_registry import displacement, primitive
from symsynth.scene.geometry import Pose, point_text
from symsynth.scene.model import ELSE, HOME, Scene

MAX_ACTIONS = 500
WORLDS = ("kinematic", "physics")
#: A position at which the robot's turn comes again this often (its action
#: failed in the world each time) ends the run: a winning strategy never
#: returns to a position in the abstraction (E_p decreases along its plays).
MAX_VISITS = 3
#: The physical world: an object farther than this from its place's pose (metres,
#: radians) is not where the costmap's rules assume it, so a rule that fails
#: there is `outside`, not a soundness bug.
EXACT = 1e-3
EXACT_ANGLE = 0.01


class ActionFailed(SymsynthError):
    pass


class Simulator:
    """Runs of one scene, task and policy; the planner (for inverse
    kinematics, self- and static collisions), the anchors and the grab and
    drop approaches are made once."""

    def __init__(self, scene: Scene, formula: ast.Formula, policy: Policy, planner: Planner, *,
                 resolution: float = 1.0, world: str = "kinematic",
                 randomization: Randomization | None = None) -> None:
        if scene.geometry is None:
            raise SymsynthError(f"scene {scene.name!r} is abstract (no 'robot' key): "
                                "there is no world to simulate")
        self.scene = scene
        self.game = GameGraph(scene, formula, resolution)
        self.policy = policy
        self.planner = planner
        self.anchors = anchor_configs(planner, scene)
        self.approaches = hand_motions.Approaches(planner)  # grab and drop paths, shared by the runs
        self.per_radian = scene.geometry.per_radian
        self.planner_step = scene.geometry.planner.check_step  # radians; `resolution` quantizes costs
        if world not in WORLDS:
            raise SymsynthError(f"unknown world {world!r}; expected {' or '.join(WORLDS)}")
        if randomization is not None and world != "physics":
            raise SymsynthError("randomization is for the physical world (world 'physics')")
        self.world, self.randomization = world, randomization

    def make_world(self, seed: int, gui: bool = False) -> SimWorld:
        """The world of a run: kinematic, or physical with run `seed`'s randomization."""
        if self.world == "physics":
            return PhysicsWorld(self.scene, gui=gui, randomization=self.randomization, seed=seed)
        return SimWorld(self.scene, gui=gui)

    def run(self, human: Human, seed: int = 0, *, recorder: Callable[[SimWorld], Recorder] | None = None,
            gui: bool = False, max_actions: int = MAX_ACTIONS) -> Run:
        clock, cpu = time.perf_counter(), time.process_time()
        world = self.make_world(seed, gui)
        try:
            episode = _Episode(self, world, human, seed, recorder(world) if recorder else None, max_actions)
            run = episode.play()
            run.world = self.world
        finally:
            world.close()
        run.seconds, run.cpu_seconds = time.perf_counter() - clock, time.process_time() - cpu
        return run


class _Episode:
    """One run: the world, the position, the robot's anchor."""

    def __init__(self, sim: Simulator, world: SimWorld, human: Human, seed: int,
                 recorder: Recorder | None, max_actions: int) -> None:
        self.sim, self.scene, self.game, self.world = sim, sim.scene, sim.game, world
        self.human, self.seed, self.recorder, self.max_actions = human, seed, recorder, max_actions
        self.run = Run(seed, human.name, sim.policy.bound)
        self.anchor: str | None = HOME  # the anchor the robot stands on, None when off every anchor
        self.actions = 0
        self.visits: dict[tuple, int] = {}  # (position, the policy's memory): robot turns there
        self.last: str | None = None
        self.expected: State = observe(self.scene, world)  # the abstraction's state after the last step
        sim.policy.start()

    # -- the loop -------------------------------------------------------------

    def play(self) -> Run:
        run = self.run
        v = observe(self.scene, self.world)
        q = self.game.read(self.game.dfa.initial, v)
        h = self.scene.k
        self._frame("start", hold=True)
        if self.game.accepts(q):
            return self._end(True, "the task holds in the initial state")
        while True:
            move = self._human_turn(v, q, h)
            if move is not None:
                v, q, h = move
                if self.game.accepts(q):
                    return self._end(True, "completed (by a human move)")
            if self.actions >= self.max_actions:
                return self._end(False, f"gave up after {self.actions} robot actions")
            seen = (v, q, h, self.sim.policy.memory())
            self.visits[seen] = self.visits.get(seen, 0) + 1
            if self.visits[seen] > MAX_VISITS:  # the abstraction's progress never came about
                return self._end(False, f"stuck: the robot's turn came {MAX_VISITS + 1} times at the observed "
                                 f"position {format_position((v, q, h), self.scene.object_names)} "
                                 "(its actions do not do in the world what the abstraction says)")
            chosen = self.sim.policy.action((v, q, h))
            if chosen is None:
                return self._end(False, "the strategy has no action at the observed position "
                                 f"{format_position((v, q, h), self.scene.object_names)}")
            action, best_effort = chosen
            run.best_effort += best_effort
            try:
                after = self._robot_turn(v, action)
            except (ActionFailed, hand_motions.PrimitiveFailed) as error:
                return self._end(False, f"{action} failed: {error}")
            self.sim.policy.moved((v, q, h), action)
            v = after
            q = self.game.read(q, v)
            if self.game.accepts(q):
                return self._end(True, "completed")

    def _end(self, completed: bool, reason: str) -> Run:
        self.run.completed, self.run.reason = completed, reason
        self.run.placement_error = self._misplaced(self.expected)
        unfired = self.human.unfired() if isinstance(self.human, ScriptedHuman) else ()
        for n, entry in unfired:  # a script's moves that never came due
            self.run.refused.append(f"script move {n} ({entry['move']} to {_where(entry['to'])}): "
                                    f"never came due (after {entry['after']})")
        self._frame(("done: " if completed else "stopped: ") + reason, hold=True)
        return self.run

    # -- the human --------------------------------------------------------------

    def _human_turn(self, v: State, q, h: int) -> tuple[State, Any, int] | None:
        options = self._options(v, q, h) if h > 0 else ()
        while True:
            choice = self.human.choose(Turn((v, q, h), self.actions, self.last, options))
            if isinstance(choice, Request):
                choice = self._resolve(choice, v, q, h)
            elif choice is not None and not self.world.stands(choice.obj, choice.pose):
                # Asked only of the option chosen (a physical check steps the world):
                # left out, and the human chooses again (an option not offered: a pass).
                if choice not in options:
                    return None
                options = tuple(o for o in options if o is not choice)
                continue
            break
        if choice is None:
            return None
        if isinstance(self.world, PhysicsWorld):
            self.world.frame = None  # the frame after the move is taken below
        self.world.place(choice.obj, choice.pose)
        observed = observe(self.scene, self.world)
        self.run.steps.append(Step("human", choice.action, observed))
        self.expected = observed if choice.after is None else choice.after[0]
        if observed != self.expected:
            self._stray(choice.action, observed, self.expected)
        self._frame(f"{len(self.run.steps)}. human {choice.action}", hold=True)
        return observed, self.game.read(q, observed), h - 1

    def _options(self, v: State, q, h: int) -> tuple[Option, ...]:
        """Every abstract human move, once per physical target it can have."""
        options = []
        for move in legal_human_moves(self.scene, v):
            for place in self._targets(move.obj, move.location):
                options.append(Option(move.action, move.obj, self.world.geometry.places[place],
                                      self._after(move.after, q, h - 1)))
        return tuple(options)

    def _targets(self, obj: str, target: str) -> list[str]:
        """The places a human move of `obj` to `target` (a location, or Else:
        every Else sample but the one it stands on) can put it, leaving out
        those where it would penetrate something."""
        if target == ELSE:
            here = place_at(self.scene, self.world.poses[obj])
            places = [e for e in self.scene.else_samples if e != here]
        else:
            places = [target]
        return [x for x in places if not self.world.blocked(obj, self.world.geometry.places[x])]

    def _after(self, w: State, q, h: int) -> Position | None:
        q2 = self.game.read(q, w)
        return None if self.game.accepts(q2) else (w, q2, h)

    def _resolve(self, request: Request, v: State, q, h: int) -> Option | None:
        """A scripted move as an option, or None (refused, with the reason)."""
        what = f"script move {request.entry + 1} ({request.obj} to {_where(request.to)})"
        if h <= 0:
            self.run.refused.append(f"{what}: the human has no moves left (k = {self.scene.k})")
            return None
        if isinstance(request.to, Pose):
            pose, place = request.to, place_at(self.scene, request.to)
        elif request.to == ELSE:
            free = self._targets(request.obj, ELSE)
            if not free:
                self.run.refused.append(f"{what}: no free Else sample")
                return None
            place = free[0]
            pose = self.world.geometry.places[place]
        else:
            place, pose = request.to, self.world.geometry.places[request.to]
        target = place if place in self.scene.locations else ELSE
        move = next((m for m in legal_human_moves(self.scene, v) if (m.obj, m.location) == (request.obj, target)),
                    None)
        if move is None:
            self.run.refused.append(f"{what}: {action_name('move', request.obj, target)} is not a legal human "
                                    f"move in {format_state(v, self.scene.object_names)}")
            return None
        blocked = self.world.blocked(request.obj, pose)
        if blocked:
            self.run.refused.append(f"{what}: it would penetrate {', '.join(sorted(blocked))}")
            return None
        if not self.world.stands(request.obj, pose):
            self.run.refused.append(f"{what}: it would not stand there (it falls or tips over)")
            return None
        return Option(move.action, move.obj, pose, self._after(move.after, q, h - 1))

    # -- the robot --------------------------------------------------------------

    def _robot_turn(self, v: State, action: str) -> State:
        """Carry out the robot move the abstraction names `action` in `v`."""
        moves = legal_robot_moves(self.scene, v)
        move = next((m for m in moves if m.action == action), None)
        if move is None and action not in robot_action_names(self.scene):
            raise ActionFailed("no robot action of this scene has this name (transit(o,g), grab(o), "
                               "transfer(l) or drop(o,l) with the scene's names)")
        if move is None:
            raise ActionFailed(f"not available in {format_state(v, self.scene.object_names)} "
                               f"(available there: {', '.join(m.action for m in moves) or 'none'})")
        expected, abstract = move.after, move.cost
        index = len(self.run.steps) + 1
        caption = f"{index}. robot {action}"
        if isinstance(self.world, PhysicsWorld) and self.recorder is not None:  # frames as the world steps
            recorder, text = self.recorder, self._caption(caption, self.run.cost)
            self.world.frame = lambda: recorder.frame(text)
            self.world.frame_every = SLIDE_FRAME_STEPS if move.kind == "slide" else FRAME_STEPS
        if move.kind == "slide":
            step = self._slide(move, v, index, caption)
        elif move.kind in ("grab", "drop"):  # through the registry, as a third-party primitive would be
            done = primitive(move.kind).execute(self.world, self.sim.approaches, move)
            measured = self.scene.grab_cost if move.kind == "grab" else self.scene.drop_cost
            self._follow(done.path, caption, measured, executed=True)
            if done.touched:
                self._diverge("contact", f"{action}: the approach {self._meets()} {', '.join(sorted(done.touched))}",
                              index)
            step = Step("robot", action, observe(self.scene, self.world), abstract, measured, done.radians,
                        "primitive")
        else:
            step = self._move(move, index, caption)
        self.run.steps.append(step)
        self.actions += 1
        self.last = action
        self.expected = expected
        if step.state != expected:
            self._stray(action, step.state, expected)
        return step.state

    def _stray(self, action: str, observed: State, expected: State) -> None:
        """A `state` divergence: the world after `action` is not what the abstraction says."""
        far = self._misplaced(expected)
        self._diverge("state", f"after {action} the world reads {format_state(observed, self.scene.object_names)}, "
                      f"the abstraction {format_state(expected, self.scene.object_names)}"
                      + ("" if far is None else f" (an object {far * 100:.1f} cm from its location)"),
                      distance=far)

    def _misplaced(self, state: State) -> float | None:
        """The largest distance of an object (not in the hand) from the location `state` puts it at."""
        places, poses = self.world.geometry.places, self.world.poses
        gaps = [distance(poses[o], places[at]) for o, at in zip(self.scene.object_names, state.at)
                if at in self.scene.locations and o != self.world.held]
        return max(gaps, default=None)

    def _slide(self, move: Move, v: State, index: int, caption: str) -> Step:
        """A slide (semantics §4b): the contact's primitive follows the
        evidence path of the slide rule that priced it; measured as the
        radians travelled x per_radian, plus the primitive's fixed cost."""
        rule = slide_rule(self.scene, v, move)
        if rule is None or rule.path is None:
            raise ActionFailed(f"{move.action}: the costmap's slide rule has no evidence path to follow")
        geometry = self.world.geometry
        if move.grasp is None:  # a slide names its contact (game.abstraction.Move)
            raise ActionFailed(f"{move.action}: a slide without a contact")
        plugin = displacement(geometry.contacts[move.grasp].primitive)
        done = plugin.execute(self.world, move, rule.path)
        measured = done.radians * geometry.per_radian + geometry.primitive_costs.get(plugin.name, plugin.fixed_cost)
        self._follow(done.path, caption, measured, executed=True)
        self.anchor = anchors(self.scene, move.location, move.grasp)[0]  # the hand ends at l'/a (§4b)
        if done.touched:
            self._diverge("contact", f"{move.action}: the slide {self._meets()} {', '.join(sorted(done.touched))}",
                          index)
        return Step("robot", move.action, observe(self.scene, self.world), move.cost, measured, done.radians,
                    "slide")

    def _move(self, move: Move, index: int, caption: str) -> Step:
        """A transit or transfer: along an evidence path, or planned at run time."""
        world, scene = self.world, self.scene
        action, abstract, obj, grasp = move.action, move.cost, move.obj, move.grasp
        if grasp is None or abstract is None:  # a transit or transfer has both (game.abstraction.Move)
            raise ActionFailed(f"{action}: a {move.kind} without a grasp or a cost")
        geometry = world.geometry
        if move.kind == "transit":  # to the object where it really stands, which may be on no place
            mode = Mode()
            place = place_at(scene, world.poses[obj])
            target = world.poses[obj] @ geometry.hand_frame(grasp).pre_image()
        else:
            mode = Mode(obj, grasp)
            place = move.location
            target = geometry.places[place] @ geometry.hand_frame(grasp).pre_image()
        off = None
        if place is not None and move.kind == "transit":  # a physical world moves objects off the exact pose
            at_anchor = geometry.places[place] @ geometry.hand_frame(grasp).pre_image()
            if not close(at_anchor, target):
                off = (f"{obj} stands {distance(at_anchor, target) * 100:.1f} cm and {at_anchor.angle_to(target):.2f} "
                       f"rad off {place}'s pose, so {place}'s anchor is not its pre-image")
                place = None
        goal = None if place is None else anchors(scene, place, grasp)[0]  # one of move.goals
        outside = off or self._outside(obj, goal)
        found = None
        if self.anchor is not None and goal is not None:
            free = self._free(obj)
            found, rejected = motions.evidence_motion(world, costmap_of(scene), mode, self.anchor, goal, free,
                                                      self.sim.planner_step)
            for message in rejected:  # a soundness bug only where the rule describes the world
                if outside:
                    self._diverge("outside", f"{action}: the evidence path of {message}, but {outside}", index)
                else:
                    self._diverge("evidence", f"{action}: the evidence path of {message}", index)
        if found is None and goal is not None and self.anchor == goal:  # both None: off every anchor
            found = motions.Motion((world.config,), "none")
        if found is None:
            goal_config = self.sim.anchors.get(goal) if goal else None
            if goal_config is None:
                goal_config = self.sim.planner.inverse_kinematics(target, world.config)
                if goal_config is None:
                    raise ActionFailed(f"no inverse kinematics solution for the end-effector at "
                                       f"{point_text(target.xyz)}")
            try:
                found = motions.runtime_motion(world, self.sim.planner, mode, tuple(goal_config),
                                               self.sim.planner_step, self.seed + self.actions)
            except motions.MotionFailed as error:
                raise ActionFailed(str(error)) from None
        measured = self.sim.per_radian * found.radians
        self._follow(found.path, caption, measured)
        self.anchor = goal
        if measured > abstract + SLACK:
            if outside:
                self._diverge("outside", f"{action}: measured {measured:.6g} > abstract {abstract:.6g}, "
                              f"but {outside}", index)
            else:
                self._diverge("cost", f"{action}: measured {measured:.6g} > abstract {abstract:.6g} "
                              f"({found.source} path, {found.radians:.4f} rad x {self.sim.per_radian:g})", index)
        return Step("robot", action, observe(scene, world), abstract, measured, found.radians, found.source)

    def _outside(self, obj: str, goal: str | None) -> str | None:
        """Why the abstraction's cost does not bound this motion, if it does not."""
        if goal is None:
            return f"{obj} stands on no place (the costmap has no motion to it)"
        if self.anchor is None:
            return "the robot stands on no anchor (an earlier motion was planned off the anchors)"
        off = [o for o in self.scene.object_names
               if o != self.world.held and place_at(self.scene, self.world.poses[o]) is None]
        if off:
            return f"{', '.join(off)} stand{'s' if len(off) == 1 else ''} on no place"
        if isinstance(self.world, PhysicsWorld):  # the costmap's rules assume objects exactly on their places
            places = self.world.geometry.places
            shifted = []
            for o in self.scene.object_names:
                place = None if o == self.world.held else place_at(self.scene, self.world.poses[o])
                pose = self.world.poses[o]
                if place is not None and (distance(pose, places[place]) > EXACT
                                          or pose.angle_to(places[place]) > EXACT_ANGLE):
                    shifted.append(f"{o} {distance(pose, places[place]) * 1000:.0f} mm, "
                                   f"{pose.angle_to(places[place]):.2f} rad off {place}")
            held = self.world.held
            if held is not None and self.world.grasp is not None:  # held as the grasp says?
                nominal = self.world.ee_pose() @ self.world.geometry.hand_frame(self.world.grasp).pose.inverse()
                pose = self.world.poses[held]
                if distance(pose, nominal) > EXACT or pose.angle_to(nominal) > EXACT_ANGLE:
                    shifted.append(f"{held} {distance(pose, nominal) * 1000:.0f} mm, "
                                   f"{pose.angle_to(nominal):.2f} rad off its grasp in the hand")
            if shifted:
                return "in the physical world " + "; ".join(shifted) + " (the rules assume the exact poses)"
        return None

    def _free(self, serves: str) -> frozenset[str]:
        """Places on which no object other than `serves` stands."""
        taken = {place_at(self.scene, pose) for name, pose in self.world.poses.items()
                 if name != serves and name != self.world.held}
        return frozenset(x for x in self.scene.locations + self.scene.else_samples if x not in taken)

    def _follow(self, path, caption: str, cost: float, executed: bool = False) -> None:
        """Move along `path` (frames on the way when recording); a primitive
        has moved the physical world itself (`executed`), the kinematic
        one is replayed for the frames."""
        if isinstance(self.world, PhysicsWorld):
            if not executed:
                self.world.follow(path, clear=True, passing=True)
            return
        if self.recorder is None:
            if path:
                self.world.set_config(path[-1])
            return
        text = self._caption(caption, self.run.cost + cost)
        for config in motions.steps(path, STRIDE):
            self.world.set_config(config)
            self.recorder.frame(text)

    def _meets(self) -> str:
        """How a primitive met what it should not: the physical world reads
        contacts, the kinematic one penetrations deeper than 1 mm."""
        return "touches" if isinstance(self.world, PhysicsWorld) else "penetrates"

    def _caption(self, caption: str, total: float) -> str:
        return f"{caption}   cost {total:.0f}" + ("" if self.run.bound is None else f" / E_p {self.run.bound:g}")

    def _frame(self, caption: str, hold: bool = False) -> None:
        if self.recorder is not None:
            self.recorder.frame(caption, hold)

    def _diverge(self, kind: str, message: str, step: int | None = None, distance: float | None = None) -> None:
        self.run.divergences.append(Divergence(step or len(self.run.steps), kind, message, distance))


def _where(to: str | Pose) -> str:
    return point_text(to.xyz) if isinstance(to, Pose) else to

