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
from typing import Any

import numpy as np

from locustjump import model as lm
from locustjump import names
from locustjump.behaviours.base import Behaviour, settle
from locustjump.rollout import RolloutResult, StartStates


@functools.lru_cache(maxsize=8)
def extended_start(p: lm.LocustParams) -> StartStates:
    """Upright, hind legs extended, settled (deterministic)."""
    return settle(p, angles=p.kick_angles(), seconds=1.0)


def joint_errors(res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
    """(n, T + 1, 4) |phi_i - theta_i(t)| in radians."""
    return np.abs(res["obs"][:, :, 0:4] - p.ready_angles())


class ReturnLegs(Behaviour):
    name = "return-legs"
    n_steps = 1000
    record = ("obs",)
    worst_fitness = -4 * np.pi  # beyond any reachable error

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return extended_start(p)

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return -joint_errors(res, p)[:, 1:].sum(axis=2).mean(axis=1)

    def metrics(
        self, res: RolloutResult, p: lm.LocustParams, genome: np.ndarray
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
        self, res: RolloutResult, p: lm.LocustParams, out: Path
    ) -> list[Path]:
        """``return_legs.png``: the paper's Fig. 10, the joint angles over time
        converging to phi."""
        from locustjump.plots import joint_angles_figure

        path = out / "return_legs.png"
        joint_angles_figure(path, res["obs"][0, :, 0:4], p.ready_angles())
        return [path]
