"""The engine's compiled path (``engine = "numba"``) against the NumPy
reference: the kernels' arithmetic step by step, bit for bit where it is the
same operations and within a stated tolerance where it is not (the networks),
and the same control flow (blow-ups, frozen records) on both paths."""

import numpy as np
import pytest

from locustjump.sim import actuation, kernels
from locustjump.sim.controller import MLP
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.job import UNSTABLE, went_unstable
from locustjump.sim.engine.rollout import RolloutJob, StartStates, observer
from locustjump.tasks import get_behaviour
from locustjump.tasks.composed import SwitchingController
from locustjump.tasks.rules import RuleController

#: per control step, |compiled - NumPy| of a network's output (rad): the sums
#: run in another order and tanh is Cephes', not NumPy's: 8 ulp of 0.17 rad
NETWORK_TOL = 8 * np.spacing(actuation.MAX_DELTA)


def _vector(f, x):
    return np.array([f(v) for v in x])


def test_tanh_and_exp_are_within_two_ulp_of_numpy():
    rng = np.random.default_rng(0)
    edges = [0.0, -0.0, 0.625, -0.625, 0.62499999, 20.0, 1e-300]
    x = np.concatenate([rng.uniform(-25, 25, 4000), rng.uniform(-1, 1, 4000), edges])
    t = _vector(kernels.tanh, x)
    assert (np.abs(t - np.tanh(x)) <= 2 * np.spacing(np.abs(np.tanh(x)))).all()
    y = np.concatenate([rng.uniform(-700, 700, 4000), rng.uniform(-2, 2, 4000)])
    e = _vector(kernels.exp, y)
    assert (np.abs(e - np.exp(y)) <= 2 * np.spacing(np.exp(y))).all()


@pytest.fixture(scope="module")
def states(params):
    """Real states: 40 getup episodes (5 start states x 8 random networks) on
    the NumPy path, every 10th control step of 300."""
    beh = get_behaviour("getup")
    genomes = MLP().random_genomes(np.random.default_rng(2), 8)
    res = beh.simulate(genomes, params, record=("qpos", "obs", "ctrl"),
                       backend=ThreadBackend(2), engine="numpy")  # fmt: skip
    pick = slice(0, 300, 10)
    n = res["qpos"].shape[0]
    flat = {k: res[k][:, pick].reshape(-1, res[k].shape[-1]) for k in res.records}
    return flat, np.repeat(genomes, n // 8, axis=0), n


def test_observation_and_actuation_are_bit_identical(states, mjmodel, params):
    from locustjump.sim import model as lm

    flat, _, _ = states
    qpos = flat["qpos"]
    idx = lm.ModelIndex.of(mjmodel)
    rng = np.random.default_rng(3)
    sens = rng.normal(0.0, 1.0, (len(qpos), mjmodel.nsensordata))  # touch +-
    want = observer(idx, params)(qpos, sens)
    got = np.empty((9, len(qpos)))
    kernels.observe(qpos, sens, np.asarray(idx.qpos_joints), np.asarray(idx.touch),
                    params.body_length, got)  # fmt: skip
    np.testing.assert_array_equal(got.T, want)
    deltas = rng.uniform(-0.5, 0.5, (len(qpos), 4))  # beyond +-10 deg too
    ctrl = flat["ctrl"].copy()
    want = actuation.apply_deltas(ctrl, deltas, idx.ranges)
    lo, hi = idx.ranges[:, 0].copy(), idx.ranges[:, 1].copy()
    d = np.ascontiguousarray(deltas.T)
    kernels.actuate(ctrl, d, lo, hi, np.zeros(len(ctrl), bool), False)
    np.testing.assert_array_equal(ctrl, want)


def test_the_kernel_applies_the_one_unstable_rule(mjmodel):
    """kernels.sense_and_check flags what job.went_unstable decides, among the
    episodes not yet stopped, and reduces the touch sensors of ``ids``."""
    rng = np.random.default_rng(6)
    n, nw = 40, UNSTABLE.stop
    qpos = rng.normal(size=(n, mjmodel.nq))
    qpos[rng.random(n) < 0.2, rng.integers(mjmodel.nq)] = np.nan
    qpos[3, 0], qpos[4, 1] = np.inf, -np.inf
    warning = np.zeros((n, nw, 2), np.int32)
    warning[rng.random(n) < 0.2, rng.integers(nw), 1] = 1
    warning[:, :, 0] = 7  # lastinfo: not a count
    unstable = rng.random(n) < 0.3
    want = went_unstable(qpos, warning[..., 1]) & ~unstable
    assert 0 < want.sum() < n
    ids = np.flatnonzero(~unstable)
    sub = rng.normal(size=(len(ids), 3, mjmodel.nsensordata))
    sens, newly = np.zeros((n, mjmodel.nsensordata)), np.zeros(n, bool)
    count = kernels.sense_and_check(sub, ids, sens, qpos, warning, unstable, newly)
    np.testing.assert_array_equal(newly, want)
    assert count == want.sum()
    np.testing.assert_array_equal(sens[ids], sub.max(axis=1))
    errors = went_unstable(np.zeros((n, 3)), np.zeros((n, nw)), np.array([5]))
    assert errors.tolist() == [e == 5 for e in range(n)]


def test_network_step_is_within_the_stated_tolerance(states):
    flat, genomes, n = states
    net = MLP()
    g = np.repeat(genomes, len(flat["obs"]) // len(genomes), axis=0)
    want = net.apply(net.prepare(g), flat["obs"])
    _, w, out = net.kernel(net.prepare(g))
    got = np.empty((4, len(g)))
    kernels.mlp(*w, kernels.soa(flat["obs"]), got, np.empty((10, len(g))), out)
    err = np.abs(got.T - want)
    assert err.max() <= NETWORK_TOL, err.max()
    assert (err == 0).mean() > 0.3  # most outputs agree exactly


def test_switching_step_picks_the_same_network(states):
    flat, genomes, _ = states
    obs = flat["obs"]
    rng = np.random.default_rng(4)
    ctl = SwitchingController(simple=genomes[:3])
    params = rng.uniform(-1, 1, (len(obs), ctl.num_params))
    prepared = ctl.prepare(params)
    want_d, want_m = ctl.act(prepared, np.zeros((len(obs), 1)), obs, None, 0)
    _, sw, nets, every = ctl.kernel(prepared)
    memory, got = np.zeros((len(obs), 1)), np.empty((4, len(obs)))
    kernels.switch(0, every, sw, nets, memory, kernels.soa(obs), got,
                   np.empty((3, len(obs))), np.empty((4, len(obs))),
                   np.empty((10, len(obs))))  # fmt: skip
    np.testing.assert_array_equal(memory, want_m)
    assert np.abs(got.T - want_d).max() <= NETWORK_TOL


@pytest.mark.parametrize("blowups", [[1], [0, 1, 2]])
def test_blowups_are_handled_alike_on_both_paths(params, mjmodel, blowups):
    """No network (the rule-based controller): both paths are the same
    arithmetic, so records, failure steps and frozen rows agree bit for bit,
    also when every episode fails."""
    rc = RuleController.for_model(params)
    starts = StartStates.ready(mjmodel).take([0, 0, 0])
    starts.qvel[blowups, :] = 1e30
    runs = {}
    for engine in ("numpy", "numba"):
        job = RolloutJob(params, rc, rc.params_for([0.0, 0.25, 0.5]), starts, 60,
                         ("qpos", "obs", "ctrl", "memory"), engine=engine)  # fmt: skip
        runs[engine] = ThreadBackend(2).run(job)
    a, b = runs["numpy"], runs["numba"]
    assert a.unstable.tolist() == [e in blowups for e in range(3)]
    for k in a.records:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    np.testing.assert_array_equal(a.steps, b.steps)
    assert a.control_steps == b.control_steps
