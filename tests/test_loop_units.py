"""The engine's one loop (``sim/engine/loop.py``) where the comparison with
the reference loop (``tests/test_rollout.py``) does not reach: MuJoCo raising
for some simulations of a call, and the progress bar."""

import warnings

import numpy as np
import pytest
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim.actuation import apply_deltas
from locustjump.sim.controller import MLP
from locustjump.sim.engine import loop
from locustjump.sim.engine.job import RolloutJob, StartStates
from locustjump.sim.engine.numpy_step import run_numpy


class Raising:
    """A batch whose ``at``-th rollout call raises for simulations ``ids``
    (after stepping them all: what they did is not read)."""

    def __init__(self, batch: Batch, at: int, ids: list[int]):
        self._batch, self._at, self._ids, self.calls = batch, at, ids, 0

    def __getattr__(self, name):
        return getattr(self._batch, name)

    def rollout(self, *args, **kw):
        out = self._batch.rollout(*args, **kw)
        self.calls += 1
        if self.calls == self._at:
            raise SimulationError(np.array(self._ids), "mj_stackAlloc: out of memory")
        return out


def _job(mjmodel, n=3, steps=12, record=("qpos", "obs"), label=""):
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(4), n, scale=0.5)
    starts = StartStates.concat([StartStates.ready(mjmodel)] * n)
    return RolloutJob(
        lm.LocustParams(), net, genomes, starts, steps, record, label, "numpy"
    )


def _ctrl_rows(job, at, ids):
    """The servo targets of every row, with the failure as in :func:`_run`."""
    with_ctrl = RolloutJob(
        job.model_params,
        job.controller,
        job.params,
        job.starts,
        job.n_steps,
        (*job.record, "ctrl"),
        engine="numpy",
    )
    return _run(with_ctrl, at, ids)["ctrl"]


def _run(job, at=None, ids=()):
    batch = Batch(lm.load_model(job.model_params), job.n_episodes, 1, persistent=True)
    return run_numpy(batch if at is None else Raising(batch, at, list(ids)), job)


@pytest.mark.parametrize(
    "record", [("qpos", "obs"), ("qpos", "penetration", "wall_contact")]
)
def test_mujoco_raising_for_one_simulation_stops_only_that_episode(mjmodel, record):
    job = _job(mjmodel, record=record)
    clean = _run(job)
    got = _run(job, at=5, ids=[1])
    assert got.unstable.tolist() == [False, True, False]
    assert got.steps.tolist() == [12, 5, 12]
    assert got.control_steps == 3 * 5 + 2 * 7  # the failed one stopped at 5
    qpos = got["qpos"]
    np.testing.assert_array_equal(qpos[1, :5], clean["qpos"][1, :5])
    assert (qpos[1, 5:] == qpos[1, 4]).all()  # its records repeat row 4
    assert np.isfinite(qpos).all()
    for e in (0, 2):  # the others go on (their touch kept from step 4 at 5)
        np.testing.assert_array_equal(qpos[e, :6], clean["qpos"][e, :6])
        assert not (qpos[e, 6:] == qpos[e, 5]).all()
    if "obs" in record:  # after the failed call the others act once, as always
        idx = lm.ModelIndex.of(mjmodel)
        net, ranges = job.controller, idx.ranges
        ctrl = _ctrl_rows(job, at=5, ids=[1])
        for e in (0, 2):
            for t in (4, 5, 6):
                deltas = net.forward(job.params[e : e + 1], got["obs"][e, t][None])
                want = apply_deltas(ctrl[e, t][None], deltas, ranges)
                np.testing.assert_array_equal(ctrl[e, t + 1], want[0])
    if "penetration" in record:  # a failed call: every episode repeats row 4
        for name in ("penetration", "wall_contact"):
            np.testing.assert_array_equal(got[name][:, 5], got[name][:, 4])
            np.testing.assert_array_equal(got[name][0, :5], clean[name][0, :5])


def test_a_failed_episode_already_stopped_is_not_counted_again(mjmodel):
    job = _job(mjmodel)
    batch = Batch(lm.load_model(job.model_params), 3, 1, persistent=True)

    class Twice(Raising):
        def rollout(self, *args, **kw):
            out = self._batch.rollout(*args, **kw)
            self.calls += 1
            if self.calls in (3, 7):
                ids = [0] if self.calls == 3 else kw.get("ids", [1, 2])[:1]
                raise SimulationError(np.array(ids), "out of memory")
            return out

    got = run_numpy(Twice(batch, 0, []), job)
    assert got.unstable.tolist() == [True, True, False]
    assert got.steps.tolist() == [3, 7, 12]


def test_a_failed_simulations_state_is_made_finite(mjmodel):
    """A simulation left with a non-finite state stops with its state made
    finite, so that no later whole-batch computation reads a NaN (NumPy
    would warn; here a warning fails the test)."""
    job = _job(mjmodel)
    batch = Batch(lm.load_model(job.model_params), 3, 1, persistent=True)

    class Blown(Raising):
        def rollout(self, *args, **kw):
            if self.calls + 1 == self._at:
                self._batch.bind("qpos")[self._ids] = np.nan
            return super().rollout(*args, **kw)

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = run_numpy(Blown(batch, 5, [1]), job)
    assert got.unstable.tolist() == [False, True, False]
    assert np.isfinite(batch.bind("qpos")).all()


def test_every_simulation_raising_ends_the_rollout(mjmodel):
    job = _job(mjmodel)
    got = _run(job, at=4, ids=[0, 1, 2])
    assert got.unstable.all() and got.steps.tolist() == [4, 4, 4]
    assert got.control_steps == 12
    assert (got["obs"][:, 4:] == got["obs"][:, 3:4]).all()


def test_the_progress_bar_counts_every_control_step(monkeypatch, mjmodel):
    updates, closed = [], []

    class Bar:
        def update(self, k):
            updates.append(k)

        def close(self):
            closed.append(True)

    monkeypatch.setattr(loop, "progress", lambda job: Bar() if job.label else None)
    _run(_job(mjmodel, n=1, steps=250, label="kick"))
    assert updates == [100, 100, 50] and closed == [True]
    _run(_job(mjmodel, n=1, steps=250))  # no label, no bar
    assert updates == [100, 100, 50]
