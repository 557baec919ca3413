"""What a run in the world recorded (`simulate.Simulator.run`): its steps,
the abstract and measured cost of each robot step, and where the world and
the abstraction diverged (the kinds are `simulate`'s docstring's)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from symsynth.game.abstraction import State, state_json

SLACK = 1e-6  # costmap units: float noise allowed between measured and abstract costs
SOUNDNESS = ("cost", "evidence")


@dataclass(frozen=True)
class Step:
    """One step of a run.  Robot steps carry the abstract cost of the action
    in the state it was chosen in and the measured cost; `source` says how
    it moved: evidence, runtime, none (already there), primitive; human
    steps have source `human` and no costs."""

    who: str
    action: str
    state: State  # γ of the world after the step
    abstract: float | None = None
    measured: float | None = None
    radians: float = 0.0
    source: str = "human"


@dataclass(frozen=True)
class Divergence:
    step: int  # 1-based index into Run.steps
    kind: str  # cost, evidence, state, outside, contact
    message: str
    #: `state`: the largest distance (metres) of an object from the location the
    #: abstraction puts it at; None when it puts none of the strayed ones on a location.
    distance: float | None = None

    @property
    def soundness(self) -> bool:
        return self.kind in SOUNDNESS


@dataclass
class Run:
    seed: int
    human: str
    bound: float | None  # E_p of the strategy followed, None when it does not win
    completed: bool = False
    reason: str = ""
    steps: list[Step] = field(default_factory=list)
    divergences: list[Divergence] = field(default_factory=list)
    refused: list[str] = field(default_factory=list)  # human moves the world or k did not allow
    best_effort: int = 0  # robot actions taken outside the strategy (best effort)
    seconds: float = 0.0
    #: The processor seconds of the run (this process's, `time.process_time`):
    #: on a shared machine, what the run cost whatever else ran beside it.
    cpu_seconds: float = 0.0
    world: str = "kinematic"  # kinematic or physics
    #: After the last step: the largest distance (metres) of an object from the location the
    #: abstraction puts it at (None: it puts none on a location).
    placement_error: float | None = None

    @property
    def cost(self) -> float:
        return sum(s.measured or 0.0 for s in self.steps)

    @property
    def abstract_cost(self) -> float:
        return sum(s.abstract or 0.0 for s in self.steps)

    @property
    def sound(self) -> bool:
        return not any(d.soundness for d in self.divergences)

    @property
    def within_bound(self) -> bool | None:
        if self.bound is None:
            return None
        return self.cost <= self.bound + SLACK

    def to_json(self, objects: tuple[str, ...]) -> dict[str, Any]:
        return {
            "seed": self.seed, "world": self.world, "human": self.human, "completed": self.completed,
            "reason": self.reason, "placement_error": self.placement_error,
            "cost": self.cost, "abstract_cost": self.abstract_cost, "cost_bound": self.bound,
            "within_bound": self.within_bound, "sound": self.sound, "best_effort_actions": self.best_effort,
            "robot_actions": sum(s.who == "robot" for s in self.steps),
            "human_moves": sum(s.who == "human" for s in self.steps),
            "seconds": self.seconds, "cpu_seconds": self.cpu_seconds, "refused_human_moves": list(self.refused),
            "divergences": [{"step": d.step, "kind": d.kind, "soundness": d.soundness, "distance": d.distance,
                             "message": d.message} for d in self.divergences],
            "trace": [{"who": s.who, "action": s.action, "abstract_cost": s.abstract,
                       "measured_cost": s.measured, "radians": s.radians, "source": s.source,
                       "state": state_json(s.state, objects)} for s in self.steps],
        }
