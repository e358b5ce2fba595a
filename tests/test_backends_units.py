"""Choosing where and how a rollout runs, by name (``sim/engine/backends.py``,
``sim/engine/strategies.py``): each backend with the settings it takes, the
strategy a job names, and the words of a wrong name."""

import pytest

from locustjump.errors import UserError
from locustjump.sim.engine import backends, strategies
from locustjump.sim.engine.threads import ThreadBackend


def test_threads_is_the_default_backend_and_takes_its_thread_count():
    b = backends.make_backend(threads=3)
    assert type(b) is ThreadBackend and b.threads == 3
    assert backends.make_backend("threads").threads == ThreadBackend().threads
    assert backends.BACKENDS == ("threads", "ray")


@pytest.mark.parametrize("kw", [{"address": "auto"}, {"actors": 2}])
def test_ray_settings_are_refused_for_threads(kw):
    with pytest.raises(UserError) as got:
        backends.make_backend("threads", **kw)
    assert str(got.value) == "address and actors are for backend ray"


def test_ray_gets_its_address_actors_and_threads(monkeypatch):
    made = []
    monkeypatch.setattr(
        backends, "RayBackend", lambda *a, **kw: made.append((a, kw)) or "ray"
    )
    assert backends.make_backend("ray", threads=2, address="auto", actors=5) == "ray"
    assert made == [(("auto",), {"actors": 5, "threads": 2})]


def test_an_unknown_backend_is_named_with_the_choices():
    with pytest.raises(ValueError) as got:
        backends.make_backend("mpi")
    assert str(got.value) == "unknown backend 'mpi'; choose from threads, ray"


def test_a_job_runs_on_the_strategy_it_names(monkeypatch):
    calls = []
    fake = {"numpy": lambda b, j: calls.append(("numpy", b, j)) or "N",
            "other": lambda b, j: calls.append(("other", b, j)) or "O"}  # fmt: skip
    monkeypatch.setattr(strategies, "STRATEGIES", fake)
    job = type("Job", (), {"engine": "other"})()
    assert strategies.run_batch("batch", job) == "O"
    assert calls == [("other", "batch", job)]
    job.engine = "gpu"
    with pytest.raises(ValueError) as got:
        strategies.run_batch("batch", job)
    assert str(got.value) == "unknown engine strategy 'gpu'; choose from numpy, other"


def test_the_engines_strategies():
    assert list(strategies.STRATEGIES) == ["numpy", "numba-loop", "numba"]
    from locustjump.sim.engine.compiled import run_compiled
    from locustjump.sim.engine.incallback import run_incallback
    from locustjump.sim.engine.numpy_step import run_numpy

    assert strategies.STRATEGIES["numpy"] is run_numpy
    assert strategies.STRATEGIES["numba-loop"] is run_compiled
    assert strategies.STRATEGIES["numba"] is run_incallback
