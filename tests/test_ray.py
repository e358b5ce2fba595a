"""The Ray backend: bit-identical to the thread backend for any number of
actors, and a killed actor is replaced without changing the result. One local
Ray instance (2 CPUs, conftest) serves the whole session."""

import os
import signal
import threading
import time

import numpy as np
import pytest

ray = pytest.importorskip("ray", reason="Ray is not installed (extra locustjump[ray])")

from helpers import assert_same_run  # noqa: E402
from locustjump import rundir  # noqa: E402
from locustjump.cli import main  # noqa: E402
from locustjump.evo import RCGAParams  # noqa: E402
from locustjump.rundir.config import TrainConfig  # noqa: E402
from locustjump.runs.trainer import train  # noqa: E402
from locustjump.sim.controller import MLP  # noqa: E402
from locustjump.sim.engine.backends import ThreadBackend, make_backend  # noqa: E402
from locustjump.sim.engine.rollout import RolloutJob, StartStates  # noqa: E402

SMALL = TrainConfig(generations=3, optimizer=RCGAParams(population=6), seed=5)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    out = tmp_path_factory.mktemp("threads") / "run"
    train(SMALL, out, progress=False, backend=ThreadBackend(2))
    return out


@pytest.mark.parametrize("actors", [1, 2, 3])
def test_ray_is_bit_identical_to_threads(local_ray, reference, tmp_path, actors):
    backend = make_backend("ray", actors=actors)
    out = tmp_path / "run"
    train(SMALL, out, progress=False, backend=backend)
    assert_same_run(reference, out)
    # close() gives the actors' CPUs back at once (another backend may need them)
    backend.close()
    deadline = time.monotonic() + 30
    while ray.available_resources().get("CPU", 0) < 2:
        assert time.monotonic() < deadline, ray.available_resources()
        time.sleep(0.05)


def _job(params, n_steps: int) -> RolloutJob:
    from locustjump.sim.model import LocustParams, load_model

    p = LocustParams()
    starts = StartStates.ready(load_model(p))
    n = params.shape[0]
    return RolloutJob(p, MLP(), params, starts.take([0] * n), n_steps, ("qpos",))


def test_a_killed_actor_is_replaced_and_the_result_is_the_same(local_ray):
    # long enough (~1 s per actor on a fast machine) that the kill lands
    # while the generation runs; the test checks that it did
    params = MLP().random_genomes(np.random.default_rng(3), 8)
    job = _job(params, 20_000)
    expected = ThreadBackend(2).run(job)
    backend = make_backend("ray", actors=2)
    victim = backend.pids()[1]
    result = {}
    worker = threading.Thread(target=lambda: result.update(r=backend.run(job)))
    worker.start()
    time.sleep(0.2)
    os.kill(victim, signal.SIGKILL)
    assert "r" not in result, "the rollout ended before the kill; lengthen it"
    worker.join(timeout=300)
    np.testing.assert_array_equal(result["r"]["qpos"], expected["qpos"])
    assert backend.replaced == 1
    assert victim not in backend.pids() and backend.replaced == 1
    # an actor that dies between generations is replaced on the next one
    os.kill(backend.pids()[0], signal.SIGKILL)
    short = _job(params[:4], 200)
    np.testing.assert_array_equal(
        backend.run(short)["qpos"], ThreadBackend(1).run(short)["qpos"]
    )
    assert backend.replaced == 2


def test_ray_bad_input(local_ray, tmp_path, capsys):
    out = tmp_path / "run"
    # more CPUs per actor than the cluster has
    assert main(["train", "kick", "--backend", "ray", "--threads", "64", "--out",
                 str(out)]) == 2  # fmt: skip
    assert "has 2 CPUs" in capsys.readouterr().err and not out.exists()
    # --address with the thread backend
    assert main(["train", "kick", "--address", "auto", "--out", str(out)]) == 2
    assert "--backend ray" in capsys.readouterr().err and not out.exists()


def test_an_address_nobody_listens_on_fails_fast(tmp_path, capsys):
    import subprocess
    import sys

    out = tmp_path / "run"
    t0 = time.monotonic()
    r = subprocess.run(
        [sys.executable, "-m", "locustjump.cli", "train", "kick", "--backend", "ray",
         "--address", "127.0.0.1:9", "--out", str(out)],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    # fails at once: seconds of start-up (about 3 s here), with room for a
    # loaded machine
    assert r.returncode == 2 and time.monotonic() - t0 < 45
    assert "--address 127.0.0.1:9" in r.stderr and len(r.stderr.splitlines()) == 1
    assert not out.exists() and not rundir.is_run(out)
