"""``tasks/starts.py``: a start state's making stated step by step — the
ground's top under the start, the Fig. 4 posture rolled, its joints set,
lifted to just clear the ground, settled, and put back over the origin on
the flat floor — and the cached ready state, read-only."""

import mujoco
import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.engine.job import StartStates
from locustjump.sim.scene import Debris, Flat
from locustjump.tasks.starts import ground_top, ready_state, settle

P = lm.LocustParams()
BL = P.body_length
#: rubble up to the start (no clearing): 0.181 m within a body length of it,
#: 0.197 m within two
NEAR = Debris(seed=0, clearing=0.0)
#: denser: the creature, dropped from above the start's highest box, lands on
#: rubble (its body 0.18 m up after 0.5 s; 0.10 m on the floor)
ON_BOX = Debris(seed=0, clearing=0.0, spacing=0.5)


def test_the_grounds_top_within_a_body_length():
    assert ground_top(P, Flat()) == 0.0
    assert ground_top(P, Debris(seed=0, clearing=1.5)) == 0.0  # a clear square
    g = np.linspace(-BL, BL, 401)
    top = NEAR.heights(g[:, None], g[None, :], BL).max()
    assert ground_top(P, NEAR) == top == pytest.approx(0.1807, abs=1e-4)


def test_every_cell_of_the_height_grid_is_looked_at():
    """Boxes one or two height cells wide (0.02-0.03 body lengths): the top
    is the highest cell within a body length, as a grid 8 times finer finds
    it (one twice as coarse misses it: 0.178 m)."""
    tiny = Debris(seed=0, clearing=0.0, size_min=0.02, size_max=0.03,
                  spacing=0.3, length=2.0, width=2.5)  # fmt: skip
    g = np.linspace(-BL, BL, 801)
    top = tiny.heights(g[:, None], g[None, :], BL).max()
    assert ground_top(P, tiny) == top == pytest.approx(0.1948, abs=1e-4)


def _lowest(m: mujoco.MjModel, qpos: np.ndarray) -> float:
    d = mujoco.MjData(m)
    d.qpos[:] = qpos
    mujoco.mj_forward(m, d)
    creature = m.geom_bodyid != 0
    return float((d.geom_xpos[creature, 2] - m.geom_rbound[creature]).min())


@pytest.mark.parametrize("scene", [Flat(), NEAR], ids=["flat", "rubble"])
def test_the_posture_rolled_set_and_lifted_to_clear_the_ground(scene):
    """Before any physics (``seconds=0``): the keyframe's orientation turned
    by the roll about the body's own x axis, the hind joints and their
    servo targets at ``angles``, the lowest bounding sphere 1 mm (real
    scale) above the ground's top."""
    m = lm.load_model(P, scene)
    idx = lm.ModelIndex.of(m)
    key = m.key(lm.READY_KEY)
    angles = np.array([0.1, 0.2, 0.3, 0.4])
    s = settle(P, roll_deg=30.0, angles=angles, seconds=0.0, scene=scene)
    half = np.radians(15.0)
    q = np.empty(4)
    mujoco.mju_mulQuat(q, key.qpos[3:7], np.array([np.cos(half), np.sin(half), 0, 0]))
    np.testing.assert_allclose(s.qpos[0, 3:7], q, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(s.qpos[0, idx.qpos_joints], angles)
    np.testing.assert_array_equal(s.ctrl[0], angles)
    low = _lowest(m, s.qpos[0])
    assert low == pytest.approx(1e-3 * P.scale + ground_top(P, scene), abs=1e-12)
    assert (s.qvel == 0).all()
    plain = settle(P, seconds=0.0, scene=scene)  # phi, unrolled
    np.testing.assert_array_equal(plain.qpos[0, 3:7], key.qpos[3:7])
    np.testing.assert_array_equal(plain.ctrl[0], key.ctrl)


def test_settling_simulates_then_recentres_on_the_flat_floor_only():
    s = settle(P, roll_deg=10.0, seconds=0.5)
    lifted = settle(P, roll_deg=10.0, seconds=0.0)
    assert (s.qpos[0, :2] == 0).all() and s.qpos[0, 2] < lifted.qpos[0, 2]
    on = settle(P, roll_deg=10.0, seconds=0.5, scene=ON_BOX)
    assert (on.qpos[0, :2] != 0).all()  # where it came to rest
    assert on.qpos[0, 2] > 0.17  # on the box
    for scene, got in ((Flat(), s), (ON_BOX, on)):  # that many steps, in the scene
        m = lm.load_model(P, scene)
        d = mujoco.MjData(m)
        start = settle(P, roll_deg=10.0, seconds=0.0, scene=scene)
        d.qpos[:], d.ctrl[:] = start.qpos[0], start.ctrl[0]
        mujoco.mj_step(m, d, nstep=round(0.5 / m.opt.timestep))
        np.testing.assert_array_equal(got.qpos[0, 2:], d.qpos[2:])
        np.testing.assert_array_equal(got.qvel[0], d.qvel)
    default = settle(P, roll_deg=135.0)  # the get-up's starts: 3 s
    np.testing.assert_array_equal(default.qpos, settle(P, roll_deg=135.0,
                                                       seconds=3.0).qpos)  # fmt: skip


def test_the_ready_state_is_cached_and_read_only():
    s = ready_state(P)
    assert ready_state(P) is s
    assert not any(a.flags.writeable for a in (s.qpos, s.qvel, s.ctrl))
    np.testing.assert_array_equal(s.qpos, StartStates.ready(lm.load_model(P)).qpos)
