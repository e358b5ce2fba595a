"""The paper's rules as a controller (:mod:`locustjump.tasks.rules`), step by
step on made-up inputs: the touch timer, the change time, the kick and the
return to phi at the servo's rate, and the get-up network taking over while
overturned (the NumPy engine's; the compiled kernels are checked against it
by ``tests/test_engine.py``)."""

import numpy as np
import pytest

from helpers import exactly
from locustjump.sim.actuation import MAX_DELTA
from locustjump.sim.controller import MLP
from locustjump.sim.params import CONTROL_DT, LocustParams
from locustjump.tasks.rules import RuleController, RuleGetupController

READY = (1.0, 0.2, 1.0, 0.2)
KICK = (0.5, 2.0, 0.5, 2.0)


def _obs(touch, up=1.0, low=0.5, n=1):
    """Inputs of ``n`` episodes: I5 (touch) below 0 when touching, I6 the
    height's, I9 U_z."""
    o = np.zeros((n, 9))
    o[:, 4] = -1.0 if touch else 1.0
    o[:, 5], o[:, 8] = low, up
    return o


def test_the_controller_of_a_creature():
    p = LocustParams()
    r = RuleController.for_model(p)
    assert r.ready == tuple(p.ready_angles()) and r.extended == tuple(p.kick_angles())
    assert r.rate == MAX_DELTA and r.num_params == 1 and r.memory_size == 1
    assert RuleController.for_model().ready == r.ready


def test_a_change_time_is_whole_control_steps():
    got = RuleController.params_for([0.0, 0.5, 1 / 240 + 1e-9])
    assert got.shape == (3, 1) and got[:, 0].tolist() == [0.0, 60.0, 1.0]
    assert RuleController.params_for(0.1).tolist() == [[round(0.1 / CONTROL_DT)]]
    with pytest.raises(ValueError, match=exactly("change time must be >= 0 seconds")):
        RuleController.params_for([0.1, -0.01])
    r = RuleController(READY, KICK)
    assert r.prepare(np.array([[3], [5]])).tolist() == [3.0, 5.0]


def test_touching_counts_up_and_lifting_resets():
    r = RuleController(READY, KICK, rate=10.0)
    change = np.array([2.0])
    memory = np.zeros((1, 1))
    targets = np.array([READY])
    seen = []
    for touch in (True, True, False, True, True, True):
        deltas, memory = r.act(change, memory, _obs(touch), targets, 0)
        targets = targets + deltas
        seen.append((memory[0, 0], tuple(targets[0])))
    assert [m for m, _ in seen] == [1.0, 2.0, 0.0, 1.0, 2.0, 3.0]
    # at the change time (2 steps touching) the legs kick; lifted, back to phi
    expected = [READY, KICK, READY, READY, KICK, KICK]
    np.testing.assert_allclose([t for _, t in seen], expected, rtol=0, atol=1e-15)


def test_the_servo_targets_move_at_most_the_rate():
    r = RuleController(READY, KICK)
    targets = np.array([READY, KICK, READY])
    obs = np.concatenate([_obs(True), _obs(False), _obs(True)])
    memory = np.array([[5.0], [5.0], [0.0]])
    deltas, memory = r.act(np.array([3.0, 3.0, 3.0]), memory, obs, targets, 7)
    assert memory[:, 0].tolist() == [6.0, 0.0, 1.0]
    step = np.clip(np.subtract(KICK, READY), -MAX_DELTA, MAX_DELTA)
    np.testing.assert_array_equal(deltas[0], step)  # kicking: at the rate
    np.testing.assert_array_equal(deltas[1], -step)  # lifted: back to phi
    np.testing.assert_array_equal(deltas[2], np.zeros(4))  # touching, not yet


def test_touching_is_an_input_below_zero():
    r = RuleController(READY, KICK)
    obs = np.zeros((3, 9))
    obs[:, 4] = [-1e-9, 0.0, 0.5]
    _, memory = r.act(np.zeros(3), np.zeros((3, 1)), obs, np.array([READY] * 3), 0)
    assert memory[:, 0].tolist() == [1.0, 0.0, 0.0]


def test_an_episode_at_change_time_zero_kicks_on_its_first_touch():
    r = RuleController(READY, KICK, rate=10.0)
    deltas, memory = r.act(np.array([0.0]), np.zeros((1, 1)), _obs(False),
                           np.array([READY]), 0)  # fmt: skip
    assert memory[0, 0] == 0.0 and not deltas.any()  # in the air: phi
    deltas, memory = r.act(np.array([0.0]), memory, _obs(True), np.array([READY]), 1)
    assert memory[0, 0] == 1.0
    np.testing.assert_array_equal(deltas[0], np.subtract(KICK, READY))


def _getup(below=0.5, low=0.0):
    return RuleGetupController(RuleController(READY, KICK, rate=10.0), below, low)


def test_the_getup_network_drives_while_overturned():
    g = _getup()
    assert g.num_params == 145 and g.memory_size == 1
    genome = np.random.default_rng(0).normal(size=144)
    params = RuleGetupController.params_for(0.05, genome)
    assert params.shape == (1, 145) and params[0, 0] == 6.0
    np.testing.assert_array_equal(params[0, 1:], genome)
    prepared = g.prepare(params)
    assert prepared[0].tolist() == [6.0]
    obs = np.concatenate([_obs(True, up=0.2), _obs(True, up=0.5), _obs(True)])
    targets = np.array([READY] * 3)
    change = (np.repeat(prepared[0], 3), MLP().prepare(np.repeat(params[:, 1:], 3, 0)))
    deltas, memory = g.act(change, np.zeros((3, 1)), obs, targets, 0)
    net = MLP().apply(change[1], obs)
    np.testing.assert_array_equal(deltas[0], net[0])  # overturned: the network
    assert deltas.dtype == np.float64
    np.testing.assert_array_equal(deltas[1:], np.zeros((2, 4)))  # 0.5, upright: rules
    assert memory[:, 0].tolist() == [1.0, 1.0, 1.0]  # the timer keeps counting


def test_the_getup_network_waits_until_the_body_is_low():
    g = _getup(low=0.4)
    genome = np.random.default_rng(1).normal(size=144)
    prepared = g.prepare(RuleGetupController.params_for(1.0, genome))
    high, low = _obs(False, up=0.0, low=0.3), _obs(False, up=0.0, low=0.4)
    for obs, network in ((high, False), (low, True)):
        deltas, _ = g.act(prepared, np.zeros((1, 1)), obs, np.array([READY]), 0)
        net = MLP().apply(prepared[1], obs)
        assert np.array_equal(deltas, net) == network
