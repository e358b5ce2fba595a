"""The paper's rule-based successive jumping (§2.2), as batched controllers
(running it: :mod:`locustjump.tasks.reference`).

Two fixed motions:

* *kick*: drive the servo targets at the maximum rate (10 deg per control step)
  to the extended posture (``LocustParams.kick_hip/kick_knee``);
* *kick legs back*: drive them at the maximum rate back to phi, the
  ready-to-jump posture.

The *touch time* counts control steps while a hind tarsus touches the ground
and is reset to 0 when none does. When the touch time has reached the *change
time* and a tarsus touches, the creature kicks; otherwise it pulls its legs
back. The default change time comes from a small search
(``scripts/tune_change_time.py``, ``docs/physics.md``), as the paper's rules
came from trial and error.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from locustjump.ranges import Range
from locustjump.sim import model as lm
from locustjump.sim.actuation import MAX_DELTA
from locustjump.sim.controller import MLP, MLPWeights
from locustjump.sim.model import CONTROL_DT

#: (Seconds) default change time, from scripts/tune_change_time.py
DEFAULT_CHANGE_TIME = 0.5
#: ``change_time``: (s) touch time before a kick; an hour is far beyond any
#: episode (the creature would never kick)
CHANGE_TIME = Range(0.0, 3600.0, unit="s")


@dataclass(frozen=True)
class RuleController:
    """Touch-time/change-time rules; ``params`` (n, 1): change time in steps.

    Memory per episode: the touch time in control steps.
    """

    ready: tuple[float, ...]  # (rad) phi, order I1–I4
    extended: tuple[float, ...]  # (rad) kick posture
    #: (rad per control step) the rate of both motions; the paper's maximum
    rate: float = MAX_DELTA

    @classmethod
    def for_model(cls, p: lm.LocustParams = lm.LocustParams()) -> RuleController:
        return cls(tuple(p.ready_angles()), tuple(p.kick_angles()))

    @property
    def num_params(self) -> int:
        return 1

    @property
    def memory_size(self) -> int:
        return 1

    @staticmethod
    def params_for(change_time: float | np.ndarray) -> np.ndarray:
        """(n, 1) params from change time(s) in seconds."""
        t = np.atleast_1d(np.asarray(change_time, dtype=np.float64))
        if (t < 0).any():
            raise ValueError("change time must be >= 0 seconds")
        return np.round(t / CONTROL_DT)[:, None]

    def prepare(self, params: np.ndarray) -> np.ndarray:
        """The change time of each episode, (n,) control steps."""
        return np.asarray(params, dtype=np.float64)[:, 0]

    def act(
        self,
        prepared: np.ndarray,
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        touching = obs[:, 4] < 0
        touch_time = np.where(touching, memory[:, 0] + 1, 0.0)
        kick = touching & (touch_time >= prepared)
        goal = np.where(kick[:, None], self.extended, self.ready)
        deltas = np.clip(goal - targets, -self.rate, self.rate)
        return deltas, touch_time[:, None]


@dataclass(frozen=True)
class RuleGetupController:
    """The rules with an evolved get-up network: a reference beyond the paper
    (issue #20). While the body is overturned (U_z, input I9, below
    ``below``) and low (input I6 = 1 / (H + 1) at least ``low``; 0: at any
    height) the frozen get-up network drives the servos, else the rules do.

    ``params`` (n, 1 + 144): the change time in control steps, then the get-up
    genome. Memory per episode: the rules' touch time (kept counting).
    """

    rules: RuleController
    below: float = 0.5
    low: float = 0.0
    getup: MLP = MLP()

    @property
    def num_params(self) -> int:
        return 1 + self.getup.num_params

    @property
    def memory_size(self) -> int:
        return 1

    @staticmethod
    def params_for(change_time: float, getup: np.ndarray) -> np.ndarray:
        """(1, 145) params: ``change_time`` seconds, the (144,) get-up genome."""
        return np.concatenate([RuleController.params_for(change_time)[0], getup])[None]

    def prepare(self, params: np.ndarray) -> tuple[np.ndarray, MLPWeights]:
        params = np.asarray(params, dtype=np.float64)
        return self.rules.prepare(params[:, :1]), self.getup.prepare(params[:, 1:])

    def act(
        self,
        prepared: tuple[np.ndarray, MLPWeights],
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        change, getup = prepared
        deltas, memory = self.rules.act(change, memory, obs, targets, step)
        over = (obs[:, 8] < self.below) & (obs[:, 5] >= self.low)
        if over.any():
            deltas = np.where(over[:, None], self.getup.apply(getup, obs), deltas)
        return deltas, memory
