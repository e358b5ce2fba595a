"""One creature and one scene -> one MJCF document -> ``mujoco.MjModel``.

The creature (:mod:`~locustjump.sim.creature`: bodies, joints, servos, touch
sensors) and the scene (:mod:`~locustjump.sim.scene`: the floor, or another
world) each write their pieces; this module writes what they share: the
solver options, the contact model, the light and the fixed camera, one
contact pair per (scene geom, creature geom), and the contact sensors the
engine records penetration and wall contact from (they observe only).

The physics timestep is ``CONTROL_DT / substeps``; contact softness is fixed in
seconds (``solref``) so that refining the timestep does not change the contact
model (PHYSICS-NOTES, convergence trap). See ``docs/physics.md`` for how the
defaults were chosen.
"""

from __future__ import annotations

import copy
import logging
from dataclasses import dataclass, field
from functools import lru_cache

import mujoco
import numpy as np

from locustjump.errors import UserError
from locustjump.sim import names
from locustjump.sim.bvh import rebuild_bvh
from locustjump.sim.creature import (  # noqa: F401 (re-exported)
    CONTACT_GEOMS,
    creature_mjcf,
    leg_tip,
)
from locustjump.sim.creature import standing_height as standing_height
from locustjump.sim.params import CONTROL_DT as CONTROL_DT
from locustjump.sim.params import LocustParams as LocustParams
from locustjump.sim.scene import Flat, Scene

#: MuJoCo's warnings (an unstable simulation: the engine stops that episode
#: and flags it, ``RolloutResult.unstable``), at INFO instead of MuJoCo's
#: default of printing them and appending them to ``MUJOCO_LOG.TXT`` in the
#: working directory, which no command may write into
MUJOCO_LOG = logging.getLogger("locustjump.mujoco")
if mujoco.get_mju_user_warning() is None:  # a handler of the user's stays
    mujoco.set_mju_user_warning(lambda msg: MUJOCO_LOG.info("MuJoCo: %s", msg))

SETTLE_TIME = 1.0  # (Seconds) settling before t = 0
READY_KEY = names.READY_KEY  # keyframe of the settled start state (Fig. 4)


def _fmt(*values: float) -> str:
    return " ".join(f"{v:.9g}" for v in values)


def contact_pairs(scene_geoms: tuple[str, ...]) -> list[tuple[str, str]]:
    """(scene geom, creature geom) of every contact pair, as written: each scene
    geom in turn against every creature geom (MuJoCo then sorts them by body,
    keeping this order within one)."""
    return [(g, c) for g in scene_geoms for c in CONTACT_GEOMS]


def contact_sensors(walls: tuple[str, ...]) -> str:
    """The contact sensors the engine records from (``penetration``,
    ``wall_contact``): the signed distance (m, negative: penetrating) of the
    creature's deepest contact, 0 without one; per geom of ``walls`` the number
    of its contacts. Position-stage sensors: they read the contacts, never
    change them."""
    deepest = (
        f'\n    <contact name="{names.DEEPEST_CONTACT}" subtree1="{names.BODY}" '
        'data="dist" reduce="mindist" num="1"/>'
    )
    return deepest + "".join(
        f'\n    <contact name="{names.WALL_CONTACT}{i}" geom1="{w}" data="found"/>'
        for i, w in enumerate(walls)
    )


def to_mjcf(
    p: LocustParams = LocustParams(), *, scene: Scene = Flat(), keyframe: bool = True
) -> str:
    """The complete MJCF document of the creature in its scene.

    Args:
      p: the creature's parameter set (and the solver's, the contact model's).
      scene: the world it stands in (default: the flat floor).
      keyframe: whether to settle the creature and store the start state of
        Fig. 4 as keyframe ``"ready"`` (needs one short simulation).
    """
    bl = p.body_length
    creature = creature_mjcf(p)
    world = scene.mjcf(bl)
    # Only the creature against the scene collides, as explicit pairs (no
    # broad phase: mj_step 6.1 -> 5.4 us, bit-identical trajectories).
    pairs = "".join(
        f'\n    <pair geom1="{g}" geom2="{c}"/>' for g, c in contact_pairs(world.geoms)
    )
    probes = contact_sensors(world.walls)
    # A scene of many static geoms: with sleeping on, MuJoCo stops computing
    # their poses at every step (1 us of a debris step's 10); the creature
    # itself never sleeps (its tree's policy), so nothing else changes
    # (bit-identical). The price: a mujoco.batch.Batch of it must be persistent.
    flags = '\n    <flag sleep="enable"/>\n  ' if world.broad_phase else ""
    xml = f"""<mujoco model="locust">
  <compiler angle="degree" autolimits="true"/>
  <option timestep="{p.timestep:.12g}" integrator="{p.integrator}" cone="pyramidal"
          iterations="{p.iterations}" ls_iterations="{p.ls_iterations}">{flags}</option>
  <size memory="1M" nuserdata="3"/>
  <visual>
    <global offwidth="1280" offheight="720"/>
    <quality shadowsize="2048"/>
    <headlight ambient="0.4 0.4 0.4" diffuse="0.6 0.6 0.6"/>
  </visual>
  <asset>
    <texture name="sky" type="skybox" builtin="gradient" width="256" height="256"
             rgb1="0.55 0.70 0.88" rgb2="0.95 0.96 0.98"/>
    {world.assets}
    {creature.assets}
  </asset>
  <default>
    <geom contype="{int(world.broad_phase)}" conaffinity="0" condim="3"
          friction="{p.friction:.9g} 0.005 0.0001"
          solref="{_fmt(*p.solref)}" solimp="{_fmt(*p.solimp)}"/>
    <pair condim="3" friction="{_fmt(p.friction, p.friction, 0.005, 0.0001, 0.0001)}"
          solref="{_fmt(*p.solref)}" solimp="{_fmt(*p.solimp)}"/>
    {creature.defaults}
  </default>
  <worldbody>
    <light name="sun" pos="0 0 {10 * bl:.9g}" dir="0 0 -1" directional="true"/>
    {world.worldbody}
    <camera name="{names.CAMERA_SIDE}" pos="{4 * bl:.9g} {-9 * bl:.9g} {2 * bl:.9g}"
            xyaxes="1 0 0 0 0.2 1"/>
    {creature.body}
  </worldbody>
  <contact>{pairs}</contact>
  <actuator>{creature.actuators}</actuator>
  <sensor>{creature.sensors}{probes}</sensor>
</mujoco>
"""
    if keyframe:  # the creature's ready posture, settled on the flat floor
        flat = xml if scene.is_flat else to_mjcf(p, keyframe=False)
        qpos, ctrl = _settle(flat, p)
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
def _compiled(p: LocustParams, scene: Scene) -> mujoco.MjModel:
    m = mujoco.MjModel.from_xml_string(to_mjcf(p, scene=scene))
    # a scene's many static geoms: a tree that lets the midphase stop early
    # (same contacts, in the same order; nothing to do on the flat floor)
    rebuild_bvh(m)
    return m


def load_model(
    p: LocustParams = LocustParams(), scene: Scene = Flat()
) -> mujoco.MjModel:
    """A fresh ``MjModel`` of the creature in ``scene`` (compiled once per
    parameter set and scene)."""
    return copy_model(_compiled(p, scene))


def check_model(p: LocustParams, scene: Scene = Flat()) -> None:
    """Compile the creature of ``p`` in ``scene``; a ``UserError`` naming
    ``[model]`` if MuJoCo rejects it (called before anything is written)."""

    try:
        _compiled(p, scene)
    except Exception as e:  # MuJoCo raises ValueError, FatalError, ...
        msg = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise UserError(f"[model]: MuJoCo rejects this creature ({msg})") from None


def copy_model(m: mujoco.MjModel) -> mujoco.MjModel:

    return copy.copy(m)


@dataclass(frozen=True)
class ModelIndex:
    """Addresses of the named elements, read from a compiled model by name."""

    qpos_joints: np.ndarray = field(repr=False)  # (4,) qpos address of I1–I4
    touch: np.ndarray = field(repr=False)  # (2,) sensordata address per tarsus
    ranges: np.ndarray = field(repr=False)  # (4, 2) joint ranges, radians
    ready_key: int = -1
    #: sensordata address of the deepest contact's signed distance (m)
    deepest: int = -1
    #: (k,) sensordata addresses of the wall sensors (contacts of each wall)
    walls: np.ndarray = field(default_factory=lambda: np.empty(0, int), repr=False)
    #: (k,) the geom each of them watches
    wall_geoms: np.ndarray = field(default_factory=lambda: np.empty(0, int), repr=False)

    @classmethod
    def of(cls, m: mujoco.MjModel) -> ModelIndex:
        jids = [m.joint(j).id for j in names.ACTUATED_JOINTS]
        sensors = [m.sensor(i).name for i in range(m.nsensor)]
        walls = [i for i, s in enumerate(sensors) if s.startswith(names.WALL_CONTACT)]
        return cls(
            qpos_joints=np.array([m.jnt_qposadr[j] for j in jids]),
            touch=np.array([m.sensor_adr[m.sensor(s).id] for s in names.TOUCH_SENSORS]),
            ranges=np.array([m.jnt_range[j] for j in jids]),
            ready_key=m.key(READY_KEY).id if m.nkey else -1,
            deepest=int(m.sensor_adr[m.sensor(names.DEEPEST_CONTACT).id]),
            walls=m.sensor_adr[walls].astype(int),
            wall_geoms=m.sensor_objid[walls].astype(int),
        )
