"""The locust model: one parameter set -> one MJCF document -> ``mujoco.MjModel``.

Geometry follows an adult desert locust (body ~5 cm, hind femur 2.4 cm, hind
tibia 2.3 cm) multiplied by one ``scale``. Every geom has density 300 kg/m^3, so
masses and inertias follow from the geometry (MuJoCo computes them).

Frame: MuJoCo is z-up; the paper's height *y* is our *z*; the creature heads
along +x. The hind legs move in the body's sagittal (x-z) plane:

* hip (body–femur) angle ``h``: direction of the femur, measured from straight
  down and turning backwards: 0 = down, 90 deg = backwards along -x,
  180 deg = up.
* knee (femur–tibia) angle ``k``: 0 = tibia folded back onto the femur,
  180 deg = straight leg.

Both ranges lie inside (0, 2 pi), so the angle never wraps (SPEC, I1–I4).
The fore and middle legs are rigid struts fixed to the body by default (the
cheapest passive legs: the creature stands, lands and can be overturned on
them); ``strut_stiffness > 0`` hangs each on a sprung, damped hinge instead.

The physics timestep is ``CONTROL_DT / substeps``; contact softness is fixed in
seconds (``solref``) so that refining the timestep does not change the contact
model (PHYSICS-NOTES, convergence trap). See ``docs/physics.md`` for how the
defaults were chosen.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import lru_cache

import mujoco
import numpy as np

from locustjump import names

CONTROL_DT = 1.0 / 120.0  # (Seconds) one control step, the paper's "step"
SETTLE_TIME = 1.0  # (Seconds) settling before t = 0
READY_KEY = names.READY_KEY  # keyframe of the settled start state (Fig. 4)


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

    def replace(self, **changes: object) -> LocustParams:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def joint_ranges(self) -> np.ndarray:
        """(4, 2) ranges of the actuated joints in radians, order of I1–I4."""
        hip, knee = np.radians(self.hip_range), np.radians(self.knee_range)
        return np.array([hip, knee, hip, knee])

    def kick_angles(self) -> np.ndarray:
        """(4,) extended kick posture in radians, order of I1–I4."""
        return np.radians([self.kick_hip, self.kick_knee] * 2)

    def ready_angles(self) -> np.ndarray:
        """(4,) ready-to-jump angles phi in radians, order of I1–I4."""
        return np.radians([self.ready_hip, self.ready_knee] * 2)


def _fmt(*values: float) -> str:
    return " ".join(f"{v:.9g}" for v in values)


def _unit(v: tuple[float, float, float]) -> np.ndarray:
    a = np.asarray(v, float)
    return a / np.linalg.norm(a)


def leg_tip(p: LocustParams, hip_deg: float, knee_deg: float) -> np.ndarray:
    """(x, z) of the tarsus centre relative to the hip, body level, in metres."""
    h = math.radians(hip_deg)
    t = h - math.pi + math.radians(knee_deg)
    x = -math.sin(h) * p.femur_length - math.sin(t) * p.tibia_length
    z = -math.cos(h) * p.femur_length - math.cos(t) * p.tibia_length
    return np.array([x, z]) * p.scale


def standing_height(p: LocustParams) -> float:
    """(m) body-centre height when standing level on the tarsi at phi."""
    _, tz = leg_tip(p, p.ready_hip, p.ready_knee)
    return -(p.hip_pos[2] * p.scale + tz) + p.tarsus_radius * p.scale


def to_mjcf(p: LocustParams = LocustParams(), *, keyframe: bool = True) -> str:
    """The complete MJCF document of the creature and its world.

    Args:
      p: the parameter set.
      keyframe: whether to settle the creature and store the start state of
        Fig. 4 as keyframe ``"ready"`` (needs one short simulation).
    """
    s = p.scale
    s5 = s**5
    flim = p.servo_force_limit * s5
    h0 = standing_height(p)
    lo_h, hi_h = p.hip_range
    lo_k, hi_k = p.knee_range

    def strut(nm: str, sign: float, attach, direction) -> str:
        a = np.array(attach) * s * np.array([1, sign, 1])
        d = _unit(direction) * np.array([1, sign, 1])
        # long enough for the tip sphere to touch the ground when standing
        length = (h0 + a[2] - (p.strut_radius + p.strut_clearance) * s) / -d[2]
        b = a + d * length
        size = f'size="{p.strut_radius * s:.9g}"'
        if p.strut_stiffness == 0:
            return f'<geom name="{nm}" class="strut" fromto="{_fmt(*a, *b)}" {size}/>'
        axis = np.cross(d, (0.0, 0.0, 1.0))
        return (
            f'<body name="{nm}" pos="{_fmt(*a)}">'
            f'<joint name="{nm}" class="strut" axis="{_fmt(*_unit(axis))}"/>'
            f'<geom name="{nm}" class="strut" '
            f'fromto="0 0 0 {_fmt(*(b - a))}" {size}/></body>'
        )

    def hind_leg(i: int, sign: float) -> str:
        hx, hy, hz = np.array(p.hip_pos) * s * np.array([1, sign, 1])
        lf, lt = p.femur_length * s, p.tibia_length * s
        return f"""
      <body name="{names.FEMURS[i]}" pos="{_fmt(hx, hy, hz)}">
        <joint name="{names.HIP_JOINTS[i]}" class="hind" range="{lo_h} {hi_h}"/>
        <geom name="{names.FEMURS[i]}" class="leg" fromto="0 0 0 0 0 {-lf:.9g}"
              size="{p.femur_radius * s:.9g}"/>
        <body name="{names.TIBIAE[i]}" pos="0 0 {-lf:.9g}">
          <joint name="{names.KNEE_JOINTS[i]}" class="hind" range="{lo_k} {hi_k}"/>
          <geom name="{names.TIBIAE[i]}" class="leg" fromto="0 0 0 0 0 {lt:.9g}"
                size="{p.tibia_radius * s:.9g}"/>
          <geom name="{names.TARSI[i]}" class="leg" type="sphere" pos="0 0 {lt:.9g}"
                size="{p.tarsus_radius * s:.9g}"/>
          <site name="{names.TARSUS_SITES[i]}" type="sphere" pos="0 0 {lt:.9g}"
                size="{1.5 * p.tarsus_radius * s:.9g}" rgba="1 0.3 0.3 0.3"/>
        </body>
      </body>"""

    legs = "".join(
        strut(names.FORE_LEGS[i], sign, p.fore_attach, p.fore_dir)
        + strut(names.MID_LEGS[i], sign, p.mid_attach, p.mid_dir)
        + hind_leg(i, sign)
        for i, sign in enumerate((1.0, -1.0))
    )
    # Only the creature against the floor collides, as explicit pairs (no
    # broad phase: mj_step 6.1 -> 5.4 us, bit-identical trajectories), in
    # geom-id order: the body's own geoms, then the hind legs'.
    creature = [names.BODY, names.HEAD]
    creature += [
        leg
        for pair in zip(names.FORE_LEGS, names.MID_LEGS, strict=True)
        for leg in pair
    ]
    creature += [
        geom
        for i in range(len(names.SIDES))
        for geom in (names.FEMURS[i], names.TIBIAE[i], names.TARSI[i])
    ]
    pairs = "".join(
        f'\n    <pair geom1="{names.FLOOR}" geom2="{g}"/>' for g in creature
    )
    servos = "".join(
        f'<position name="{a}" joint="{j}" class="servo"/>'
        for a, j in zip(names.ACTUATORS, names.ACTUATED_JOINTS, strict=True)
    )
    touch = "".join(
        f'<touch name="{t}" site="{site}"/>'
        for t, site in zip(names.TOUCH_SENSORS, names.TARSUS_SITES, strict=True)
    )
    strut_joint = (
        ""
        if p.strut_stiffness == 0
        else f'<joint type="hinge" stiffness="{p.strut_stiffness * s5:.9g}" '
        f'damping="{p.strut_damping * s5:.9g}" '
        f'armature="{p.joint_armature * s5:.9g}" '
        f'range="{-p.strut_swing:.9g} {p.strut_swing:.9g}"/>'
    )
    bl = p.body_length
    head_x = (p.body_half_length + p.head_radius) * s
    track = names.CAMERA_TRACK
    xml = f"""<mujoco model="locust">
  <compiler angle="degree" autolimits="true"/>
  <option timestep="{p.timestep:.12g}" integrator="{p.integrator}" cone="pyramidal"
          iterations="{p.iterations}" ls_iterations="{p.ls_iterations}"/>
  <size memory="1M"/>
  <visual>
    <global offwidth="1280" offheight="720"/>
    <quality shadowsize="2048"/>
    <headlight ambient="0.4 0.4 0.4" diffuse="0.6 0.6 0.6"/>
  </visual>
  <asset>
    <texture name="sky" type="skybox" builtin="gradient" width="256" height="256"
             rgb1="0.55 0.70 0.88" rgb2="0.95 0.96 0.98"/>
    <texture name="grid" type="2d" builtin="checker" width="512" height="512"
             rgb1="0.82 0.82 0.78" rgb2="0.62 0.64 0.60" mark="edge"
             markrgb="0.3 0.3 0.3"/>
    <material name="grid" texture="grid" texrepeat="1 1" texuniform="true"
              reflectance="0"/>
    <material name="cuticle" rgba="0.55 0.62 0.25 1"/>
    <material name="leg" rgba="0.45 0.50 0.20 1"/>
  </asset>
  <default>
    <geom density="{p.density:.9g}" contype="0" conaffinity="0" condim="3"
          friction="{p.friction:.9g} 0.005 0.0001"
          solref="{_fmt(*p.solref)}" solimp="{_fmt(*p.solimp)}" material="cuticle"/>
    <pair condim="3" friction="{_fmt(p.friction, p.friction, 0.005, 0.0001, 0.0001)}"
          solref="{_fmt(*p.solref)}" solimp="{_fmt(*p.solimp)}"/>
    <default class="strut"><geom type="capsule" material="leg"/>{strut_joint}</default>
    <default class="leg"><geom type="capsule" material="leg"/></default>
    <default class="hind">
      <joint type="hinge" axis="0 1 0" damping="{p.joint_damping * s5:.9g}"
             armature="{p.joint_armature * s5:.9g}" limited="true"/>
    </default>
    <default class="servo">
      <position kp="{p.servo_kp * s5:.9g}" kv="{p.servo_kv * s5:.9g}"
                inheritrange="1"
                forcerange="{-flim:.9g} {flim:.9g}"/>
    </default>
  </default>
  <worldbody>
    <light name="sun" pos="0 0 {10 * bl:.9g}" dir="0 0 -1" directional="true"/>
    <geom name="{names.FLOOR}" type="plane" size="0 0 {0.05 * bl:.9g}" material="grid"/>
    <camera name="{names.CAMERA_SIDE}" pos="{4 * bl:.9g} {-9 * bl:.9g} {2 * bl:.9g}"
            xyaxes="1 0 0 0 0.2 1"/>
    <body name="{names.BODY}" pos="0 0 {h0:.9g}">
      <freejoint name="{names.ROOT_JOINT}"/>
      <camera name="{track}" mode="trackcom" pos="0 {-3 * bl:.9g} {0.6 * bl:.9g}"
              xyaxes="1 0 0 0 0.2 1"/>
      <geom name="{names.BODY}" type="capsule" fromto="{-p.body_half_length * s:.9g} 0 0
            {p.body_half_length * s:.9g} 0 0" size="{p.body_radius * s:.9g}"/>
      <geom name="{names.HEAD}" type="sphere" pos="{head_x:.9g} 0 0"
            size="{p.head_radius * s:.9g}"/>
      {legs}
    </body>
  </worldbody>
  <contact>{pairs}</contact>
  <actuator>{servos}</actuator>
  <sensor>{touch}</sensor>
</mujoco>
"""
    if keyframe:
        qpos, ctrl = _settle(xml, p)
        key = (
            f'  <keyframe><key name="{READY_KEY}" qpos="{_fmt(*qpos)}" '
            f'ctrl="{_fmt(*ctrl)}"/></keyframe>\n</mujoco>\n'
        )
        xml = xml.replace("</mujoco>\n", key)
    return xml


def _settle(xml: str, p: LocustParams) -> tuple[np.ndarray, np.ndarray]:
    """Settle the creature at phi for SETTLE_TIME; return qpos (x, y reset), ctrl."""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    qadr = [m.jnt_qposadr[m.joint(j).id] for j in names.ACTUATED_JOINTS]
    d.qpos[qadr] = p.ready_angles()
    d.ctrl[:] = p.ready_angles()
    mujoco.mj_forward(m, d)
    mujoco.mj_step(m, d, nstep=round(SETTLE_TIME / m.opt.timestep))
    qpos = d.qpos.copy()
    qpos[:2] = 0.0  # back to the origin, heading kept
    return qpos, d.ctrl.copy()


@lru_cache(maxsize=8)
def _compiled(p: LocustParams) -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_string(to_mjcf(p))


def load_model(p: LocustParams = LocustParams()) -> mujoco.MjModel:
    """A fresh ``MjModel`` of the creature (compiled once per parameter set)."""
    m = _compiled(p)
    return copy_model(m)


def check_model(p: LocustParams) -> None:
    """Compile the creature of ``p``; a ``UserError`` naming ``[model]`` if MuJoCo
    rejects it (called before anything is written)."""
    from locustjump.errors import UserError

    try:
        _compiled(p)
    except Exception as e:  # MuJoCo raises ValueError, FatalError, ...
        msg = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise UserError(f"[model]: MuJoCo rejects this creature ({msg})") from None


def copy_model(m: mujoco.MjModel) -> mujoco.MjModel:
    import copy

    return copy.copy(m)


@dataclass(frozen=True)
class ModelIndex:
    """Addresses of the named elements, read from a compiled model by name."""

    qpos_joints: np.ndarray = field(repr=False)  # (4,) qpos address of I1–I4
    qvel_joints: np.ndarray = field(repr=False)
    touch: np.ndarray = field(repr=False)  # (2,) sensordata address per tarsus
    ranges: np.ndarray = field(repr=False)  # (4, 2) joint ranges, radians
    ready_key: int = -1

    @classmethod
    def of(cls, m: mujoco.MjModel) -> ModelIndex:
        jids = [m.joint(j).id for j in names.ACTUATED_JOINTS]
        return cls(
            qpos_joints=np.array([m.jnt_qposadr[j] for j in jids]),
            qvel_joints=np.array([m.jnt_dofadr[j] for j in jids]),
            touch=np.array([m.sensor_adr[m.sensor(s).id] for s in names.TOUCH_SENSORS]),
            ranges=np.array([m.jnt_range[j] for j in jids]),
            ready_key=m.key(READY_KEY).id if m.nkey else -1,
        )
