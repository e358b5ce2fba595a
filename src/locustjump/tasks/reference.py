"""The rule-based reference episode: the paper's rule-based successive
jumping (:mod:`locustjump.tasks.rules`) simulated from the Fig. 4 start state,
what the kick and the composed behaviour compare with
(``Behaviour.reference``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump.ranges import renamed
from locustjump.sim import model as lm
from locustjump.sim.analysis import Jump, find_jumps, stuck_overturned
from locustjump.sim.engine.job import N_STEPS
from locustjump.sim.engine.rollout import DEFAULT_ENGINE, rollout
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.rules import CHANGE_TIME, DEFAULT_CHANGE_TIME, RuleController
from locustjump.tasks.starts import ready_state

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


@dataclass(frozen=True)
class RulesRun:
    """One rule-based episode: records (T + 1 rows) and its jumps."""

    qpos: np.ndarray
    obs: np.ndarray
    ctrl: np.ndarray
    jumps: list[Jump]
    change_time: float
    unstable: bool
    scene: Scene = Flat()  #: where it ran

    def head(self, steps: int, p: lm.LocustParams) -> RulesRun:
        """Its first ``steps`` control steps (the same as a run of ``steps``:
        episodes do not depend on their length), jumps found again at ``p``."""
        qpos = self.qpos[: steps + 1]
        obs, ctrl = self.obs[: steps + 1], self.ctrl[: steps + 1]
        jumps = find_jumps(qpos, p, self.scene)
        return RulesRun(
            qpos, obs, ctrl, jumps, self.change_time, self.unstable, self.scene
        )


def run_rules(
    change_time: float = DEFAULT_CHANGE_TIME,
    steps: int = 3000,
    *,
    model_params: lm.LocustParams = lm.LocustParams(),
    backend: Backend | None = None,
    label: str = "",
    engine: str = DEFAULT_ENGINE,
    scene: Scene = Flat(),
) -> RulesRun:
    """Run the rule-based successive jumping from the Fig. 4 start state in
    ``scene`` (``backend``: where, :mod:`~.engine.backends`; ``label``: a
    progress bar on a terminal)."""
    change_time = CHANGE_TIME.check("change_time", change_time)
    steps = N_STEPS.check("steps", steps)
    rc = RuleController.for_model(model_params)
    with renamed({"n_steps": "steps"}):  # a rollout too long for the memory
        res = rollout(
            rc,
            rc.params_for(change_time),
            ready_state(model_params, scene),
            steps,
            model_params=model_params,
            record=("qpos", "obs", "ctrl"),
            backend=backend,
            label=label,
            engine=engine,
            scene=scene,
        )
    qpos = res["qpos"][0]
    return RulesRun(
        qpos,
        res["obs"][0],
        res["ctrl"][0],
        find_jumps(qpos, model_params, scene),
        float(change_time),
        bool(res.unstable[0]),
        scene,
    )


def rules_outcome(run: RulesRun, p: lm.LocustParams) -> dict[str, Any]:
    """How far the rules got: jumps, the first time it lay overturned for good
    (:func:`~locustjump.sim.analysis.stuck_overturned`; the rules cannot get
    up), the jumps before that and the distance (m, along x) by then."""
    stuck = stuck_overturned(run.obs[:, 8])
    end = len(run.qpos) - 1 if stuck is None else stuck
    return {
        "jumps": len(run.jumps),
        "stuck_overturned_s": None if stuck is None else stuck * lm.CONTROL_DT,
        "jumps_before_stuck": sum(j.start < end for j in run.jumps),
        "distance_m": float(run.qpos[end, 0] - run.qpos[0, 0]),
        "final_up_z": float(run.obs[-1, 8]),
    }
