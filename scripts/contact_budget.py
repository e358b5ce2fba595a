"""What pushed a creature, and with what work, substep by substep: the
measurements that ``scripts/wall_takeoff.py`` reports.

A recorded episode's servo targets are replayed, open loop, on one ``MjData``
with the engine's arithmetic, checked against the record. At each substep
each contact's force on the creature (``mj_contactForce``, contact frame to
world) times the timestep is summed by world geom and by pair, with the work
of contacts, servos, joint damping and constraints, and the wall contacts'
distance from the face. A ``Budget`` of control steps closes the impulses
(floor, rubble, walls; up, away from the side wall, forward) against gravity
and the momentum's change, the work against the energy's. A jump is measured
from ``LEAD`` steps before its apex; its take-off is the last step in which
the floor and the rubble pushed the creature up."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from locustjump.present.episodes import EpisodeScore, episode_score
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.analysis import clearance, find_jumps
from locustjump.sim.engine.backends import Backend
from locustjump.sim.engine.job import CONTACT_RECORDS, StartStates, observer
from locustjump.sim.scene import Scene
from locustjump.tasks.base import Behaviour

RECORD = ("qpos", "ctrl", "obs", "memory", *CONTACT_RECORDS)
FLOOR, RUBBLE, WALL = 0, 1, 2  #: contact classes (Replay.kind)
#: a jump touches no wall: no wall contact in this many steps to its apex;
#: its rise: the body centre's apex minus its lowest in these steps
QUIET = 150
LEAD = 300  #: a jump is measured from this many steps before its apex
KNEES = [names.ACTUATED_JOINTS.index(k) for k in names.KNEE_JOINTS]  #: their servos


@dataclass(frozen=True)
class Recorded:
    """One episode of the run's best genome, as the engine ran it."""

    here: Behaviour  #: the behaviour on this episode's scene
    p: lm.LocustParams
    genome: np.ndarray
    score: EpisodeScore  #: as ``score_run`` computes it
    rec: dict[str, np.ndarray]  #: the records of the one episode, (T + 1, ...)

    @property
    def label(self) -> str:
        seed = getattr(self.here.scene, "seed", None)
        return "flat floor" if seed is None else f"terrain {seed}"


def simulate(
    beh: Behaviour, genome: np.ndarray, engine: str, scene: Scene,
    p: lm.LocustParams, backend: Backend,
) -> Recorded:  # fmt: skip
    """The genome's episode on ``scene`` on the run's engine, recorded (as
    ``score_run`` simulates it, with more records)."""
    here = beh.on(scene)
    fit, res = here.evaluate(genome[None], p, backend=backend, engine=engine,
                             record=RECORD)  # fmt: skip
    score = episode_score(here, res, p, float(fit[0]))
    return Recorded(here, p, genome, score, {k: res[k][0] for k in RECORD})


class Replay:
    """One ``MjData`` stepped as the engine steps one episode (the arithmetic
    of ``sim.engine.episode.Episode``), measured when asked."""

    def __init__(self, here: Behaviour, p: lm.LocustParams):
        self.m = lm.load_model(p, here.scene)
        self.d = mujoco.MjData(self.m)
        self.scratch = mujoco.MjData(self.m)
        self.substeps = p.substeps
        index = lm.ModelIndex.of(self.m)
        self.walls = index.wall_geoms
        self.ranges = index.ranges
        self.joints = index.qpos_joints
        self.observe = observer(index, p)
        self.names = [self.m.geom(g).name for g in range(self.m.ngeom)]
        #: per geom: FLOOR, RUBBLE, WALL, or -1: the creature's
        self.kind = np.array([
            FLOOR if n == names.FLOOR else RUBBLE if n.startswith(names.DEBRIS)
            else WALL if n.startswith(names.WALL) else -1 for n in self.names
        ])  # fmt: skip
        self.mass = float(self.m.body_subtreemass[1])
        self.limit = self.m.actuator_forcerange[:, 1].copy()
        self.touch = np.zeros(self.m.nsensordata)
        self.gap = np.inf
        self._f6 = np.zeros(6)
        self._vel = np.zeros(6)

    def reset(self, starts: StartStates) -> None:
        m, d = self.m, self.d
        mujoco.mj_resetData(m, d)
        d.qpos[:], d.qvel[:], d.ctrl[:] = starts.qpos[0], starts.qvel[0], starts.ctrl[0]
        mujoco.mj_forward(m, d)
        self.touch[:] = d.sensordata

    def obs(self) -> np.ndarray:
        """The (1, 9) inputs now (touch: over the last control step)."""
        obs: np.ndarray = self.observe(self.d.qpos[None], self.touch[None])
        return obs

    def step(self, ctrl: np.ndarray, meter: Meter | None = None) -> set[int]:
        """One control step with servo targets ``ctrl``; the walls it touched
        (inside a wall's margin counts, as in the engine's record). Sets
        ``gap``: the least distance of a wall contact from its face (m)."""
        m, d = self.m, self.d
        d.ctrl[:] = ctrl
        self.touch[:] = -np.inf
        self.gap = np.inf
        walls: set[int] = set()
        for _ in range(self.substeps):
            v = d.qvel.copy()
            mujoco.mj_step(m, d)
            np.maximum(self.touch, d.sensordata, out=self.touch)
            n = d.ncon
            geoms = np.concatenate([d.contact.geom1[:n], d.contact.geom2[:n]])
            walls.update(int(g) for g in geoms[np.isin(geoms, self.walls)])
            hit = np.isin(geoms[:n], self.walls) | np.isin(geoms[n:], self.walls)
            gap = np.min(d.contact.dist[:n][hit], initial=np.inf)
            self.gap = min(self.gap, float(gap))
            if meter is not None:
                meter.add(self, v)
        return walls

    def state(self) -> tuple[np.ndarray, float, float]:
        """(the creature's linear momentum (3,), its centre of mass's height,
        kinetic + gravitational energy) now."""
        s, m = self.scratch, self.m
        s.qpos[:], s.qvel[:] = self.d.qpos, self.d.qvel
        mujoco.mj_forward(m, s)
        mujoco.mj_subtreeVel(m, s)
        mujoco.mj_energyPos(m, s)
        mujoco.mj_energyVel(m, s)
        return (self.mass * s.subtree_linvel[1].copy(), float(s.subtree_com[1, 2]),
                float(s.energy.sum()))  # fmt: skip

    def contacts(self) -> list[tuple[int, int, np.ndarray, np.ndarray]]:
        """The contacts the last ``mj_step`` applied (found at its start
        state): (world geom, creature geom, force on the creature (N, world
        axes), velocity of the creature's point of contact (m/s))."""
        m, d = self.m, self.d
        out = []
        for i in range(d.ncon):
            c = d.contact[i]
            g1, g2 = int(c.geom1), int(c.geom2)
            if (self.kind[g1] < 0) == (self.kind[g2] < 0):
                continue  # the creature on itself (none in this model)
            mujoco.mj_contactForce(m, d, i, self._f6)
            # geom1's force on geom2; the frame's rows are its axes, the
            # first the normal (from geom1 to geom2)
            force = c.frame.reshape(3, 3).T @ self._f6[:3]
            if self.kind[g2] >= 0:  # the creature is geom1
                force, g1, g2 = -force, g2, g1
            mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_GEOM, g2, self._vel, 0)
            v = self._vel[3:] + np.cross(self._vel[:3], c.pos - d.geom_xpos[g2])
            out.append((g1, g2, force, v))
        return out


class Meter:
    """One control step's sums over its substeps, each force taken at the
    substep's start state (where ``mj_step`` computes the force it applies):
    the contacts' impulses on the creature and work on it, by world geom and
    by pair; the servos' work and the substeps at their force limit; joint
    damping's and all constraint forces' work."""

    def __init__(self, ngeom: int, h: float):
        self.h = h
        self.impulse = np.zeros((ngeom, 3))  #: by world geom, N s, world axes
        self.pairs: dict[tuple[int, int], np.ndarray] = {}  #: (world, creature)
        self.work = np.zeros(ngeom)  #: by world geom, J
        self.servo = np.zeros(4)  #: J per servo
        self.at_limit = np.zeros(4)  #: substeps at the force limit, per servo
        self.force = np.zeros(4)  #: mean servo force / limit
        self.passive = 0.0
        self.constraint = 0.0
        self.substeps = 0

    def add(self, r: Replay, v: np.ndarray) -> None:
        """Measure the ``mj_step`` just taken from velocity ``v``."""
        d, h = r.d, self.h
        for g, c, force, at in r.contacts():
            self.impulse[g] += force * h
            self.pairs[g, c] = self.pairs.get((g, c), np.zeros(3)) + force * h
            self.work[g] += float(force @ at) * h
        f = d.actuator_force
        self.servo += f * d.actuator_velocity * h
        self.at_limit += np.abs(f) >= r.limit * (1 - 1e-9)
        self.force += f / r.limit
        self.passive += float(d.qfrc_passive @ v) * h
        self.constraint += float(d.qfrc_constraint @ v) * h
        self.substeps += 1


@dataclass(frozen=True)
class Trace:
    """A replayed episode measured on steps ``a + 1 .. b``: a meter per step
    and the states after steps ``a .. b``."""

    a: int
    b: int
    meters: list[Meter]
    momentum: np.ndarray  #: (n + 1, 3)
    com_z: np.ndarray  #: (n + 1,)
    energy: np.ndarray  #: (n + 1,)
    deviation: float  #: max |qpos - the engine's| over steps 0 .. b
    obs_equal: bool  #: the inputs equal the engine's at every step
    wall_mismatch: list[int]  #: steps whose wall flag differs from the record
    gap: np.ndarray  #: per step a + 1 .. b: Replay.gap (inf: no wall contact)
    kind: np.ndarray  #: per geom (Replay.kind)
    geoms: list[str]  #: the geoms' names
    weight: float  #: the creature's weight, N
    joints: np.ndarray  #: qpos addresses of the servos' joints

    def meter(self, t: int) -> Meter:
        """The meter of control step ``t``."""
        return self.meters[t - 1 - self.a]


def replay(r: Recorded, a: int, b: int) -> Trace:
    """The recorded servo targets replayed open loop up to step ``b``,
    measured on steps ``a + 1 .. b``."""
    rp = Replay(r.here, r.p)
    rp.reset(r.here.start_states(r.p))
    ctrl, qpos, obs, wall = (r.rec[k] for k in ("ctrl", "qpos", "obs", "wall_contact"))
    dev = float(np.abs(rp.d.qpos - qpos[0]).max())
    same = bool(np.array_equal(rp.obs()[0], obs[0]))
    mismatch: list[int] = []
    gaps: list[float] = []
    meters: list[Meter] = []
    states = []
    for t in range(b + 1):
        if t:
            meter = Meter(rp.m.ngeom, float(rp.m.opt.timestep)) if t > a else None
            if bool(rp.step(ctrl[t], meter)) != bool(wall[t]):
                mismatch.append(t)
            if meter is not None:
                meters.append(meter)
                gaps.append(rp.gap)
            dev = max(dev, float(np.abs(rp.d.qpos - qpos[t]).max()))
            same = same and bool(np.array_equal(rp.obs()[0], obs[t]))
        if t >= a:
            states.append(rp.state())
    return Trace(a, b, meters, np.array([s[0] for s in states]),
                 np.array([s[1] for s in states]), np.array([s[2] for s in states]),
                 dev, same, mismatch, np.array(gaps), rp.kind, rp.names,
                 rp.mass * float(-rp.m.opt.gravity[2]), rp.joints)  # fmt: skip


def axes_for(y: float, walls: bool) -> np.ndarray:
    """(3, 3) rows: up, away from the nearest side wall (the body at ``y``;
    +y on a scene without walls), forward."""
    away = -1.0 if walls and y > 0 else 1.0
    return np.array([[0.0, 0.0, 1.0], [0.0, away, 0.0], [1.0, 0.0, 0.0]])


@dataclass(frozen=True)
class Budget:
    """What acted on the creature over control steps ``a + 1 .. b``
    (directions: up, away from the wall, forward)."""

    label: str
    a: int
    b: int
    by_class: np.ndarray  #: (3 classes, 3 directions) contact impulse, N s
    by_pair: dict[str, np.ndarray]  #: "creature geom | world geom" -> N s
    gravity: float  #: N s, up
    change: np.ndarray  #: (3 directions) the momentum's change, N s
    v_z: tuple[float, float]  #: the centre of mass's vertical speed at a, b
    work: np.ndarray  #: (3 classes) the contacts' work, J
    servo: np.ndarray  #: (4,) each servo's work, J
    at_limit: np.ndarray  #: (4,) share of the substeps at the force limit
    angles: tuple[np.ndarray, np.ndarray]  #: joint angles (deg) at a, b
    passive: float  #: joint damping's work, J
    limits: float  #: the other constraints' (joint limits) work, J
    energy: float  #: change of kinetic + gravitational energy, J
    rise: float  #: the centre of mass's rise, m


def budget(
    label: str, tr: Trace, qpos: np.ndarray, a: int, b: int, axes: np.ndarray
) -> Budget:
    """The budget of steps ``a + 1 .. b`` of ``tr`` (``qpos``: the record)."""
    ms = tr.meters[a - tr.a : b - tr.a]
    imp = np.sum([m.impulse for m in ms], axis=0) @ axes.T  # (ngeom, 3)
    work = np.sum([m.work for m in ms], axis=0)
    pairs: dict[str, np.ndarray] = {}
    for m in ms:
        for (g, c), v in m.pairs.items():
            key = f"{tr.geoms[c]} \\| {tr.geoms[g]}"
            pairs[key] = pairs.get(key, np.zeros(3)) + v @ axes.T
    w = np.array([work[tr.kind == k].sum() for k in (FLOOR, RUBBLE, WALL)])
    i, j = a - tr.a, b - tr.a
    mass = tr.weight / 9.81
    subs = sum(m.substeps for m in ms)
    return Budget(
        label, a, b,
        np.array([imp[tr.kind == k].sum(axis=0) for k in (FLOOR, RUBBLE, WALL)]),
        pairs, -tr.weight * (b - a) * lm.CONTROL_DT,
        (tr.momentum[j] - tr.momentum[i]) @ axes.T,
        (float(tr.momentum[i, 2]) / mass, float(tr.momentum[j, 2]) / mass), w,
        np.sum([m.servo for m in ms], axis=0),
        np.sum([m.at_limit for m in ms], axis=0) / subs,
        (np.degrees(qpos[a, tr.joints]), np.degrees(qpos[b, tr.joints])),
        sum(m.passive for m in ms), sum(m.constraint for m in ms) - float(w.sum()),
        float(tr.energy[j] - tr.energy[i]), float(tr.com_z[j] - tr.com_z[i]),
    )  # fmt: skip


def take_off(tr: Trace, apex: int) -> int:
    """The last control step up to ``apex`` in which the floor and the rubble
    together pushed the creature up."""
    ground = (tr.kind == FLOOR) | (tr.kind == RUBBLE)
    for t in range(apex, tr.a, -1):
        if tr.meter(t).impulse[ground, 2].sum() > 0:
            return t
    raise ValueError(f"no push from the ground in steps {tr.a + 1}..{apex}")


@dataclass(frozen=True)
class Jump:
    """A jump of a recorded episode."""

    r: Recorded
    apex: int  #: control step
    height: float  #: (m) the body centre above the ground under it at the apex
    rise: float  #: (m) the body centre's apex minus its lowest in QUIET steps

    @property
    def label(self) -> str:
        return f"{self.r.label}, apex at step {self.apex}"


def jump_of(r: Recorded, qpos: np.ndarray, apex: int) -> Jump:
    """The jump of trajectory ``qpos`` (of ``r``'s scene) with apex ``apex``."""
    z = clearance(qpos[apex : apex + 1], r.p, r.here.scene)[0]
    low = float(qpos[max(apex - QUIET, 0) : apex + 1, 2].min())
    return Jump(r, apex, float(z), float(qpos[apex, 2] - low))


def quiet_jumps(r: Recorded) -> list[Jump]:
    """The jumps of ``r`` with no wall contact in the QUIET steps to the apex."""
    q, wall = r.rec["qpos"], r.rec["wall_contact"]
    return [
        jump_of(r, q, j.apex_step)
        for j in find_jumps(q, r.p, r.here.scene)
        if not wall[max(j.apex_step - QUIET, 0) : j.apex_step + 1].any()
    ]


@dataclass(frozen=True)
class Studied:
    """A jump replayed and measured from ``LEAD`` steps before its apex."""

    name: str
    jump: Jump
    trace: Trace
    take_off: int  #: its take-off step (:func:`take_off`)
    axes: np.ndarray  #: its directions (:func:`axes_for`)

    @classmethod
    def of(cls, name: str, j: Jump) -> Studied:
        tr = replay(j.r, max(j.apex - LEAD, 0), j.apex)
        to = take_off(tr, j.apex)
        walls = bool((tr.kind == WALL).any())
        return cls(name, j, tr, to, axes_for(float(j.r.rec["qpos"][to, 1]), walls))


def held(tr: Trace, qpos: np.ndarray, to: int) -> str:
    """The stretches of steps up to ``to`` in which both knee servos pushed
    at their force limit in every substep, with the knees' angles (deg) at
    the start and the end of the last one."""
    flags = np.zeros(to + 1, bool)
    for t in range(tr.a + 1, to + 1):
        m = tr.meter(t)
        flags[t] = all(m.at_limit[k] == m.substeps for k in KNEES)
    runs = stretches(flags, tr.a + 1, to)
    if not flags.any():
        return runs
    last = runs.split(", ")[-1].split("-")
    a, b = int(last[0]), int(last[-1])
    deg = [np.degrees(qpos[t, tr.joints[KNEES]]).round() for t in (a - 1, b)]
    return (f"{runs} (knees l, r at {deg[0][0]:.0f}, {deg[0][1]:.0f} deg before "
            f"step {a}, {deg[1][0]:.0f}, {deg[1][1]:.0f} after step {b})")  # fmt: skip


def stretches(flags: np.ndarray, a: int, b: int) -> str:
    """The stretches of steps in ``a .. b`` whose flag is set."""
    hit = [t for t in range(a, b + 1) if flags[t]]
    out: list[str] = []
    for k, t in enumerate(hit):
        if k == 0 or hit[k - 1] != t - 1:
            first = t
        if k + 1 == len(hit) or hit[k + 1] != t + 1:
            out.append(f"{first}" if first == t else f"{first}-{t}")
    return ", ".join(out) or "none"
