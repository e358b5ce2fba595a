"""One episode on one ``MjData`` (``sim/engine/episode.py``), the parts the
bit-for-bit comparison with the engine (``tests/test_rollout.py``) does not
reach: a fresh episode's state, the default start, MuJoCo raising mid-step,
and the reference loop's step count."""

import mujoco
import numpy as np

from locustjump.sim.controller import MLP
from locustjump.sim.engine.episode import Episode, reference_rollout
from locustjump.sim.engine.job import RolloutJob, StartStates
from locustjump.sim.model import LocustParams


def test_a_fresh_episode_is_stable_without_contacts():
    ep = Episode()
    assert ep.unstable is False and ep.contacts is False
    assert ep.penetration == 0.0 and ep.wall_contact == 0.0
    assert type(ep.penetration) is float and type(ep.wall_contact) is float


def test_reset_starts_from_the_first_state_unless_told(mjmodel):
    ready = StartStates.ready(mjmodel)
    moved = StartStates(ready.qpos.copy(), ready.qvel.copy(), ready.ctrl.copy())
    moved.qpos[0, 2] += 0.01  # a centimetre higher
    both = StartStates.concat([ready, moved])
    ep = Episode()
    ep.reset(both)
    np.testing.assert_array_equal(ep.data.qpos, ready.qpos[0])
    assert ep.unstable is False
    ep.reset(both, 1)
    np.testing.assert_array_equal(ep.data.qpos, moved.qpos[0])


def test_mujoco_raising_mid_step_makes_the_episode_unstable(mjmodel, monkeypatch):
    ep = Episode()
    ep.reset(StartStates.ready(mjmodel))
    ep.step(np.zeros((1, 4)))
    assert ep.unstable is False

    def fatal(m, d):
        raise mujoco.FatalError("mj_stackAlloc: out of memory")

    monkeypatch.setattr(mujoco, "mj_step", fatal)
    obs = ep.step(np.zeros((1, 4)))
    assert ep.unstable is True and obs.shape == (1, 9)
    monkeypatch.undo()
    ep.step(np.zeros((1, 4)))
    assert ep.unstable is True  # until the next reset
    ep.reset(StartStates.ready(mjmodel))
    assert ep.unstable is False


def test_the_reference_loop_counts_its_control_steps(mjmodel):
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(0), 2)
    starts = StartStates.concat([StartStates.ready(mjmodel)] * 2)
    job = RolloutJob(LocustParams(), net, genomes, starts, 12, engine="numpy")
    res = reference_rollout(job)
    assert res.steps.tolist() == [12, 12] and res.control_steps == 24
    assert res.unstable.tolist() == [False, False]
