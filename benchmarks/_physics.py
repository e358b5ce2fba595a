"""Physics-only baseline shared by the benchmarks: replay an engine rollout's
servo targets open-loop with ``mujoco.rollout`` (same model, same substeps,
same start states, same number of threads)."""

from __future__ import annotations

import statistics
import time

import mujoco
import numpy as np
from mujoco import rollout as mj_rollout

from locustjump.sim import model as lm
from locustjump.sim.engine.rollout import StartStates
from locustjump.sim.scene import Flat, Scene


def physics_only_seconds(
    p: lm.LocustParams,
    starts: StartStates,
    ctrl: np.ndarray,
    threads: int,
    repeats: int,
    scene: Scene = Flat(),
) -> float:
    """Median seconds to simulate ``len(starts)`` episodes with the recorded
    servo targets ``ctrl (n, T + 1, nu)`` (row 0, the start, is skipped) held
    for each physics substep, in ``scene``."""
    m = lm.load_model(p, scene)
    d = mujoco.MjData(m)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty((len(starts), mujoco.mj_stateSize(m, spec)))
    for e in range(len(starts)):
        mujoco.mj_resetData(m, d)
        d.qpos[:], d.qvel[:] = starts.qpos[e], starts.qvel[e]
        mujoco.mj_forward(m, d)
        mujoco.mj_getState(m, d, state0[e], spec)
    controls = np.repeat(ctrl[:, 1:], p.substeps, axis=1)
    datas = [mujoco.MjData(m) for _ in range(threads)]
    times = []
    with mj_rollout.Rollout(nthread=threads) as r:
        r.rollout(m, datas, state0, controls)  # warm-up
        for _ in range(repeats):
            t0 = time.perf_counter()
            r.rollout(m, datas, state0, controls)
            times.append(time.perf_counter() - t0)
    return statistics.median(times)
