"""What a behaviour is: start states, an episode length, a fitness, metrics."""

from __future__ import annotations

from pathlib import Path
from typing import Any, ClassVar

import mujoco
import numpy as np

from locustjump import model as lm
from locustjump.controller import MLP, Controller
from locustjump.rollout import Backend, RolloutResult, StartStates, rollout


def settle(
    p: lm.LocustParams,
    *,
    roll_deg: float = 0.0,
    angles: np.ndarray | None = None,
    seconds: float = 3.0,
) -> StartStates:
    """A start state settled on the ground before t = 0 (deterministic).

    The Fig. 4 posture (keyframe ``ready``) is rolled by ``roll_deg`` about the
    body's x-axis, its hind joints and servo targets set to ``angles`` (4,
    radians; default phi), lifted until its bounding spheres clear the floor,
    and simulated for ``seconds`` with the servos holding their targets. The
    body is then moved back over the origin (heading and height kept).
    """
    m = lm.load_model(p)
    idx = lm.ModelIndex.of(m)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(lm.READY_KEY).id)
    if angles is not None:
        d.qpos[idx.qpos_joints] = angles
        d.ctrl[:] = angles
    q_roll = np.empty(4)
    mujoco.mju_axisAngle2Quat(q_roll, np.array([1.0, 0.0, 0.0]), np.radians(roll_deg))
    q = np.empty(4)
    mujoco.mju_mulQuat(q, d.qpos[3:7].copy(), q_roll)  # rotation in the body frame
    d.qpos[3:7] = q
    mujoco.mj_forward(m, d)
    creature = m.geom_bodyid != 0
    low = (d.geom_xpos[creature, 2] - m.geom_rbound[creature]).min()
    d.qpos[2] += 1e-3 * p.scale - low
    mujoco.mj_forward(m, d)
    mujoco.mj_step(m, d, nstep=round(seconds / m.opt.timestep))
    d.qpos[:2] = 0.0
    return StartStates(d.qpos[None].copy(), d.qvel[None].copy(), d.ctrl[None].copy())


class Behaviour:
    """One of the paper's experiments.

    A subclass sets ``name``, ``n_steps`` and ``record`` (what its fitness
    reads) and implements :meth:`start_states`, :meth:`episode_fitness` and
    :meth:`metrics`. Fitness is maximised; an episode whose simulation went
    unstable gets ``worst_fitness``.
    """

    name: ClassVar[str]
    n_steps: ClassVar[int]
    record: ClassVar[tuple[str, ...]] = ("qpos",)
    #: what ``evaluate_run`` records (its trajectory CSV needs the first three)
    eval_record: ClassVar[tuple[str, ...]] = ("qpos", "obs", "ctrl")
    worst_fitness: ClassVar[float] = 0.0

    @property
    def controller(self) -> Controller:
        """The evolved network (the paper's 9-10-4 MLP)."""
        return MLP()

    def start_states(self, p: lm.LocustParams) -> StartStates:
        raise NotImplementedError

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        """(n_episodes,) fitness of each episode of ``res``."""
        raise NotImplementedError

    def metrics(
        self, res: RolloutResult, p: lm.LocustParams, genome: np.ndarray
    ) -> dict[str, Any]:
        """Behaviour metrics of one controller's episodes (JSON-serialisable)."""
        raise NotImplementedError

    def state_labels(self) -> list[str]:
        """A file-name-safe label per start state."""
        return ["start"]

    def write_figures(
        self, res: RolloutResult, p: lm.LocustParams, out: Path
    ) -> list[Path]:
        """Figures of one controller's episodes into directory ``out``."""
        from locustjump.analysis import find_jumps
        from locustjump.plots import trajectory_figure

        path = out / "trajectory.png"
        qpos = res["qpos"][0]
        trajectory_figure(path, [(self.name, qpos, find_jumps(qpos, p))])
        return [path]

    # -- shared machinery --

    def simulate(
        self,
        genomes: np.ndarray,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
        record: tuple[str, ...] | None = None,
    ) -> RolloutResult:
        """Every genome from every start state (controller-major episodes)."""
        return rollout(
            self.controller,
            genomes,
            self.start_states(p),
            self.n_steps,
            model_params=p,
            record=self.record if record is None else record,
            backend=backend,
        )

    def fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        """(n_controllers,) fitness: the mean over each controller's start states."""
        f = np.where(res.unstable, self.worst_fitness, self.episode_fitness(res, p))
        k = len(self.start_states(p))
        return f.reshape(-1, k).mean(axis=1)

    def evaluate(
        self,
        genomes: np.ndarray,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
    ) -> tuple[np.ndarray, RolloutResult]:
        """Fitness (n,) of genomes (n, P) and the rollout it came from."""
        res = self.simulate(genomes, p, backend=backend)
        return self.fitness(res, p), res
