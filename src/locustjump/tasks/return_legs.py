"""Behaviour Simple 3: returning the legs to the ready posture (paper §3.3,
Fig. 10).

* start: standing upright with the hind legs extended (the rule-based kick's
  extended posture ``LocustParams.kick_hip/kick_knee``), settled for 1 s with
  the servos holding it, as after getting up (Fig. 10a);
* episode: 1000 control steps;
* fitness (our reading of Eq. 3, SPEC):
  ``E = -(1/T) sum_t sum_i |phi_i - theta_i(t)|``, theta the four hind joint
  angles (inputs I1–I4, radians), phi the ready-to-jump angles, t = 1..T.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.engine.job import RolloutResult, StartStates
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.base import Behaviour, StepReward
from locustjump.tasks.reference import RulesRun
from locustjump.tasks.starts import settle


@functools.lru_cache(maxsize=8)
def extended_start(p: lm.LocustParams, scene: Scene = Flat()) -> StartStates:
    """Upright, hind legs extended, settled in ``scene`` (deterministic)."""
    return settle(p, angles=p.kick_angles(), seconds=1.0, scene=scene)


def joint_errors(res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
    """(n, T + 1, 4) |phi_i - theta_i(t)| in radians."""
    errors: np.ndarray = np.abs(res["obs"][:, :, 0:4] - p.ready_angles())
    return errors


class LegsReward(StepReward):
    """Dense Eq. 3: ``-sum_i |phi_i - theta_i(t)| / T`` (radians)."""

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        self._ready = np.asarray(self.p.ready_angles())

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        return -float(np.abs(obs[0:4] - self._ready).sum()) / self.behaviour.n_steps


class ReturnLegs(Behaviour):
    name = "return-legs"
    n_steps = 1000
    record = ("obs",)
    worst_fitness = -4 * np.pi  # beyond any reachable error
    gym_id = "LocustReturnLegs-v0"

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return extended_start(p, self.scene)

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        fitness: np.ndarray = -joint_errors(res, p)[:, 1:].sum(axis=2).mean(axis=1)
        return fitness

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        reference: RulesRun | None = None,
    ) -> dict[str, Any]:
        err = np.degrees(joint_errors(res, p)[0])
        return {
            "fitness": float(self.fitness(res, p)[0]),
            "start_error_deg": {
                j: round(float(e), 3)
                for j, e in zip(names.ACTUATED_JOINTS, err[0], strict=True)
            },
            "final_error_deg": {
                j: round(float(e), 3)
                for j, e in zip(names.ACTUATED_JOINTS, err[-1], strict=True)
            },
            "final_up_z": round(float(res["obs"][0, -1, 8]), 4),
            "unstable": bool(res.unstable[0]),
        }

    def reward(self, p: lm.LocustParams) -> StepReward:
        return LegsReward(self, p)
