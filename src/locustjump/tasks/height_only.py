"""Beyond the paper: successive jumping scored by the paper's Eq. 4 alone on
every scene — the ablation of the distance term we added on terrains.

``composed-height`` and ``monolithic-height`` are the composed and the
monolithic behaviour (same start on its side, same 3000-step episode, same
networks) with fitness ``E = sum_{t=1..3000} (z_t - h(x_t, y_t))``: the body
centre's height above the ground under it, summed over control steps (m x
steps), **without** ``PROGRESS_WEIGHT x`` forward progress. On the flat floor
(``h = 0``) they are the composed and monolithic behaviours exactly. Their
terms: ``height`` (all of E) and ``distance`` (0). They ask whether a
comparison on debris depends on the term we added (issue #45).
"""

from __future__ import annotations

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.analysis import clearance
from locustjump.sim.engine.job import RolloutResult
from locustjump.tasks.base import Behaviour, StepReward
from locustjump.tasks.composed import Composed, successive_terms
from locustjump.tasks.monolithic import Monolithic


class HeightOnlyReward(StepReward):
    """Dense Eq. 4 above the ground: ``z_t - h(x_t, y_t)`` (m), whose sum over
    the episode is the height-only fitness."""

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        pass

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        return float(clearance(qpos[None], self.p, self.behaviour.scene)[0])


class _HeightOnly(Behaviour):
    """Eq. 4 above the ground, no distance term (mixed into a ``Successive``)."""

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return successive_terms(res["qpos"], p, self.scene)[0]

    def episode_terms(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        height = self.episode_fitness(res, p)
        return {"height": height, "distance": np.zeros_like(height)}

    def reward(self, p: lm.LocustParams) -> StepReward:
        return HeightOnlyReward(self, p)


class ComposedHeight(_HeightOnly, Composed):
    """The paper's composed behaviour, scored by Eq. 4 alone on any scene."""

    name = "composed-height"


class MonolithicHeight(_HeightOnly, Monolithic):
    """The monolithic baseline, scored by Eq. 4 alone on any scene."""

    name = "monolithic-height"
    gym_id = None  # the Gymnasium environment is the monolithic one's


#: The distance-term ablation's behaviours, registered beside the paper's.
HEIGHT_ONLY = (ComposedHeight, MonolithicHeight)

__all__ = ["HEIGHT_ONLY", "ComposedHeight", "MonolithicHeight"]
