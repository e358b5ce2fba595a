"""The locust apart from its world: its bodies, joints, actuators and sensors as
pieces of MJCF, and the geoms of it that may touch the world.

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

:mod:`locustjump.sim.model` puts these pieces into one document with a
:mod:`~locustjump.sim.scene`; nothing here knows the world it stands in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from locustjump.sim import names
from locustjump.sim.params import LocustParams

#: The default class of everything of the creature (its density and cuticle
#: colour); the contact model above it is the world's.
CLASS = "locust"

#: Every geom of the creature, each of which may touch the world, in the order
#: its contact pairs are written. MuJoCo sorts the pairs by body, keeping this
#: order within a body, and the solver takes the contacts in that order:
#: changing it may change every trajectory.
CONTACT_GEOMS: tuple[str, ...] = (
    names.BODY,
    names.HEAD,
    *(
        leg
        for pair in zip(names.FORE_LEGS, names.MID_LEGS, strict=True)
        for leg in pair
    ),
    *(
        geom
        for i in range(len(names.SIDES))
        for geom in (names.FEMURS[i], names.TIBIAE[i], names.TARSI[i])
    ),
)


@dataclass(frozen=True)
class CreatureMJCF:
    """The creature's pieces of one MJCF document, each a fragment of XML."""

    assets: str  #: children of ``<asset>``: its materials
    defaults: str  #: a child of ``<default>``: class ``CLASS`` and its classes
    body: str  #: a child of ``<worldbody>``: the body, its legs and camera
    actuators: str  #: children of ``<actuator>``: the four servos
    sensors: str  #: children of ``<sensor>``: the two touch sensors


def _fmt(*values: float) -> str:
    return " ".join(f"{v:.9g}" for v in values)


def _unit(v: ArrayLike) -> NDArray[np.float64]:
    a = np.asarray(v, float)
    unit: NDArray[np.float64] = a / np.linalg.norm(a)
    return unit


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
    height: float = -(p.hip_pos[2] * p.scale + tz) + p.tarsus_radius * p.scale
    return height


def _strut(
    p: LocustParams,
    nm: str,
    sign: float,
    attach: tuple[float, float, float],
    direction: tuple[float, float, float],
) -> str:
    s = p.scale
    a = np.array(attach) * s * np.array([1, sign, 1])
    d = _unit(direction) * np.array([1, sign, 1])
    # long enough for the tip sphere to touch the ground when standing
    drop = standing_height(p) + a[2] - (p.strut_radius + p.strut_clearance) * s
    length = drop / -d[2]
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


def _hind_leg(p: LocustParams, i: int, sign: float) -> str:
    s = p.scale
    hx, hy, hz = np.array(p.hip_pos) * s * np.array([1, sign, 1])
    lf, lt = p.femur_length * s, p.tibia_length * s
    lo_h, hi_h = p.hip_range
    lo_k, hi_k = p.knee_range
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


def _defaults(p: LocustParams) -> str:
    s5 = p.scale**5
    flim = p.servo_force_limit * s5
    strut_joint = (
        ""
        if p.strut_stiffness == 0
        else f'<joint type="hinge" stiffness="{p.strut_stiffness * s5:.9g}" '
        f'damping="{p.strut_damping * s5:.9g}" '
        f'armature="{p.joint_armature * s5:.9g}" '
        f'range="{-p.strut_swing:.9g} {p.strut_swing:.9g}"/>'
    )
    return f"""<default class="{CLASS}">
      <geom density="{p.density:.9g}" material="cuticle"/>
      <default class="strut">
        <geom type="capsule" material="leg"/>{strut_joint}
      </default>
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
    </default>"""


def creature_mjcf(p: LocustParams) -> CreatureMJCF:
    """The creature of ``p`` as pieces of MJCF (see :class:`CreatureMJCF`).

    Its elements are in class ``CLASS``, which the document's ``<default>``
    must hold (the world's contact model around it). The body stands level at
    :func:`standing_height` above z = 0.
    """
    s = p.scale
    bl = p.body_length
    legs = "".join(
        _strut(p, names.FORE_LEGS[i], sign, p.fore_attach, p.fore_dir)
        + _strut(p, names.MID_LEGS[i], sign, p.mid_attach, p.mid_dir)
        + _hind_leg(p, i, sign)
        for i, sign in enumerate((1.0, -1.0))
    )
    head_x = (p.body_half_length + p.head_radius) * s
    h0 = standing_height(p)
    # sleep="never": it is always simulated, also where the world sleeps
    body = f"""<body name="{names.BODY}" childclass="{CLASS}" pos="0 0 {h0:.9g}"
      sleep="never">
      <freejoint name="{names.ROOT_JOINT}"/>
      <camera name="{names.CAMERA_TRACK}" mode="trackcom"
              pos="0 {-3 * bl:.9g} {0.6 * bl:.9g}" xyaxes="1 0 0 0 0.2 1"/>
      <geom name="{names.BODY}" type="capsule" fromto="{-p.body_half_length * s:.9g} 0 0
            {p.body_half_length * s:.9g} 0 0" size="{p.body_radius * s:.9g}"/>
      <geom name="{names.HEAD}" type="sphere" pos="{head_x:.9g} 0 0"
            size="{p.head_radius * s:.9g}"/>
      {legs}
    </body>"""
    servos = "".join(
        f'<position name="{a}" joint="{j}" class="servo"/>'
        for a, j in zip(names.ACTUATORS, names.ACTUATED_JOINTS, strict=True)
    )
    touch = "".join(
        f'<touch name="{t}" site="{site}"/>'
        for t, site in zip(names.TOUCH_SENSORS, names.TARSUS_SITES, strict=True)
    )
    return CreatureMJCF(
        assets='<material name="cuticle" rgba="0.55 0.62 0.25 1"/>\n'
        '    <material name="leg" rgba="0.45 0.50 0.20 1"/>',
        defaults=_defaults(p),
        body=body,
        actuators=servos,
        sensors=touch,
    )
