"""The creature (``sim/creature.py``) as MuJoCo compiles it: every length,
radius, range and gain of ``LocustParams`` is read back from the model, and
the geometry is checked where the physics rests on it (the tarsi stand on
z = 0, the struts reach the ground, the legs bend the way the SPEC says)."""

import math

import mujoco
import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.creature import CONTACT_GEOMS, leg_tip, standing_height

P = lm.LocustParams()
S, S5 = P.scale, P.scale**5
SPRUNG = P.replace(strut_stiffness=1e-5, strut_damping=3e-6, strut_swing=12.0)
STIFF = SPRUNG.replace(strut_stiffness=1.0)


def _bare(p: lm.LocustParams = P) -> mujoco.MjModel:
    """The creature as written: no keyframe, every joint at 0."""
    return mujoco.MjModel.from_xml_string(lm.to_mjcf(p, keyframe=False))


@pytest.fixture
def m() -> mujoco.MjModel:
    """Compiled afresh for each test (not ``load_model``'s cached one), so
    that each test runs the code it states (what mutation testing selects by)."""
    return _bare()


def _posed(m: mujoco.MjModel, hip: float, knee: float) -> mujoco.MjData:
    """The creature where the MJCF puts it, both hind legs at (hip, knee) deg."""
    d = mujoco.MjData(m)
    for j, a in zip(names.ACTUATED_JOINTS, (hip, knee, hip, knee), strict=True):
        d.qpos[m.jnt_qposadr[m.joint(j).id]] = math.radians(a)
    mujoco.mj_kinematics(m, d)
    return d


def test_the_contact_geoms_and_their_order():
    assert CONTACT_GEOMS == (
        "body", "head", "fore_l", "mid_l", "fore_r", "mid_r",
        "femur_l", "tibia_l", "tarsus_l", "femur_r", "tibia_r", "tarsus_r",
    )  # fmt: skip


@pytest.mark.parametrize(
    ("hip", "knee", "tip"),
    [
        (0, 180, (0.0, -(0.024 + 0.023))),  # straight leg, straight down
        (90, 180, (-(0.024 + 0.023), 0.0)),  # straight leg, straight back
        (0, 0, (0.0, -0.024 + 0.023)),  # tibia folded back up the femur
        (90, 90, (-0.024, -0.023)),  # femur back, tibia down
        (180, 90, (-0.023, 0.024)),  # femur up, tibia turned on back
    ],
)
def test_leg_tip_at_known_angles(hip, knee, tip):
    np.testing.assert_allclose(leg_tip(P, hip, knee), np.array(tip) * S, atol=1e-12)
    half = P.replace(scale=S / 2)
    np.testing.assert_allclose(
        leg_tip(half, hip, knee), np.array(tip) * S / 2, atol=1e-12
    )


@pytest.mark.parametrize(("hip", "knee"), [(100, 10), (80, 130), (20, 160), (140, 5)])
def test_mujoco_puts_the_tarsus_where_leg_tip_says(m, hip, knee):
    """The hinges turn as the SPEC says (hip 0 = down, turning backwards;
    knee 0 = folded), and the hind legs hang at the hip, mirrored in y."""
    d = _posed(m, hip, knee)
    tx, tz = leg_tip(P, hip, knee)
    h0 = standing_height(P)
    for i, sign in enumerate((1, -1)):
        hip_at = np.array(P.hip_pos) * S * (1, sign, 1) + (0, 0, h0)
        np.testing.assert_allclose(
            d.geom(names.TARSI[i]).xpos, hip_at + (tx, 0, tz), atol=1e-12
        )
        np.testing.assert_allclose(
            d.site(names.TARSUS_SITES[i]).xpos, d.geom(names.TARSI[i]).xpos
        )
        np.testing.assert_allclose(d.body(names.FEMURS[i]).xpos, hip_at, atol=1e-12)


def test_at_the_ready_posture_the_tarsi_stand_on_the_ground(m):
    d = _posed(m, P.ready_hip, P.ready_knee)
    for g in names.TARSI:
        # (to the 9 digits the MJCF is written with)
        assert d.geom(g).xpos[2] - P.tarsus_radius * S == pytest.approx(0.0, abs=1e-9)
    assert m.body(names.BODY).pos.tolist() == pytest.approx([0, 0, standing_height(P)])
    assert standing_height(P) > 0


def test_the_hind_legs_lengths_radii_and_ranges(m):
    for i in range(2):
        femur, tibia, tarsus = (
            m.geom(g[i]) for g in (names.FEMURS, names.TIBIAE, names.TARSI)
        )
        assert femur.size[:2].tolist() == pytest.approx(
            [P.femur_radius * S, P.femur_length * S / 2]
        )
        assert tibia.size[:2].tolist() == pytest.approx(
            [P.tibia_radius * S, P.tibia_length * S / 2]
        )
        assert tarsus.size[0] == pytest.approx(P.tarsus_radius * S)
        assert m.site(names.TARSUS_SITES[i]).size[0] == pytest.approx(
            1.5 * P.tarsus_radius * S
        )
        assert femur.type == tibia.type == mujoco.mjtGeom.mjGEOM_CAPSULE
        assert tarsus.type == mujoco.mjtGeom.mjGEOM_SPHERE
        # the femur geom runs down from the hip, the tibia up from the knee
        assert femur.pos.tolist() == pytest.approx([0, 0, -P.femur_length * S / 2])
        assert tibia.pos.tolist() == pytest.approx([0, 0, P.tibia_length * S / 2])
        assert m.body(names.TIBIAE[i]).pos.tolist() == pytest.approx(
            [0, 0, -P.femur_length * S]
        )
        for j, rng in (
            (names.HIP_JOINTS[i], P.hip_range),
            (names.KNEE_JOINTS[i], P.knee_range),
        ):
            jnt = m.joint(j)
            assert jnt.type == mujoco.mjtJoint.mjJNT_HINGE and jnt.limited == 1
            assert jnt.axis.tolist() == [0, 1, 0]
            np.testing.assert_allclose(jnt.range, np.radians(rng))
            assert m.dof_damping[jnt.dofadr[0]] == pytest.approx(P.joint_damping * S5)
            assert m.dof_armature[jnt.dofadr[0]] == pytest.approx(P.joint_armature * S5)


def test_the_servos_drive_i1_to_i4_with_gains_scaled_by_scale_to_the_fifth(m):
    assert [m.actuator(i).name for i in range(m.nu)] == list(names.ACTUATORS)
    for i, j in enumerate(names.ACTUATED_JOINTS):
        a = m.actuator(i)
        assert a.trnid[0] == m.joint(j).id
        assert a.gainprm[0] == pytest.approx(P.servo_kp * S5)
        assert a.biasprm[:3].tolist() == pytest.approx(
            [0, -P.servo_kp * S5, -P.servo_kv * S5]
        )
        flim = P.servo_force_limit * S5
        assert a.forcerange.tolist() == pytest.approx([-flim, flim]) and a.forcelimited
        np.testing.assert_allclose(a.ctrlrange, m.joint(j).range)  # inheritrange


def test_the_touch_sensors_sit_on_the_tarsi(m):
    for t, site in zip(names.TOUCH_SENSORS, names.TARSUS_SITES, strict=True):
        assert m.sensor(t).type == mujoco.mjtSensor.mjSENS_TOUCH
        assert m.sensor(t).objid == m.site(site).id


def test_the_masses_follow_the_density(m):
    """Density 300 kg/m^3 for every geom: the femur body is one capsule, the
    tibia body a capsule and the tarsus sphere."""

    def capsule(r: float, length: float) -> float:
        return math.pi * r**2 * length + 4 / 3 * math.pi * r**3

    femur = capsule(P.femur_radius * S, P.femur_length * S)
    tibia = capsule(P.tibia_radius * S, P.tibia_length * S)
    tarsus = 4 / 3 * math.pi * (P.tarsus_radius * S) ** 3
    assert m.body(names.FEMURS[0]).mass == pytest.approx(P.density * femur)
    assert m.body(names.TIBIAE[1]).mass == pytest.approx(P.density * (tibia + tarsus))
    light = _bare(P.replace(density=150.0))
    np.testing.assert_allclose(light.body_mass, m.body_mass / 2)


def test_the_body_head_and_materials(m):
    body, head = m.geom(names.BODY), m.geom(names.HEAD)
    assert body.size[:2].tolist() == pytest.approx(
        [P.body_radius * S, P.body_half_length * S]
    )
    assert head.size[0] == pytest.approx(P.head_radius * S)
    assert head.pos.tolist() == pytest.approx(
        [(P.body_half_length + P.head_radius) * S, 0, 0]
    )
    assert body.pos.tolist() == pytest.approx([0, 0, 0])
    assert m.joint(names.ROOT_JOINT).type == mujoco.mjtJoint.mjJNT_FREE
    rgba = {m.material(i).name: m.mat_rgba[i].tolist() for i in range(m.nmat)}
    assert rgba["cuticle"] == pytest.approx([0.55, 0.62, 0.25, 1])
    assert rgba["leg"] == pytest.approx([0.45, 0.50, 0.20, 1])
    assert body.matid == head.matid == m.material("cuticle").id
    for g in (names.FORE_LEGS[0], names.MID_LEGS[1], names.FEMURS[0], names.TARSI[1]):
        assert m.geom(g).matid == m.material("leg").id
    # the creature's tree is always simulated, also where the world sleeps
    tree = m.body_treeid[m.body(names.BODY).id]
    assert m.tree_sleep_policy[tree] == mujoco.mjtSleepPolicy.mjSLEEP_NEVER


def test_the_tracking_camera(m):
    bl = P.body_length
    cam = m.camera(names.CAMERA_TRACK)
    assert cam.mode == mujoco.mjtCamLight.mjCAMLIGHT_TRACKCOM
    assert m.cam_bodyid[cam.id] == m.body(names.BODY).id
    assert cam.pos.tolist() == pytest.approx([0, -3 * bl, 0.6 * bl])
    up = np.array([0, 0.2, 1]) / np.hypot(0.2, 1)  # xyaxes: x ahead, y this
    np.testing.assert_allclose(
        m.cam_mat0[cam.id].reshape(3, 3)[:, :2], np.c_[[1, 0, 0], up]
    )


def _strut_ends(
    m: mujoco.MjModel, d: mujoco.MjData, g: str
) -> tuple[np.ndarray, np.ndarray]:
    """The two ends of a strut capsule's axis, upper first, in the world."""
    half = m.geom(g).size[1] * d.geom(g).xmat.reshape(3, 3)[:, 2]
    a, b = d.geom(g).xpos + half, d.geom(g).xpos - half
    return (a, b) if a[2] > b[2] else (b, a)


@pytest.mark.parametrize("p", [P, SPRUNG], ids=["rigid", "sprung"])
def test_the_struts_reach_down_to_their_clearance(p):
    """Each fore and middle strut starts at its attachment, points along its
    direction (mirrored in y on the right) and ends its clearance above the
    ground when the creature stands."""
    m = _bare(p)
    d = _posed(m, p.ready_hip, p.ready_knee)
    h0 = standing_height(p)
    for legs, attach, direction in (
        (names.FORE_LEGS, p.fore_attach, p.fore_dir),
        (names.MID_LEGS, p.mid_attach, p.mid_dir),
    ):
        for g, sign in zip(legs, (1, -1), strict=True):
            top, tip = _strut_ends(m, d, g)
            mirror = np.array([1, sign, 1])
            np.testing.assert_allclose(
                top, np.array(attach) * S * mirror + (0, 0, h0), atol=1e-12
            )
            unit = np.array(direction) * mirror / np.linalg.norm(direction)
            np.testing.assert_allclose(
                (tip - top) / np.linalg.norm(tip - top), unit, atol=1e-12
            )
            bottom = tip[2] - p.strut_radius * S
            assert bottom == pytest.approx(p.strut_clearance * S, abs=1e-12)
            assert m.geom(g).size[0] == pytest.approx(p.strut_radius * S)
            assert m.geom(g).type == mujoco.mjtGeom.mjGEOM_CAPSULE
            assert m.geom(g).matid == m.material("leg").id


@pytest.mark.parametrize("sp", [SPRUNG, STIFF], ids=["sprung", "stiff"])
def test_rigid_struts_are_geoms_of_the_body_sprung_ones_hang_on_hinges(sp):
    rigid, sprung = _bare(), _bare(sp)
    assert rigid.njnt == 5 and sprung.njnt == 9
    for g in (*names.FORE_LEGS, *names.MID_LEGS):
        assert rigid.geom_bodyid[rigid.geom(g).id] == rigid.body(names.BODY).id
        body = sprung.body(g)
        assert sprung.geom_bodyid[sprung.geom(g).id] == body.id
        j = sprung.joint(g)
        assert j.type == mujoco.mjtJoint.mjJNT_HINGE and j.bodyid == body.id
        assert sprung.jnt_stiffness[j.id] == pytest.approx(sp.strut_stiffness * S5)
        assert sprung.dof_damping[j.dofadr[0]] == pytest.approx(
            SPRUNG.strut_damping * S5
        )
        assert sprung.dof_armature[j.dofadr[0]] == pytest.approx(
            SPRUNG.joint_armature * S5
        )
        np.testing.assert_allclose(j.range, np.radians([-12.0, 12.0]))
        # the hinge swings the strut across its own direction, about a level axis
        d = np.array(SPRUNG.fore_dir if g in names.FORE_LEGS else SPRUNG.mid_dir)
        d = d * (1, 1 if g.endswith("_l") else -1, 1)
        axis = np.cross(d, (0, 0, 1))
        np.testing.assert_allclose(j.axis, axis / np.linalg.norm(axis), atol=1e-9)
    # the hind legs are the same legs
    np.testing.assert_allclose(
        sprung.body(names.FEMURS[1]).mass, rigid.body(names.FEMURS[1]).mass
    )
