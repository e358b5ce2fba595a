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
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump.rundir.layout import EVAL
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.engine.rollout import RolloutResult, StartStates
from locustjump.tasks.base import Behaviour, Claim, StepReward, settle, yes

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

FIGURE = "return_legs.png"  # Fig. 10
#: What we count as "the legs return to phi" (stated in results.md).
LEGS_ERROR_OK_DEG = 5.0


@functools.lru_cache(maxsize=8)
def extended_start(p: lm.LocustParams) -> StartStates:
    """Upright, hind legs extended, settled (deterministic)."""
    return settle(p, angles=p.kick_angles(), seconds=1.0)


def joint_errors(res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
    """(n, T + 1, 4) |phi_i - theta_i(t)| in radians."""
    return np.abs(res["obs"][:, :, 0:4] - p.ready_angles())


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
    figures = ((f"{EVAL}/{FIGURE}", "return-legs", "Returning the legs (Fig. 10):"),)
    headline = ("final_error_deg",)
    gym_id = "LocustReturnLegs-v0"

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return extended_start(p)

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return -joint_errors(res, p)[:, 1:].sum(axis=2).mean(axis=1)

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        *,
        backend: Backend | None = None,
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

    def write_figures(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        out: Path,
        *,
        backend: Backend | None = None,
    ) -> list[Path]:
        """``return_legs.png``: the paper's Fig. 10, the joint angles over time
        converging to phi."""
        from locustjump.present.plots import joint_angles_figure

        path = out / FIGURE
        joint_angles_figure(path, res["obs"][0, :, 0:4], p.ready_angles())
        return [path]

    def claims(self, record: dict[str, Any] | None) -> list[Claim]:
        claim = Claim("the legs return to the ready posture (Fig. 10)", "yes")
        if record is None:
            return [claim]
        err = max(record["metrics"]["final_error_deg"].values())
        return [
            Claim(
                claim.text,
                claim.paper,
                f"largest final error {err:.2f} deg",
                f"{yes(err <= LEGS_ERROR_OK_DEG)} (every joint within "
                f"{LEGS_ERROR_OK_DEG:g} deg)",
                err,
                err <= LEGS_ERROR_OK_DEG,
                "largest final joint error (deg)",
            )
        ]

    def reward(self, p: lm.LocustParams) -> StepReward:
        return LegsReward(self, p)
