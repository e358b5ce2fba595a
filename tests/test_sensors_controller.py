import mujoco
import numpy as np

from locustjump.sim import actuation, sensors
from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine.rollout import observer


def test_up_axis_is_third_row_of_rotation(rng):
    quats = rng.normal(size=(20, 4))
    quats /= np.linalg.norm(quats, axis=1, keepdims=True)
    got = sensors.up_axis_in_body(quats)
    for q, row in zip(quats, got, strict=True):
        mat = np.zeros(9)
        mujoco.mju_quat2Mat(mat, q)
        np.testing.assert_allclose(row, mat.reshape(3, 3)[2], atol=1e-12)


def test_paper_inputs_at_start(params, mjmodel):
    d = mujoco.MjData(mjmodel)
    idx = lm.ModelIndex.of(mjmodel)
    mujoco.mj_resetDataKeyframe(mjmodel, d, idx.ready_key)

    observe_batch = observer(idx, params)

    def observe() -> np.ndarray:
        mujoco.mj_forward(mjmodel, d)
        return observe_batch(d.qpos[None], d.sensordata[None])[0]

    obs = observe()
    np.testing.assert_allclose(obs[:4], params.ready_angles(), atol=np.radians(3))
    assert ((obs[:4] > 0) & (obs[:4] < 2 * np.pi)).all()
    assert obs[4] == -1.0  # tarsi touch while standing
    assert obs[5] == 1.0 / (d.qpos[2] / params.body_length + 1.0)
    assert obs[8] > 0.99  # upright
    # lifted into the air: touch off
    d.qpos[2] += 1.0
    obs = observe()
    assert obs[4] == 1.0


def test_apply_deltas_limits_rate_and_range(params):
    r = lm.ModelIndex.of(lm.load_model(params)).ranges
    targets = np.array([[r[0, 0], r[1, 1], 1.0, 1.0]])
    out = actuation.apply_deltas(targets, np.array([[-1.0, 1.0, 1.0, -0.01]]), r)
    np.testing.assert_allclose(
        out, [[r[0, 0], r[1, 1], 1.0 + actuation.MAX_DELTA, 0.99]]
    )


def test_mlp_layout_and_batching(rng):
    net = MLP()
    assert net.num_params == 144
    g = net.random_genomes(rng, 6)
    w1, b1, w2, b2 = net.unflatten(g)
    assert w1.shape == (6, 10, 9) and b2.shape == (6, 4)
    np.testing.assert_array_equal(w1[2].ravel(), g[2, :90])
    x = rng.normal(size=(6, 9))
    out = net.forward(g, x)
    for i in range(6):
        h = np.tanh(w1[i] @ x[i] + b1[i])
        np.testing.assert_allclose(out[i], np.tanh(w2[i] @ h + b2[i]) * np.radians(10))
        np.testing.assert_array_equal(
            out[i], net.forward(g[i : i + 1], x[i : i + 1])[0]
        )
    assert np.abs(out).max() <= actuation.MAX_DELTA
    switch = MLP(n_out=3, output="sigmoid")
    assert switch.num_params == 9 * 10 + 10 + 10 * 3 + 3
    s = switch.forward(switch.random_genomes(rng, 4), x[:4])
    assert s.shape == (4, 3) and ((s >= 0) & (s <= 1)).all()
