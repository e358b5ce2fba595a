"""The creature's numbers (:class:`locustjump.sim.params.LocustParams`): what
follows from them (timestep, body length, postures) and the words of each
value refused before MuJoCo sees it."""

import math

import numpy as np
import pytest

from helpers import exactly
from locustjump.ranges import SettingTypeError, SettingValueError
from locustjump.sim.params import CONTROL_DT, LocustParams


def test_what_follows_from_the_numbers():
    p = LocustParams()
    assert CONTROL_DT == 1 / 120
    assert p.timestep == 1 / 360 and LocustParams(substeps=12).timestep == 1 / 1440
    assert p.body_length == pytest.approx((2 * 0.018 + 0.005 + 2 * 0.0045) * 10.0)
    q = LocustParams(body_half_length=0.01, body_radius=0.002, head_radius=0.003,
                     scale=2.0)  # fmt: skip
    assert q.body_length == (2 * 0.01 + 0.002 + 2 * 0.003) * 2.0
    np.testing.assert_array_equal(p.kick_angles(), np.radians([80, 130, 80, 130]))
    np.testing.assert_array_equal(p.ready_angles(), np.radians([100, 10, 100, 10]))
    r = LocustParams(ready_hip=90.0, ready_knee=20.0, kick_hip=70.0, kick_knee=140.0)
    np.testing.assert_array_equal(r.ready_angles(), np.radians([90, 20, 90, 20]))
    np.testing.assert_array_equal(r.kick_angles(), np.radians([70, 140, 70, 140]))


def test_a_replaced_copy_is_checked_again():
    p = LocustParams()
    assert p.replace(substeps=6) == LocustParams(substeps=6) and p.substeps == 3
    with pytest.raises(SettingValueError, match="^substeps must be an integer in"):
        p.replace(substeps=0)


@pytest.mark.parametrize("integrator", ["Euler", "RK4", "implicit", "implicitfast"])
def test_every_integrator_of_mujoco(integrator):
    assert LocustParams(integrator=integrator).integrator == integrator


def test_another_integrator_is_named():
    with pytest.raises(SettingValueError, match=exactly(
        "integrator must be one of Euler, RK4, implicit, implicitfast, got 'rk4'"
    )):  # fmt: skip
        LocustParams(integrator="rk4")


@pytest.mark.parametrize(
    "solimp", [(0.0, 0.95, 0.001), (1.0, 0.95, 0.001), (0.9, 0.0, 0.001),
               (0.9, 1.0, 0.001), (0.9, 0.95, 0.0), (0.9, 0.95, -1.0)],
)  # fmt: skip
def test_an_impedance_outside_its_range_is_named(solimp):
    with pytest.raises(SettingValueError, match=exactly(
        f"solimp must be (d0, dwidth) in (0, 1) and a width > 0, got {solimp}"
    )):  # fmt: skip
        LocustParams(solimp=solimp)


def test_an_impedance_inside_its_range():
    for solimp in ((1e-9, 1 - 1e-9, 1e-12), (0.5, 0.5, 5.0)):
        assert LocustParams(solimp=solimp).solimp == solimp


@pytest.mark.parametrize("joint", ["hip", "knee"])
@pytest.mark.parametrize(
    "bounds", [(0.0, 100.0), (-5.0, 100.0), (50.0, 50.0), (60.0, 50.0),
               (10.0, 360.0), (10.0, 400.0)],
)  # fmt: skip
def test_a_joint_range_is_lo_below_hi_within_a_turn(joint, bounds):
    with pytest.raises(SettingValueError, match=exactly(
        f"{joint}_range must be (lo, hi) with 0 < lo < hi < 360 degrees, got {bounds}"
    )):  # fmt: skip
        LocustParams(**{f"{joint}_range": bounds})


def test_a_joint_range_just_inside_a_turn():
    p = LocustParams(hip_range=(1e-9, 359.9), knee_range=(5.0, 359.0))
    assert p.hip_range == (1e-9, 359.9)


@pytest.mark.parametrize(
    ("field", "value", "joint", "lo", "hi"),
    [
        ("ready_hip", 19.0, "hip", 20, 140),
        ("ready_hip", 141.0, "hip", 20, 140),
        ("kick_hip", 140.5, "hip", 20, 140),
        ("ready_knee", 4.0, "knee", 5, 160),
        ("kick_knee", 161.0, "knee", 5, 160),
    ],
)
def test_a_posture_outside_its_joints_range_is_named(field, value, joint, lo, hi):
    with pytest.raises(SettingValueError) as e:
        LocustParams(**{field: value})
    assert str(e.value) == (
        f"{field} must be in {joint}_range [{lo}, {hi}] degrees, got {value}"
    )
    assert e.value.setting == field


def test_a_posture_at_its_joints_bounds():
    p = LocustParams(ready_hip=20.0, kick_hip=140.0, ready_knee=5.0, kick_knee=160.0)
    assert (p.ready_hip, p.kick_hip, p.ready_knee, p.kick_knee) == (20, 140, 5, 160)
    q = LocustParams(hip_range=(10.5, 150.25), ready_hip=150.5 - 0.25)
    with pytest.raises(SettingValueError, match=r"in hip_range \[10\.5, 150\.25\]"):
        q.replace(kick_hip=150.3)


def test_the_declared_ranges_are_checked_first():
    with pytest.raises(SettingTypeError, match="^substeps must be an integer"):
        LocustParams(substeps=3.0)
    with pytest.raises(SettingValueError, match="^scale must be in"):
        LocustParams(scale=math.inf)
    assert LocustParams(hip_pos=[0.0, 0.0, 0.0]).hip_pos == (0.0, 0.0, 0.0)  # a tuple
