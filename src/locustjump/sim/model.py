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

import copy
import math
from dataclasses import dataclass, field
from functools import lru_cache

import mujoco
import numpy as np

from locustjump.errors import UserError
from locustjump.sim import names
from locustjump.sim.params import (  # noqa: F401 (re-exported)
    CONTROL_DT,
    LocustParams,
)

SETTLE_TIME = 1.0  # (Seconds) settling before t = 0
READY_KEY = names.READY_KEY  # keyframe of the settled start state (Fig. 4)


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
  <size memory="1M" nuserdata="3"/>
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
    return copy_model(_compiled(p))


def check_model(p: LocustParams) -> None:
    """Compile the creature of ``p``; a ``UserError`` naming ``[model]`` if MuJoCo
    rejects it (called before anything is written)."""

    try:
        _compiled(p)
    except Exception as e:  # MuJoCo raises ValueError, FatalError, ...
        msg = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise UserError(f"[model]: MuJoCo rejects this creature ({msg})") from None


def copy_model(m: mujoco.MjModel) -> mujoco.MjModel:

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
