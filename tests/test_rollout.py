"""The batched engine against the single-MjData reference, and determinism."""

import dataclasses

import numpy as np
import pytest
from mujoco.batch import Batch

from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine import strategies
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.episode import reference_rollout
from locustjump.sim.engine.job import ENGINES, RECORDABLE
from locustjump.sim.engine.rollout import (
    RolloutJob,
    RolloutResult,
    StartStates,
    rollout,
)
from locustjump.sim.engine.strategies import STRATEGIES, run_batch
from locustjump.sim.scene import Debris
from locustjump.tasks.composed import SwitchingController
from locustjump.tasks.rules import RuleController
from locustjump.tasks.starts import ready_state

RECORD = ("qpos", "obs", "ctrl", "memory")


def _equal(a: RolloutResult, b: RolloutResult) -> None:
    for k in a.records:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    np.testing.assert_array_equal(a.unstable, b.unstable)
    np.testing.assert_array_equal(a.steps, b.steps)


@pytest.fixture(scope="module", params=ENGINES)
def mlp_job(request, params, mjmodel):
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(7), 5, scale=2.0)
    starts = StartStates.ready(mjmodel)
    return RolloutJob(params, net, genomes, starts.take([0] * 5), 120, RECORD,
                      engine=request.param)  # fmt: skip


def test_engine_matches_reference_mlp(mlp_job):
    got, ref = ThreadBackend(2).run(mlp_job), reference_rollout(mlp_job)
    if mlp_job.engine == "numpy":
        _equal(got, ref)  # the reference is the NumPy path, episode by episode
    else:  # the compiled networks differ by ulps a step; 120 steps grow them
        for k in got.records:
            np.testing.assert_allclose(got[k], ref[k], rtol=0, atol=1e-9, err_msg=k)
        np.testing.assert_array_equal(got.steps, ref.steps)


@pytest.mark.parametrize("engine", ENGINES)
def test_engine_matches_reference_rules(params, mjmodel, engine):
    # no network: both paths are the same arithmetic, bit for bit
    rc = RuleController.for_model(params)
    job = RolloutJob(
        params,
        rc,
        rc.params_for([0.0, 0.25, 0.5]),
        StartStates.ready(mjmodel).take([0, 0, 0]),
        200,
        RECORD,
        engine=engine,
    )
    _equal(ThreadBackend(2).run(job), reference_rollout(job))


def test_every_engine_name_has_a_strategy():
    assert set(ENGINES) <= set(STRATEGIES)


def _on_batch(strategy: str, job: RolloutJob, threads: int = 2) -> RolloutResult:
    m = lm.load_model(job.model_params)
    return STRATEGIES[strategy](Batch(m, job.n_episodes, threads, persistent=True), job)


def _blowup_starts(mjmodel, k: int, blowups) -> StartStates:
    """``k`` ready states, those in ``blowups`` with a velocity that fails at
    once (1e30) or a few steps later (300)."""
    starts = StartStates.ready(mjmodel).take([0] * k)
    for e, v in blowups.items():
        starts.qvel[e, :] = v
    return starts


@pytest.mark.parametrize("strategy", list(STRATEGIES))
def test_every_strategy_gives_the_numpy_records_without_networks(
    params, mjmodel, strategy
):
    """The rule-based controller (no network): every strategy does the NumPy
    reference's arithmetic, so records, failures, steps and the count of
    control steps agree bit for bit, with episodes failing at once and later,
    and with every episode failing."""
    rc = RuleController.for_model(params)
    for blowups in ({1: 1e30, 3: 300.0}, {0: 1e30, 1: 1e30, 2: 300.0, 3: 1e30}):
        job = RolloutJob(params, rc, rc.params_for([0.0, 0.25, 0.5, 0.1]),
                         _blowup_starts(mjmodel, 4, blowups), 80, RECORD)  # fmt: skip
        want = _on_batch("numpy", job)
        assert want.unstable.tolist() == [e in blowups for e in range(4)]
        got = _on_batch(strategy, job)
        _equal(got, want)
        assert got.control_steps == want.control_steps
        ref = reference_rollout(job)
        np.testing.assert_array_equal(want.steps, ref.steps)
        np.testing.assert_array_equal(want.unstable, ref.unstable)
        # at its start state (1e30) the batch records the state MuJoCo's
        # forward() reset it to, the reference the start state: compare the rest
        later = want.steps > 1
        for k in want.records:
            np.testing.assert_array_equal(want[k][later], ref[k][later], err_msg=k)


@pytest.mark.parametrize("strategy", list(STRATEGIES))
@pytest.mark.parametrize("controller", ["mlp", "switch"])
def test_every_strategy_gives_the_numpy_records_with_networks(
    params, mjmodel, strategy, controller
):
    """Networks: the compiled strategies sum in another order (within a few
    ulp a step, tests/test_engine.py), so records agree closely and failures
    and steps exactly; the NumPy strategy is the reference itself."""
    rng = np.random.default_rng(11)
    simple = MLP().random_genomes(rng, 3)
    ctl = MLP() if controller == "mlp" else SwitchingController(simple=simple, every=7)
    genomes = rng.uniform(-1, 1, (5, ctl.num_params))
    job = RolloutJob(params, ctl, genomes, _blowup_starts(mjmodel, 5, {2: 300.0}),
                     90, RECORD)  # fmt: skip
    want, got = _on_batch("numpy", job), _on_batch(strategy, job)
    assert want.unstable.tolist() == [False, False, True, False, False]
    np.testing.assert_array_equal(got.unstable, want.unstable)
    np.testing.assert_array_equal(got.steps, want.steps)
    assert got.control_steps == want.control_steps
    for k in want.records:
        np.testing.assert_allclose(got[k], want[k], rtol=0, atol=1e-9, err_msg=k)
    if strategy == "numpy":
        _equal(got, reference_rollout(job))


def test_run_batch_runs_the_strategy_the_job_names(params, mjmodel, monkeypatch):
    rc = RuleController.for_model(params)
    job = RolloutJob(params, rc, rc.params_for([0.0]), StartStates.ready(mjmodel), 5)
    batch = Batch(lm.load_model(params), 1, 1, persistent=True)
    ran = []
    monkeypatch.setitem(STRATEGIES, "spy", lambda b, j: ran.append((b, j)))
    monkeypatch.setattr(strategies, "strategy_name", lambda j: "spy")
    run_batch(batch, job)
    assert ran == [(batch, job)]
    monkeypatch.setattr(strategies, "strategy_name", lambda j: "warp")
    with pytest.raises(ValueError, match="unknown engine strategy 'warp'"):
        run_batch(batch, job)


def test_same_result_any_threads_and_split(mlp_job):
    one = ThreadBackend(1).run(mlp_job)
    _equal(one, ThreadBackend(2).run(mlp_job))
    for k in (2, 3, 5):
        parts = [ThreadBackend(2).run(j) for j in mlp_job.split(k)]
        _equal(one, RolloutResult.concat(parts))


def test_rollout_is_controller_major(params, mjmodel):
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(3), 3)
    starts = StartStates.ready(mjmodel)
    two = StartStates.concat([starts, starts])
    two.qpos[1, 0] = 0.5  # second start state shifted along x
    res = rollout(net, genomes, two, 10, model_params=params)
    assert res["qpos"].shape == (6, 11, mjmodel.nq)
    assert res["qpos"][0, 0, 0] == 0.0 and res["qpos"][1, 0, 0] == 0.5
    single = rollout(net, genomes[1:2], two.take([1]), 10, model_params=params)
    np.testing.assert_array_equal(res["qpos"][3], single["qpos"][0])


def test_unstable_episode_is_flagged_and_others_go_on(params, mjmodel):
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(5), 3)
    starts = StartStates.ready(mjmodel).take([0, 0, 0])
    calm = ThreadBackend(2).run(RolloutJob(params, net, genomes, starts, 50))
    starts.qvel[1, :] = 1e30  # blows up at once
    res = ThreadBackend(2).run(RolloutJob(params, net, genomes, starts, 50))
    assert res.unstable.tolist() == [False, True, False]
    assert res.steps[1] < 50
    assert np.isfinite(res["qpos"][1]).all()  # records stay finite
    for e in (0, 2):
        np.testing.assert_array_equal(res["qpos"][e], calm["qpos"][e])
    ref = reference_rollout(RolloutJob(params, net, genomes, starts, 50))
    assert ref.unstable.tolist() == [False, True, False]


def test_job_validation(params, mjmodel):
    net = MLP()
    starts = StartStates.ready(mjmodel)
    with pytest.raises(ValueError, match="params has shape"):
        RolloutJob(params, net, np.zeros((1, 3)), starts, 10)
    with pytest.raises(ValueError, match="n_steps"):
        RolloutJob(params, net, np.zeros((1, 144)), starts, 0)
    with pytest.raises(ValueError, match="cannot record"):
        RolloutJob(params, net, np.zeros((1, 144)), starts, 5, ("xpos",))


def test_a_thread_backend_is_closed_by_its_context_manager(params):
    from locustjump.sim.engine.backends import make_backend
    from locustjump.sim.model import load_model

    m = load_model(params)
    net = MLP()
    g = net.random_genomes(np.random.default_rng(0), 2)
    with make_backend("threads", threads=1) as b:
        a = rollout(net, g, StartStates.ready(m), 5, model_params=params, backend=b)
    np.testing.assert_array_equal(
        a["qpos"], rollout(net, g, StartStates.ready(m), 5, model_params=params)["qpos"]
    )
    with pytest.raises(RuntimeError, match="closed"):
        b.run(None)


def _walled_job(p: lm.LocustParams, ctl, params, record):
    """Four episodes in a walled debris field: thrown sideways and backwards
    at the walls (6 m/s), left alone, and blown up after a few steps."""
    scene = Debris(seed=2)
    s = ready_state(p, scene)
    starts = StartStates(*(np.repeat(a, 4, axis=0) for a in (s.qpos, s.qvel, s.ctrl)))
    starts.qvel[0, :3] = (0.0, 6.0, 2.0)
    starts.qvel[1, :3] = (-6.0, 0.0, 2.0)
    starts.qvel[3, :] = 300.0
    return RolloutJob(p, ctl, params, starts, 150, record, scene=scene)


@pytest.mark.parametrize("strategy", list(STRATEGIES))
def test_contact_records_are_the_references_on_every_strategy(params, strategy):
    """penetration and wall_contact (from the contact sensors, reduced over
    the substeps by the loop) are bit for bit those the reference reads from
    MuJoCo's contacts after every substep, on every strategy; a creature
    thrown at a wall touches it, one left alone in the field does not."""
    rc = RuleController.for_model(params)
    job = _walled_job(params, rc, rc.params_for([0.0, 0.25, 0.5, 0.1]), RECORDABLE)
    m = lm.load_model(params, job.scene)
    got = STRATEGIES[strategy](Batch(m, 4, 2, persistent=True), job)
    ref = reference_rollout(job)
    assert got.unstable.tolist() == [False, False, False, True]
    _equal(got, ref)
    pen, wall = got["penetration"], got["wall_contact"]
    assert pen.shape == wall.shape == (4, 151)
    assert (wall[:2].sum(axis=1) > 0).all() and (wall[2] == 0).all()
    assert set(np.unique(wall)) <= {0.0, 1.0}
    assert (pen >= 0).all() and (pen[:3].max(axis=1) > 0).all()
    assert (pen[3, got.steps[3] :] == pen[3, got.steps[3]]).all()  # frozen


@pytest.mark.parametrize("strategy", list(STRATEGIES))
def test_recording_contacts_changes_no_other_record(params, strategy):
    """Networks too: the other records of a job that also records contacts
    are bit for bit those of the same job without (the in-callback strategy
    runs it on its step-by-step loop, whose numbers are its own)."""
    rng = np.random.default_rng(4)
    genomes = MLP().random_genomes(rng, 4, scale=2.0)
    job = _walled_job(params, MLP(), genomes, RECORD)
    both = dataclasses.replace(job, record=RECORDABLE)
    m = lm.load_model(params, job.scene)
    plain = STRATEGIES[strategy](Batch(m, 4, 2, persistent=True), job)
    more = STRATEGIES[strategy](Batch(m, 4, 2, persistent=True), both)
    for k in RECORD:
        np.testing.assert_array_equal(more[k], plain[k], err_msg=k)
    np.testing.assert_array_equal(more.steps, plain.steps)
    np.testing.assert_array_equal(more.unstable, plain.unstable)
