"""The kick's ceiling: how high can this creature jump at all (issue #20)?

Beyond the paper. The kick (:mod:`.kick`) with two changes that can only
raise what an optimizer finds, each on its own and together:

* fitness **apex rise** ``max_t z_t - z_0`` (m) instead of Eq. 1's
  ``max dx+ * dz+`` (``kick-apex``, ``kick-apex-open``);
* an **open-loop** controller instead of the 9-10-4 network: one target
  change per joint and block of ``OPEN_LOOP_BLOCK`` control steps, free of
  the network's dependence on its inputs (``kick-open``, ``kick-apex-open``).

The actuation stays the paper's: target changes within +-10 deg per control
step, targets clipped to the joint ranges, the model's servos. Start and
episode are the kick's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.actuation import MAX_DELTA, N_ACTUATORS
from locustjump.sim.controller import Controller
from locustjump.sim.engine.job import RolloutResult
from locustjump.tasks.base import StepReward
from locustjump.tasks.kick import Kick

#: Control steps per block of the open-loop controller (1/24 s).
OPEN_LOOP_BLOCK = 5


@dataclass(frozen=True)
class OpenLoop:
    """An open-loop sequence of target changes, batched over episodes.

    ``params`` (n, blocks * 4): per block of ``block`` control steps and joint
    (order I1-I4), a gene ``g``; the target change at every step of the block
    is ``tanh(g) * 10 deg``. After the last block the targets stay put.
    """

    blocks: int
    block: int = OPEN_LOOP_BLOCK

    def __post_init__(self) -> None:
        if self.blocks < 1 or self.block < 1:
            raise ValueError("blocks and block must be >= 1")

    @classmethod
    def covering(cls, n_steps: int, block: int = OPEN_LOOP_BLOCK) -> OpenLoop:
        """Blocks enough for an episode of ``n_steps`` control steps."""
        return cls(-(-n_steps // block), block)

    @property
    def num_params(self) -> int:
        return self.blocks * N_ACTUATORS

    @property
    def memory_size(self) -> int:
        return 0

    def prepare(self, params: np.ndarray) -> np.ndarray:
        """(n, blocks + 1, 4) target changes in radians; the last block is 0."""
        params = np.asarray(params, dtype=np.float64)
        if params.ndim != 2 or params.shape[1] != self.num_params:
            raise ValueError(
                f"genome has shape {params.shape}, expected (n, {self.num_params})"
            )
        d = np.tanh(params).reshape(len(params), self.blocks, N_ACTUATORS)
        d *= MAX_DELTA
        return np.concatenate([d, np.zeros((len(params), 1, N_ACTUATORS))], axis=1)

    def act(
        self,
        prepared: np.ndarray,
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        return prepared[:, min(step // self.block, self.blocks)], memory


def apex_rise(qpos: np.ndarray) -> np.ndarray:
    """``max_t z_t - z_0`` of trajectories ``qpos (n, T + 1, nq)``: (n,) m."""
    z = qpos[:, :, 2]
    rise: np.ndarray = z.max(axis=1) - z[:, 0]
    return rise


class KickApex(Kick):
    """The kick, fitness the apex rise of the body centre (m)."""

    name = "kick-apex"
    gym_id = None

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return apex_rise(res["qpos"])

    def reward(self, p: lm.LocustParams) -> StepReward:
        return StepReward(self, p)  # sparse: the apex rise at the last step


class OpenLoopKick(Kick):
    """The kick (Eq. 1), evolved as an open-loop sequence."""

    name = "kick-open"
    gym_id = None

    @property
    def controller(self) -> Controller:
        return OpenLoop.covering(self.n_steps)


class OpenLoopKickApex(OpenLoopKick, KickApex):
    """The apex rise, evolved as an open-loop sequence."""

    name = "kick-apex-open"


#: The ceiling's behaviours, registered beside the paper's.
CEILING = (KickApex, OpenLoopKick, OpenLoopKickApex)
