"""``LocustParams``: every number of the creature and its physics, checked
against physical ranges (``docs/physics.md``). :mod:`locustjump.sim.model` turns
them into an MJCF document."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np

from locustjump.ranges import Range, SettingValueError, check_settings, setting

CONTROL_DT = 1.0 / 120.0  # (Seconds) one control step, the paper's "step"


#: Physical ranges (docs/physics.md): a creature between a flea's size and a few
#: metres, materials between cork and steel scaled, positive gains; a value
#: outside is refused before MuJoCo sees it.
_LENGTH = Range(1.0e-5, 1.0, unit="m")  # at real scale
_GAIN = Range(0.0, 1.0e3)  # a damping, a stiffness, an armature: 0 allowed
_POSITIVE_GAIN = Range(1.0e-12, 1.0e3)
_POINT = Range(size=3)  # (m) a point, or a direction, at real scale
_ANGLES = Range(size=2, unit="deg")
_ANGLE = Range(unit="deg")
_INTEGRATORS = ("Euler", "RK4", "implicit", "implicitfast")


@dataclass(frozen=True)
class LocustParams:
    """Every number of the creature and its physics, at real scale (metres).

    Lengths are multiplied by ``scale`` when written; servo gains, armature and
    damping by ``scale**5`` (inertia ~ mass * length^2), so the servo's natural
    frequency does not depend on the scale. Each field's range is declared
    beside it (:mod:`locustjump.ranges`).
    """

    #: (-) size multiplier over a real locust: a 0.5 mm to a 50 m body
    scale: float = setting(10.0, Range(0.01, 1000.0))
    #: (kg/m^3) every geom: lighter than cork to beyond osmium
    density: float = setting(300.0, Range(1.0, 1.0e5, unit="kg/m^3"))

    # Body: a capsule along x plus a head sphere.
    #: (m) cylinder half-length of the body capsule
    body_half_length: float = setting(0.018, _LENGTH)
    body_radius: float = setting(0.005, _LENGTH)  # (m)
    head_radius: float = setting(0.0045, _LENGTH)  # (m) sphere at the front end
    # Hind legs.
    hip_pos: tuple[float, float, float] = setting((0.003, 0.006, -0.003), _POINT)
    femur_length: float = setting(0.024, _LENGTH)  # (m)
    femur_radius: float = setting(0.0018, _LENGTH)  # (m)
    tibia_length: float = setting(0.023, _LENGTH)  # (m)
    tibia_radius: float = setting(0.0008, _LENGTH)  # (m)
    tarsus_radius: float = setting(0.0015, _LENGTH)  # (m) sphere at the tibia tip
    # Passive fore and middle legs: rigid struts from an attachment point.
    fore_attach: tuple[float, float, float] = setting((0.014, 0.004, -0.003), _POINT)
    fore_dir: tuple[float, float, float] = setting((0.45, 0.55, -0.70), _POINT)
    mid_attach: tuple[float, float, float] = setting((0.004, 0.005, -0.003), _POINT)
    mid_dir: tuple[float, float, float] = setting((0.0, 0.60, -0.80), _POINT)
    strut_radius: float = setting(0.0009, _LENGTH)  # (m)
    # Struts end this far above the floor when standing level, so that the hind
    # tarsi always carry weight (and their touch sensors fire) at rest.
    strut_clearance: float = setting(0.0005, Range(0.0, 0.1, unit="m"))
    # 0: struts fixed to the body. > 0: each strut swings on a passive hinge
    # (horizontal axis across the strut, so weight splays it outwards) with
    # this spring. Standing, the middle legs carry about a third of the weight
    # (the abdomen tip and hind tarsi the rest, the fore legs none) and sag
    # 0.2 deg at 2e-4 N m/rad, 1.2 deg at 2.5e-6 (scripts/rules_posture_grid.py).
    #: (N m/rad) at real scale
    strut_stiffness: float = setting(0.0, Range(0.0, 1.0e3, unit="N m/rad"))
    #: (N m s/rad) of a sprung strut's hinge
    strut_damping: float = setting(4.0e-6, _GAIN)
    #: (deg) a sprung strut's hinge range is +-this
    strut_swing: float = setting(
        30.0, Range(0.0, 90.0, lo_open=True, hi_open=True, unit="deg")
    )

    # Joint ranges and the ready-to-jump posture phi (Fig. 3/4), in degrees.
    hip_range: tuple[float, float] = setting((20.0, 140.0), _ANGLES)  # (deg)
    knee_range: tuple[float, float] = setting((5.0, 160.0), _ANGLES)  # (deg)
    #: (deg) femur levated 10 deg above horizontal
    ready_hip: float = setting(100.0, _ANGLE)
    ready_knee: float = setting(10.0, _ANGLE)  # (deg) tibia folded under the femur
    # Extended posture of the rule-based kick (and of the max-rate kick of the
    # physics gates): chosen by the kick fitness E (docs/physics.md).
    kick_hip: float = setting(80.0, _ANGLE)  # (deg)
    kick_knee: float = setting(130.0, _ANGLE)  # (deg)

    # Servos (position actuators) and joint dynamics, at real scale.
    servo_kp: float = setting(2.0e-4, _POSITIVE_GAIN)  # (N m/rad)
    servo_kv: float = setting(4.0e-6, _GAIN)  # (N m s/rad)
    servo_force_limit: float = setting(2.0e-4, _POSITIVE_GAIN)  # (N m)
    joint_damping: float = setting(1.0e-6, _GAIN)  # (N m s/rad) hind hinges
    joint_armature: float = setting(1.0e-8, _GAIN)  # (kg m^2) hind hinges

    # Simulation.
    #: physics steps per control step
    substeps: int = setting(3, Range(1, 1000, integer=True))
    integrator: str = "implicitfast"
    #: (s, -) contact time constant, damping
    solref: tuple[float, float] = setting(
        (0.0056, 1.0), Range(0.0, lo_open=True, size=2)
    )
    #: (-, -, m) impedance
    solimp: tuple[float, float, float] = setting((0.9, 0.95, 0.001), Range(size=3))
    #: (-) sliding friction coefficient
    friction: float = setting(1.0, Range(1.0e-6, 100.0))
    iterations: int = setting(50, Range(1, 10000, integer=True))
    ls_iterations: int = setting(20, Range(1, 10000, integer=True))

    def __post_init__(self) -> None:
        check_settings(self)
        if self.integrator not in _INTEGRATORS:
            raise SettingValueError(
                "integrator", f"one of {', '.join(_INTEGRATORS)}", self.integrator
            )
        if not (
            0 < self.solimp[0] < 1 and 0 < self.solimp[1] < 1 and self.solimp[2] > 0
        ):
            raise SettingValueError(
                "solimp", "(d0, dwidth) in (0, 1) and a width > 0", self.solimp
            )
        for nm in ("hip", "knee"):
            lo, hi = getattr(self, f"{nm}_range")
            if not 0.0 < lo < hi < 360.0:
                raise SettingValueError(
                    f"{nm}_range", "(lo, hi) with 0 < lo < hi < 360 degrees", (lo, hi)
                )
            for pose in ("ready", "kick"):
                if not lo <= getattr(self, f"{pose}_{nm}") <= hi:
                    raise SettingValueError(
                        f"{pose}_{nm}",
                        f"in {nm}_range [{lo:g}, {hi:g}] degrees",
                        getattr(self, f"{pose}_{nm}"),
                    )

    @property
    def timestep(self) -> float:
        """(Seconds) physics timestep."""
        return CONTROL_DT / self.substeps

    @property
    def body_length(self) -> float:
        """(m) nose-to-tail length of the body at this scale."""
        return (
            2 * self.body_half_length + self.body_radius + 2 * self.head_radius
        ) * self.scale

    def replace(self, **changes: Any) -> LocustParams:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def kick_angles(self) -> np.ndarray:
        """(4,) extended kick posture in radians, order of I1–I4."""
        return np.radians([self.kick_hip, self.kick_knee] * 2)

    def ready_angles(self) -> np.ndarray:
        """(4,) ready-to-jump angles phi in radians, order of I1–I4."""
        return np.radians([self.ready_hip, self.ready_knee] * 2)
