"""The document around the creature (``sim/model.py``): solver options, the
contact model, what the viewer and the renderer read, the contact sensors,
the settled keyframe, and the checks and copies the commands rely on."""

import logging
import math
from dataclasses import dataclass
from typing import ClassVar

import mujoco
import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.creature import CONTACT_GEOMS
from locustjump.sim.scene import Flat, Scene, SceneMJCF

P = lm.LocustParams()
BL = P.body_length


@dataclass(frozen=True)
class Plinth(Scene):
    """The flat floor with a box under the start (raising the creature by
    ``0.1`` body length) and, ahead, a wall; optionally a broad phase."""

    name: ClassVar[str] = "plinth-test"
    broad: bool = False

    def mjcf(self, body_length: float) -> SceneMJCF:
        floor = Flat().mjcf(body_length)
        h = 0.05 * body_length
        box = f'<geom name="plinth" type="box" pos="0 0 {h}" '
        box += f'size="{body_length} {body_length} {h}"/>'
        wall = f'<geom name="front" type="box" pos="{3 * body_length} 0 {body_length}" '
        wall += f'size="0.01 {body_length} {body_length}"/>'
        return SceneMJCF(
            assets=floor.assets,
            worldbody=floor.worldbody + box + wall,
            geoms=(*floor.geoms, "plinth", "front"),
            broad_phase=self.broad,
            walls=("front",),
        )


@pytest.fixture(autouse=True)
def _uncached():
    """Each test compiles its models afresh (not from ``load_model``'s cache),
    so that it runs the code it states (what mutation testing selects by)."""
    lm._compiled.cache_clear()
    yield
    lm._compiled.cache_clear()


@pytest.fixture
def m() -> mujoco.MjModel:
    return lm.load_model(P)


def test_solver_options(m):
    assert m.opt.timestep == pytest.approx(lm.CONTROL_DT / 3, rel=1e-11)
    assert m.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert m.opt.cone == mujoco.mjtCone.mjCONE_PYRAMIDAL
    assert (m.opt.iterations, m.opt.ls_iterations) == (50, 20)
    other = lm.load_model(
        P.replace(substeps=12, iterations=7, ls_iterations=5, integrator="RK4")
    )
    assert other.opt.timestep == pytest.approx(lm.CONTROL_DT / 12, rel=1e-11)
    assert (other.opt.iterations, other.opt.ls_iterations) == (7, 5)
    assert other.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4
    # the engine's buffers: three user slots a simulation, 1 MB of arena
    assert (m.nuserdata, m.narena) == (3, 1 << 20)


def test_the_contact_model(m):
    f = P.friction
    for g in CONTACT_GEOMS:
        geom = m.geom(g)
        assert (geom.contype, geom.conaffinity, geom.condim) == (0, 0, 3)
        assert geom.friction.tolist() == pytest.approx([f, 0.005, 0.0001])
        np.testing.assert_allclose(geom.solref, P.solref)
        np.testing.assert_allclose(geom.solimp[:3], P.solimp)
    assert (m.pair_dim == 3).all()
    np.testing.assert_allclose(m.pair_friction, [[f, f, 0.005, 1e-4, 1e-4]] * m.npair)
    np.testing.assert_allclose(m.pair_solref, [P.solref] * m.npair)
    np.testing.assert_allclose(m.pair_solimp[:, :3], [P.solimp] * m.npair)
    slick = lm.load_model(P.replace(friction=0.25, solref=(0.004, 2.0)))
    assert slick.pair_friction[0, :2].tolist() == [0.25, 0.25]
    assert slick.geom(names.BODY).friction[0] == 0.25
    np.testing.assert_allclose(slick.pair_solref[0], [0.004, 2.0])


def test_what_the_renderer_and_the_viewer_read(m):
    assert (m.vis.global_.offwidth, m.vis.global_.offheight) == (1280, 720)
    assert m.vis.quality.shadowsize == 2048
    np.testing.assert_allclose(m.vis.headlight.ambient, [0.4] * 3)
    np.testing.assert_allclose(m.vis.headlight.diffuse, [0.6] * 3)
    sky = [
        i for i in range(m.ntex) if m.tex_type[i] == mujoco.mjtTexture.mjTEXTURE_SKYBOX
    ]
    assert len(sky) == 1 and m.tex_width[sky[0]] == 256
    sun = m.light("sun")
    assert sun.pos.tolist() == pytest.approx([0, 0, 10 * BL])
    assert sun.dir.tolist() == pytest.approx([0, 0, -1])
    assert m.light_type[sun.id] == mujoco.mjtLightType.mjLIGHT_DIRECTIONAL
    side = m.camera(names.CAMERA_SIDE)
    assert side.pos.tolist() == pytest.approx([4 * BL, -9 * BL, 2 * BL])
    assert (
        m.cam_bodyid[side.id] == 0 and side.mode == mujoco.mjtCamLight.mjCAMLIGHT_FIXED
    )
    up = np.array([0, 0.2, 1]) / np.hypot(0.2, 1)
    np.testing.assert_allclose(
        m.cam_mat0[side.id].reshape(3, 3)[:, :2], np.c_[[1, 0, 0], up]
    )


def test_contact_pairs_and_sensors_as_written():
    assert lm.contact_pairs(()) == []
    assert lm.contact_pairs(("a", "b"))[len(CONTACT_GEOMS)] == ("b", CONTACT_GEOMS[0])
    assert lm.contact_sensors(()) == (
        f'\n    <contact name="{names.DEEPEST_CONTACT}" subtree1="{names.BODY}" '
        'data="dist" reduce="mindist" num="1"/>'
    )
    walls = lm.contact_sensors(("w0", "w1"))
    assert walls.endswith(
        f'\n    <contact name="{names.WALL_CONTACT}0" geom1="w0" data="found"/>'
        f'\n    <contact name="{names.WALL_CONTACT}1" geom1="w1" data="found"/>'
    )


def test_the_contact_sensors_read_the_deepest_contact_and_the_walls():
    m = lm.load_model(P, Plinth())
    idx = lm.ModelIndex.of(m)
    assert idx.walls.shape == (1,) and idx.wall_geoms.tolist() == [m.geom("front").id]
    assert idx.walls.dtype.kind == idx.wall_geoms.dtype.kind == "i"  # they index
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, idx.ready_key)
    d.qpos[2] += 0.2 * BL  # in the air above the plinth (0.1 body length high)
    mujoco.mj_forward(m, d)
    assert d.ncon == 0
    assert d.sensordata[idx.deepest] == 0.0 and d.sensordata[idx.walls[0]] == 0.0
    d.qpos[2] -= 0.12 * BL  # sunk into it
    mujoco.mj_forward(m, d)
    deepest = min(c.dist for c in d.contact[: d.ncon])
    assert deepest < 0 and d.sensordata[idx.deepest] == pytest.approx(deepest)
    d.qpos[0] = 3 * BL  # inside the wall
    mujoco.mj_forward(m, d)
    assert d.sensordata[idx.walls[0]] >= 1


def test_the_keyframe_is_the_creature_settled_at_phi_on_the_flat_floor(m):
    key = m.key(lm.READY_KEY)
    np.testing.assert_allclose(key.ctrl, np.radians([100, 10, 100, 10]))
    assert key.qpos[:2].tolist() == [0.0, 0.0]
    # the settled state: SETTLE_TIME seconds from the written pose at phi
    bare = mujoco.MjModel.from_xml_string(lm.to_mjcf(P, keyframe=False))
    d = mujoco.MjData(bare)
    adr = [bare.jnt_qposadr[bare.joint(j).id] for j in names.ACTUATED_JOINTS]
    d.qpos[adr] = d.ctrl[:] = P.ready_angles()
    mujoco.mj_forward(bare, d)
    mujoco.mj_step(bare, d, nstep=round(1.0 / bare.opt.timestep))
    assert lm.SETTLE_TIME == 1.0
    np.testing.assert_allclose(key.qpos[2:], d.qpos[2:], rtol=1e-8, atol=1e-12)
    assert 0.8 * lm.standing_height(P) < key.qpos[2] < lm.standing_height(P)  # sags
    # any scene starts from the keyframe settled on the flat floor, not on it,
    # the same creature's
    raised = lm.load_model(P, Plinth())
    np.testing.assert_array_equal(raised.key(lm.READY_KEY).qpos, key.qpos)
    crouched = P.replace(ready_knee=20.0)
    np.testing.assert_array_equal(
        lm.load_model(crouched, Plinth()).key(lm.READY_KEY).qpos,
        lm.load_model(crouched).key(lm.READY_KEY).qpos,
    )
    assert lm.to_mjcf(P, keyframe=False).count("<keyframe>") == 0


def test_a_scene_with_a_broad_phase_collides_through_it_and_sleeps():
    """The creature's geoms collide with its static geoms through the broad
    phase (contype 1), and the static geoms sleep; the flat floor does neither."""
    flat, broad = lm.load_model(P), lm.load_model(P, Plinth(broad=True))
    sleep = mujoco.mjtEnableBit.mjENBL_SLEEP
    assert not flat.opt.enableflags & sleep and broad.opt.enableflags & sleep
    assert not lm.load_model(P, Plinth()).opt.enableflags & sleep
    assert all(
        broad.geom(g).contype == 1 and broad.geom(g).conaffinity == 0
        for g in CONTACT_GEOMS
    )


def test_load_model_gives_a_copy_of_one_compiled_model():
    a = lm.load_model(P)
    a.opt.timestep = 1.0
    a.body_mass[1] = 99.0
    b = lm.load_model(P)
    assert b.opt.timestep == pytest.approx(lm.CONTROL_DT / 3)
    assert b.body_mass[1] != 99.0 and b is not a


def test_check_model_names_the_model_table_when_mujoco_refuses():
    lm.check_model(P)  # the default compiles
    lm.check_model(P, Plinth())
    tiny = P.replace(scale=0.01, density=1.0)  # masses below MuJoCo's minimum
    with pytest.raises(UserError) as e:
        lm.check_model(tiny)
    msg = str(e.value)
    assert msg.startswith("[model]: MuJoCo rejects this creature (")
    assert "\n" not in msg and "inertia" in msg and msg.endswith(")")
    assert e.value.__cause__ is None and e.value.__suppress_context__


@pytest.mark.parametrize(
    ("error", "said"),
    [
        (ValueError("XML Error: bad\nElement 'geom', line 3"), "XML Error: bad"),
        (RuntimeError("  "), "RuntimeError"),  # nothing said: its type
    ],
)
def test_check_model_says_the_first_line_or_the_type(monkeypatch, error, said):
    def refuse(p, scene):
        raise error

    monkeypatch.setattr(lm, "_compiled", refuse)
    with pytest.raises(
        UserError, match=rf"^\[model\]: MuJoCo rejects this creature \({said}\)$"
    ):
        lm.check_model(P)


def test_model_index_reads_the_named_addresses(m):
    idx = lm.ModelIndex.of(m)
    assert idx.qpos_joints.tolist() == [7, 8, 9, 10]  # after the free joint
    touch = [m.sensor_adr[m.sensor(t).id] for t in names.TOUCH_SENSORS]
    assert idx.touch.tolist() == touch
    np.testing.assert_allclose(idx.ranges, np.radians([P.hip_range, P.knee_range] * 2))
    assert idx.ready_key == 0
    assert idx.deepest == m.sensor_adr[m.sensor(names.DEEPEST_CONTACT).id]
    assert idx.walls.shape == idx.wall_geoms.shape == (0,)
    bare = mujoco.MjModel.from_xml_string(lm.to_mjcf(P, keyframe=False))
    assert lm.ModelIndex.of(bare).ready_key == -1
    sprung = lm.ModelIndex.of(lm.load_model(P.replace(strut_stiffness=1e-5)))
    # the fore legs' hinges come before the left hind leg's in the tree
    assert sprung.qpos_joints.tolist() == [9, 10, 13, 14]


def test_mujoco_warnings_go_to_the_log_not_to_a_file(caplog, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    m = lm.load_model(P)
    d = mujoco.MjData(m)
    d.qvel[0] = math.inf
    with caplog.at_level(logging.INFO, logger="locustjump.mujoco"):
        mujoco.mj_step(m, d)
    (record,) = [r for r in caplog.records if r.name == "locustjump.mujoco"]
    assert record.levelno == logging.INFO and record.getMessage().startswith("MuJoCo: ")
    assert "QVEL" in record.getMessage()
    assert list(tmp_path.iterdir()) == []  # no MUJOCO_LOG.TXT
