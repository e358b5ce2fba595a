"""``rollout`` (``sim/engine/rollout.py``), the engine's entry point: the job
it builds from its arguments (controller-major episodes, every option handed
on), the memory check it makes first, and the backend it runs on."""

import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine import rollout as ro
from locustjump.sim.scene import Debris

P = lm.LocustParams()


class Capture:
    """A backend that keeps the job it is given and runs it nowhere."""

    def __init__(self) -> None:
        self.jobs: list[ro.RolloutJob] = []

    def run(self, job: ro.RolloutJob) -> str:
        self.jobs.append(job)
        return "ran"


def _starts(k: int) -> ro.StartStates:
    one = ro.StartStates.ready(lm.load_model(P))
    s = ro.StartStates.concat([one] * k)
    s.qpos[:, 0] = np.arange(k)  # each start state told apart by its x
    return s


def test_the_job_has_every_controller_from_every_start_controller_major():
    net, backend = MLP(), Capture()
    genomes = np.arange(3 * net.num_params, dtype=np.float64).reshape(3, -1)
    out = ro.rollout(net, genomes, _starts(2), 7, backend=backend, model_params=P)
    assert out == "ran"
    (job,) = backend.jobs
    np.testing.assert_array_equal(job.params, genomes[[0, 0, 1, 1, 2, 2]])
    np.testing.assert_array_equal(job.starts.qpos[:, 0], [0, 1, 0, 1, 0, 1])
    assert job.n_steps == 7 and job.controller is net and job.model_params is P


def test_every_option_is_handed_on_to_the_job():
    net, backend = MLP(), Capture()
    scene, p = Debris(seed=3), P.replace(substeps=4)
    ro.rollout(
        net, np.zeros(net.num_params), _starts(1), 5, model_params=p,
        record=["qpos", "ctrl"], backend=backend, label="look", engine="numpy",
        scene=scene,
    )  # fmt: skip
    (job,) = backend.jobs
    assert job.record == ("qpos", "ctrl") and isinstance(job.record, tuple)
    assert (job.label, job.engine, job.scene, job.model_params) == (
        "look", "numpy", scene, p,
    )  # fmt: skip
    # one genome as a row of integers: one controller, in float64
    assert job.params.shape == (1, net.num_params) and job.params.dtype == np.float64
    ro.rollout(net, np.zeros(net.num_params, dtype=int), _starts(1), 5, backend=backend)
    assert backend.jobs[1].params.dtype == np.float64
    assert backend.jobs[1].record == ("qpos", "obs") and backend.jobs[1].label == ""
    assert backend.jobs[1].engine == ro.DEFAULT_ENGINE
    assert backend.jobs[1].scene == ro.Flat() and backend.jobs[1].model_params == P


class Remembering(MLP):
    """The paper's network with 5 numbers of memory (as the switcher has)."""

    @property
    def memory_size(self) -> int:
        return 5


def test_the_memory_is_checked_first_for_every_episode(monkeypatch):
    asked = []
    monkeypatch.setattr(ro, "require_memory", lambda *a, **kw: asked.append((a, kw)))
    net, backend = Remembering(), Capture()
    genomes = np.zeros((3, net.num_params))
    record = ("qpos", "memory")
    ro.rollout(net, genomes, _starts(2), 9, backend=backend, record=record)
    (((need, what), kw),) = asked
    m = lm.load_model(P)
    assert need == ro.rollout_bytes(m, 6, 9, record, 5)
    assert need - ro.rollout_bytes(m, 6, 9, record, 1) == 6 * 10 * 4 * 8  # 4 more
    assert what == "a rollout of 6 episodes x 9 steps"
    assert kw == {"setting": ("n_steps", 9)}


def test_a_rollout_too_big_is_refused_before_it_starts(monkeypatch):
    monkeypatch.setattr("locustjump.sim.resources.available_bytes", lambda: 1 << 20)
    backend = Capture()
    with pytest.raises(UserError, match=r"a rollout of 2,000 episodes x 3,000 steps"):
        ro.rollout(MLP(), np.zeros((1000, MLP().num_params)), _starts(2), 3000,
                   backend=backend)  # fmt: skip
    assert backend.jobs == []


@pytest.mark.parametrize("n_steps", [0, -1, 2.5])
def test_n_steps_must_be_a_whole_positive_number(n_steps):
    with pytest.raises(UserError, match=r"^n_steps must be an integer"):
        ro.rollout(MLP(), np.zeros(MLP().num_params), _starts(1), n_steps,
                   backend=Capture())  # fmt: skip


def test_without_a_backend_one_is_made_for_the_call_and_closed(monkeypatch):
    made = []

    class Own(Capture):
        def __enter__(self):
            made.append(self)
            return self

        def __exit__(self, *exc):
            self.closed = True

    monkeypatch.setattr(ro, "ThreadBackend", Own)
    assert ro.rollout(MLP(), np.zeros(MLP().num_params), _starts(1), 3) == "ran"
    (own,) = made
    assert len(own.jobs) == 1 and own.closed
