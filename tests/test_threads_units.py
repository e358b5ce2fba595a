"""The thread backend (``sim/engine/threads.py``), piece by piece: its
default and checked thread count, one cached batch per model, scene and
episode count with no more threads than episodes, and a closed backend."""

import os

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine import threads as th
from locustjump.sim.engine.job import RolloutJob, StartStates
from locustjump.sim.scene import Debris, Flat


def test_the_default_is_the_cpus_this_process_may_use():
    assert th.default_threads() == len(os.sched_getaffinity(0))
    assert th.ThreadBackend().threads == th.default_threads()
    assert th.ThreadBackend(3).threads == 3


@pytest.mark.parametrize(
    ("bad", "error"), [(0, ValueError), (1 << 16 | 1, ValueError), (1.5, TypeError)]
)
def test_a_bad_thread_count_is_named(bad, error):
    with pytest.raises(error) as got:
        th.ThreadBackend(bad)
    assert str(got.value).startswith("threads must be an integer in [1, 65536], got")
    assert th.ThreadBackend(1 << 16).threads == 1 << 16


def test_the_default_reads_the_affinity_else_the_cpu_count(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 8)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 3}, raising=False)
    assert th.default_threads() == 2  # two of the eight CPUs are this process's
    monkeypatch.delattr(os, "sched_getaffinity", raising=False)  # macOS, Windows
    assert th.default_threads() == 8
    monkeypatch.setattr(os, "cpu_count", lambda: None)  # undeterminable
    assert th.default_threads() == 1


@pytest.fixture
def built(monkeypatch):
    """The batches the backend builds (model, n, threads, persistent), and
    the jobs it runs on which of them (no simulation)."""
    made, ran = [], []

    class FakeBatch:
        def __init__(self, model, n, nthread, persistent=False):
            made.append((model, n, nthread, persistent))

    monkeypatch.setattr(th, "Batch", FakeBatch)
    monkeypatch.setattr(
        th, "run_batch", lambda batch, job: ran.append((batch, job)) or job
    )
    return made, ran


def _job(mjmodel, n, scene=Flat(), p=lm.LocustParams()):
    net = MLP()
    starts = StartStates.concat([StartStates.ready(mjmodel)] * n)
    return RolloutJob(p, net, np.zeros((n, net.num_params)), starts, 3, scene=scene)


def test_one_batch_per_model_scene_and_episode_count(built, mjmodel):
    made, ran = built
    backend = th.ThreadBackend(4)
    five = _job(mjmodel, 5)
    assert backend.run(five) is five
    backend.run(five)
    assert len(made) == 1 and ran[0][0] is ran[1][0]  # built once, reused
    model, n, nthread, persistent = made[0]
    assert (n, nthread, persistent) == (5, 4, True)
    assert model.ngeom == lm.load_model(lm.LocustParams()).ngeom
    backend.run(_job(mjmodel, 2))  # fewer episodes than threads: one each
    assert made[1][1:] == (2, 2, True)
    backend.run(_job(mjmodel, 2, Debris(seed=4)))
    assert made[2][0].ngeom == lm.load_model(lm.LocustParams(), Debris(seed=4)).ngeom
    backend.run(_job(mjmodel, 2, p=lm.LocustParams(substeps=6)))
    assert len(made) == 4 and made[3][0].opt.timestep != made[1][0].opt.timestep


def test_a_closed_backend_runs_nothing(built, mjmodel):
    made, _ = built
    with th.ThreadBackend(2) as backend:
        assert isinstance(backend, th.ThreadBackend)
        backend.run(_job(mjmodel, 1))
    with pytest.raises(RuntimeError) as got:
        backend.run(_job(mjmodel, 1))
    assert str(got.value) == "this ThreadBackend is closed"
    assert len(made) == 1
