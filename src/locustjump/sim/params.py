"""``LocustParams``: every number of the creature and its physics, checked
against physical ranges (``docs/physics.md``). :mod:`locustjump.sim.model` turns
them into an MJCF document."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

CONTROL_DT = 1.0 / 120.0  # (Seconds) one control step, the paper's "step"


#: Physical ranges of the scalar fields (low, high, low included): a creature
#: between a flea's size and a few metres, materials between cork and steel
#: scaled, positive gains; a value outside is refused before MuJoCo sees it.
_RANGES: dict[str, tuple[float, float, bool]] = {
    "scale": (0.01, 1000.0, True),  # a 0.5 mm to a 50 m body
    "density": (1.0, 1.0e5, True),  # (kg/m^3) lighter than cork to beyond osmium
    **dict.fromkeys(
        (
            "body_half_length",
            "body_radius",
            "head_radius",
            "femur_length",
            "femur_radius",
            "tibia_length",
            "tibia_radius",
            "tarsus_radius",
            "strut_radius",
        ),
        (1.0e-5, 1.0, True),
    ),  # (m) at real scale  # fmt: skip
    "strut_clearance": (0.0, 0.1, True),  # (m)
    "strut_stiffness": (0.0, 1.0e3, True),
    "strut_damping": (0.0, 1.0e3, True),
    "servo_kp": (1.0e-12, 1.0e3, True),
    "servo_kv": (0.0, 1.0e3, True),
    "servo_force_limit": (1.0e-12, 1.0e3, True),
    "joint_damping": (0.0, 1.0e3, True),
    "joint_armature": (0.0, 1.0e3, True),
    "substeps": (1, 1000, True),
    "friction": (1.0e-6, 100.0, True),
    "iterations": (1, 10000, True),
    "ls_iterations": (1, 10000, True),
}
_INTEGRATORS = ("Euler", "RK4", "implicit", "implicitfast")


@dataclass(frozen=True)
class LocustParams:
    """Every number of the creature and its physics, at real scale (metres).

    Lengths are multiplied by ``scale`` when written; servo gains, armature and
    damping by ``scale**5`` (inertia ~ mass * length^2), so the servo's natural
    frequency does not depend on the scale.
    """

    scale: float = 10.0  # (-) size multiplier over a real locust
    density: float = 300.0  # (kg/m^3) every geom

    # Body: a capsule along x plus a head sphere.
    body_half_length: float = 0.018  # (m) cylinder half-length of the body capsule
    body_radius: float = 0.005  # (m)
    head_radius: float = 0.0045  # (m) sphere at the front end
    # Hind legs.
    hip_pos: tuple[float, float, float] = (0.003, 0.006, -0.003)  # (m) left hip
    femur_length: float = 0.024  # (m)
    femur_radius: float = 0.0018  # (m)
    tibia_length: float = 0.023  # (m)
    tibia_radius: float = 0.0008  # (m)
    tarsus_radius: float = 0.0015  # (m) sphere at the tibia tip
    # Passive fore and middle legs: rigid struts from an attachment point.
    fore_attach: tuple[float, float, float] = (0.014, 0.004, -0.003)  # (m)
    fore_dir: tuple[float, float, float] = (0.45, 0.55, -0.70)  # unit-less
    mid_attach: tuple[float, float, float] = (0.004, 0.005, -0.003)  # (m)
    mid_dir: tuple[float, float, float] = (0.0, 0.60, -0.80)  # unit-less
    strut_radius: float = 0.0009  # (m)
    # Struts end this far above the floor when standing level, so that the hind
    # tarsi always carry weight (and their touch sensors fire) at rest.
    strut_clearance: float = 0.0005  # (m)
    # 0: struts fixed to the body. > 0: each strut swings on a passive hinge
    # (horizontal axis across the strut, so weight splays it outwards) with
    # this spring. Standing, the middle legs carry about a third of the weight
    # (the abdomen tip and hind tarsi the rest, the fore legs none) and sag
    # 0.2 deg at 2e-4 N m/rad, 1.2 deg at 2.5e-6 (scripts/rules_posture_grid.py).
    strut_stiffness: float = 0.0  # (N m/rad) at real scale
    strut_damping: float = 4.0e-6  # (N m s/rad) of a sprung strut's hinge
    strut_swing: float = 30.0  # (deg) a sprung strut's hinge range is +-this

    # Joint ranges and the ready-to-jump posture phi (Fig. 3/4), in degrees.
    hip_range: tuple[float, float] = (20.0, 140.0)  # (deg)
    knee_range: tuple[float, float] = (5.0, 160.0)  # (deg)
    ready_hip: float = 100.0  # (deg) femur levated 10 deg above horizontal
    ready_knee: float = 10.0  # (deg) tibia folded under the femur
    # Extended posture of the rule-based kick (and of the max-rate kick of the
    # physics gates): chosen by the kick fitness E (docs/physics.md).
    kick_hip: float = 80.0  # (deg)
    kick_knee: float = 130.0  # (deg)

    # Servos (position actuators) and joint dynamics, at real scale.
    servo_kp: float = 2.0e-4  # (N m/rad)
    servo_kv: float = 4.0e-6  # (N m s/rad)
    servo_force_limit: float = 2.0e-4  # (N m)
    joint_damping: float = 1.0e-6  # (N m s/rad) hind hinges
    joint_armature: float = 1.0e-8  # (kg m^2) hind hinges

    # Simulation.
    substeps: int = 3  # physics steps per control step
    integrator: str = "implicitfast"
    solref: tuple[float, float] = (0.0056, 1.0)  # (s, -) contact time constant, damping
    solimp: tuple[float, float, float] = (0.9, 0.95, 0.001)  # (-, -, m) impedance
    friction: float = 1.0  # (-) sliding friction coefficient
    iterations: int = 50
    ls_iterations: int = 20

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            values = v if isinstance(v, tuple) else (v,)
            if any(isinstance(x, float) and not math.isfinite(x) for x in values):
                raise ValueError(f"{f.name} must be finite, got {v}")
        for name, (lo, hi, closed) in _RANGES.items():
            v = getattr(self, name)
            if not ((lo <= v if closed else lo < v) and v <= hi):
                bound = "[" if closed else "("
                raise ValueError(
                    f"{name} must be in {bound}{lo:g}, {hi:g}] (docs/physics.md), "
                    f"got {v}"
                )
        if self.integrator not in _INTEGRATORS:
            raise ValueError(
                f"integrator must be one of {', '.join(_INTEGRATORS)}, "
                f"got {self.integrator!r}"
            )
        if not (self.solref[0] > 0 and self.solref[1] > 0):
            raise ValueError(f"solref must be two numbers > 0, got {self.solref}")
        if not (
            0 < self.solimp[0] < 1 and 0 < self.solimp[1] < 1 and self.solimp[2] > 0
        ):
            raise ValueError(
                f"solimp must be (d0, dwidth) in (0, 1) and a width > 0, got "
                f"{self.solimp}"
            )
        if self.substeps < 1:
            raise ValueError(f"substeps must be >= 1, got {self.substeps}")
        if not self.strut_stiffness >= 0:
            raise ValueError(
                f"strut_stiffness must be >= 0, got {self.strut_stiffness}"
            )
        if not 0 < self.strut_swing < 90:
            raise ValueError(f"strut_swing must be in (0, 90), got {self.strut_swing}")
        for nm in ("hip", "knee"):
            lo, hi = getattr(self, f"{nm}_range")
            if not 0.0 < lo < hi < 360.0:
                raise ValueError(f"{nm}_range must satisfy 0 < lo < hi < 360")
            for pose in ("ready", "kick"):
                if not lo <= getattr(self, f"{pose}_{nm}") <= hi:
                    raise ValueError(f"{pose}_{nm} must lie in {nm}_range")

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
