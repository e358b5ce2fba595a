"""Per-episode diagnostics of a run's best genome: tables that can catch an
exploit (issue #44).

:func:`score_run` re-simulates a run's best genome in its behaviour's episode
on each terrain asked for and returns one :class:`EpisodeScore` per terrain:
the behaviour's own fitness (what ``locustjump evaluate RUN --terrain-seeds``
and ``Behaviour.evaluate`` give), the terms it adds up (composed and
monolithic: Eq. 4's height above the ground and 200 x forward progress),
and what no fitness shows: the share of control steps spent touching a wall,
the deepest penetration of any contact and the highest the body rose. The
contact figures come from the engine's records ``penetration`` and
``wall_contact`` (:data:`~locustjump.sim.engine.job.CONTACT_RECORDS`: maxima
over each control step's physics substeps, from MuJoCo's contact sensors).

:func:`deepest_contact` finds, for one terrain, where that deepest contact
was: the step, the two geoms, and how fast they approached when it began.

Example::

    from locustjump.present.episodes import score_run
    for s in score_run("results/debris/long-seed0/monolithic",
                       terrain_seeds=range(100, 120)):
        print(s.terrain, s.fitness, s.height_term, s.distance_term,
              s.wall_contact, s.penetration_m)
"""

from __future__ import annotations

import copy
import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from locustjump import rundir
from locustjump.sim import model as lm
from locustjump.sim.analysis import clearance, find_jumps
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.job import CONTACT_RECORDS
from locustjump.sim.scene import Scene

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend
    from locustjump.sim.engine.job import RolloutResult, StartStates
    from locustjump.tasks.base import Behaviour


@dataclass(frozen=True)
class EpisodeScore:
    """One run's best genome in its behaviour's episode on one terrain.

    With several start states (a behaviour that has them), ``fitness`` and
    the terms are their mean (as the behaviour scores), ``distance_m`` their
    mean, ``jumps`` their sum, ``wall_contact`` the share over all their
    control steps and the maxima over all of them. An episode that went
    unstable counts up to its last simulated step. A run with the option
    ``score_substeps`` is scored as it trained (the minimum over those
    resolutions) where :func:`score_run` is given no ``substeps``, and at
    the ``substeps`` it is given alone otherwise; the terms and the other
    figures are of the episode simulated at ``substeps``, so only as trained
    may the terms not add up to the fitness.
    """

    #: debris terrain seed; None on a scene without terrains (the flat floor)
    terrain: int | None
    #: the behaviour's own fitness (mean over its start states), as
    #: ``Behaviour.evaluate`` and ``locustjump evaluate --terrain-seeds`` give
    fitness: float
    #: composed/monolithic: Eq. 4's sum of the body's height above the ground
    #: under it (m x steps); None for behaviours without terms
    height_term: float | None
    #: composed/monolithic: 200 x forward progress (m x steps; 0 on the flat
    #: floor); ``height_term + distance_term == fitness``
    distance_term: float | None
    distance_m: float  #: forward progress of the body centre (m)
    jumps: int  #: jumps (``sim.analysis.find_jumps``)
    #: share of control steps with any contact between the creature and a wall
    #: (0 on scenes without walls); a contact inside a wall's margin
    #: (``Debris.wall_margin``: the wall already pushes, the limb has not
    #: reached its face) counts as touching it
    wall_contact: float
    #: deepest penetration (m) of any contact of the creature (rubble, floor,
    #: walls: into a wall's face, not its margin), the maximum over the
    #: episode and its physics substeps
    penetration_m: float
    #: the body centre's highest point above the ground under it (m)
    highest_m: float
    unstable: bool = False  #: an episode's simulation went unstable

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def score_run(
    run: str | os.PathLike[str],
    *,
    terrain_seeds: Sequence[int] | None = None,
    substeps: int | None = None,
    scene: Scene | None = None,
    backend: Backend | None = None,
) -> list[EpisodeScore]:
    """Run ``run``'s best genome in its behaviour's episode on each terrain.

    Args:
      run: a run directory with a best genome.
      terrain_seeds: terrain seeds of the run's own scene kind and parameters
        (``scene``'s if given); None: the run's own terrains (its training
        terrains; one score on the flat floor).
      substeps: physics substeps per control step; None: as trained (a run
        with ``score_substeps``: the worst of its resolutions, as it was
        scored in training; given, the fitness at these substeps alone).
      scene: another scene kind and parameters than the run's (e.g. a flat-
        floor run zero-shot on ``Debris()``).
      backend: where to simulate (default: a thread backend, this call only).

    Returns:
      One :class:`EpisodeScore` per terrain, in order. Simulated on the
      run's engine; recording the contacts changes no number (the ``numba``
      engine runs them on its step-by-step loop, which gives its numbers).

    Raises:
      ValueError: ``terrain_seeds`` for a scene with one terrain, or a bad
        ``substeps``.
    """
    cfg, beh, best = rundir.load_run(Path(run))
    p = cfg.model
    if substeps is not None:
        if isinstance(substeps, bool) or not isinstance(substeps, int):
            raise ValueError(f"substeps must be an integer, got {substeps!r}")
        p = dataclasses.replace(p, substeps=substeps)
        if beh.options.score_substeps:  # judged at these substeps alone
            beh = copy.copy(beh)
            beh.options = dataclasses.replace(beh.options, score_substeps=())
    scenes = _scenes(beh, terrain_seeds, scene)
    own = backend is None
    backend = ThreadBackend() if backend is None else backend
    try:
        return [_score(beh.on(s), best.genome, p, cfg.engine, backend) for s in scenes]
    finally:
        if own:
            backend.close()


def _scenes(
    beh: Behaviour, seeds: Sequence[int] | None, scene: Scene | None
) -> list[Scene]:
    base = beh.terrains.scene if scene is None else scene
    if seeds is None:
        return list(beh.terrains.scenes) if scene is None else [scene]
    if not base.seeded:
        raise ValueError(
            f"terrain_seeds: the {base.name} scene has one terrain (give a scene "
            "with terrains, e.g. Debris())"
        )
    return [base.with_seed(int(s)) for s in seeds]


def _score(
    here: Behaviour,
    genome: np.ndarray,
    p: lm.LocustParams,
    engine: str,
    backend: Backend,
) -> EpisodeScore:
    """The score of ``genome`` in ``here``'s (one-terrain) episode."""
    record = tuple(dict.fromkeys(("qpos", *here.record, *CONTACT_RECORDS)))
    fit, res = here.evaluate(
        genome[None], p, backend=backend, engine=engine, record=record
    )
    return episode_score(here, res, p, float(fit[0]))


def episode_score(
    here: Behaviour, res: RolloutResult, p: lm.LocustParams, fitness: float
) -> EpisodeScore:
    """The :class:`EpisodeScore` of one controller's episodes ``res`` (from
    each of ``here``'s start states; recorded: ``qpos`` and
    :data:`~locustjump.sim.engine.job.CONTACT_RECORDS`) in ``here``'s scene,
    at physics ``p``; ``fitness``: its fitness as the behaviour scores it."""
    terms = here.fitness_terms(res, p)
    height = terms["height"][0] if "height" in terms else None
    distance = terms["distance"][0] if "distance" in terms else None
    scene = here.scene
    # each episode up to its last simulated step (an unstable one repeats it)
    episodes = [
        (q[: n + 1], pen[: n + 1], wall[1 : n + 1])
        for q, pen, wall, n in zip(
            res["qpos"], res["penetration"], res["wall_contact"], res.steps,
            strict=True,
        )
    ]  # fmt: skip
    walls = np.concatenate([w for _, _, w in episodes])
    return EpisodeScore(
        terrain=getattr(scene, "seed", None),
        fitness=float(fitness),
        height_term=None if height is None else float(height),
        distance_term=None if distance is None else float(distance),
        distance_m=float(np.mean([q[-1, 0] - q[0, 0] for q, _, _ in episodes])),
        jumps=sum(len(find_jumps(q, p, scene)) for q, _, _ in episodes),
        wall_contact=float(walls.mean()) if walls.size else 0.0,
        penetration_m=float(max(pen.max() for _, pen, _ in episodes)),
        highest_m=float(max(clearance(q, p, scene).max() for q, _, _ in episodes)),
        unstable=bool(res.unstable.any()),
    )


@dataclass(frozen=True)
class DeepestContact:
    """Where an episode's deepest contact was (:func:`deepest_contact`)."""

    terrain: int | None  #: terrain seed (None: a scene without terrains)
    episode: int  #: the start state's index
    step: int  #: control step (its physics: after action ``step - 1``)
    substep: int  #: physics substep within it (0-based)
    #: penetration (m) into the geom's face; negative: a contact inside a
    #: wall's margin that stopped that far short of it
    depth_m: float
    geoms: tuple[str, str]  #: the contact's geoms (MuJoCo's geom1, geom2)
    #: (m/s) speed at which they approached along the contact normal at the
    #: first substep of this spell of contact between them
    approach_speed: float
    #: (m/s) their relative speed then, in any direction: a limb this fast
    #: moves ``speed * timestep`` in one substep, so its first contact may be
    #: found that deep already (MuJoCo has no continuous collision detection)
    speed: float
    #: (N) the contact's normal force at the deepest substep
    normal_force: float

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def deepest_contact(
    run: str | os.PathLike[str],
    *,
    terrain: int | None = None,
    substeps: int | None = None,
    scene: Scene | None = None,
    among: str | None = None,
    backend: Backend | None = None,
) -> DeepestContact | None:
    """The deepest contact of run ``run``'s best genome in its behaviour's
    episode on terrain ``terrain`` (of its scene, or ``scene``'s; None: its
    first training terrain), at ``substeps`` (None: as trained); with
    ``among``, the deepest of the contacts with a geom whose name starts
    with it (e.g. ``names.WALL``; None if there is none).

    The episode is simulated on the run's engine (recording the servo targets
    and ``penetration``), then its servo targets are replayed, open loop, on
    one ``MjData`` (the same arithmetic as the engine's, so the same states):
    the contact found deepest at a substep, and the speeds at which its two
    geoms met when they last came into contact.

    Raises:
      ValueError: the replay did not reproduce the recorded penetration.
    """
    cfg, beh, best = rundir.load_run(Path(run))
    p = cfg.model
    if substeps is not None:
        p = dataclasses.replace(p, substeps=substeps)
    seeds = None if terrain is None else [terrain]
    here = beh.on(_scenes(beh, seeds, scene)[0])
    starts = here.start_states(p)
    own = backend is None
    backend = ThreadBackend() if backend is None else backend
    try:
        res = here.simulate(best.genome[None], p, backend=backend, engine=cfg.engine,
                            record=("ctrl", "penetration"))  # fmt: skip
    finally:
        if own:
            backend.close()
    pen = res["penetration"]
    if among is None:  # the recorded deepest: replay up to its step
        e, until = map(int, np.unravel_index(int(np.argmax(pen)), pen.shape))
    else:
        e, until = int(np.argmax(pen.max(axis=1))), int(res.steps.max())
    m = lm.load_model(p, here.scene)
    found = _replay(m, p, starts, int(e), res["ctrl"][e], int(until), among)
    if among is None and not np.isclose(found["depth_m"], pen[e, until], atol=1e-12):
        raise ValueError(
            f"the replay found {found['depth_m']} m at step {until}, the rollout "
            f"recorded {pen[e, until]} m"
        )
    if found["step"] < 0:
        return None
    return DeepestContact(getattr(here.scene, "seed", None), int(e), **found)


def _replay(
    m: mujoco.MjModel,
    p: lm.LocustParams,
    starts: StartStates,
    e: int,
    ctrl: np.ndarray,
    until: int,
    among: str | None,
) -> dict[str, Any]:
    """From start state ``e``, servo targets ``ctrl (T + 1, nu)`` replayed up
    to control step ``until``: the deepest contact (of a geom named
    ``among...`` if given; step -1: none) and the speeds at which its geoms
    began touching."""
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:], d.ctrl[:] = starts.qpos[e], starts.qvel[e], starts.ctrl[e]
    mujoco.mj_forward(m, d)
    names = [m.geom(g).name for g in range(m.ngeom)]
    watch = np.array([among is None or n.startswith(among) for n in names])
    onset: dict[
        tuple[int, int], tuple[float, float]
    ] = {}  # pair -> speeds at its onset
    best: dict[str, Any] = {"step": -1, "depth_m": -np.inf}
    for t in range(until + 1):
        d.ctrl[:] = ctrl[t]
        for sub in range(p.substeps if t else 1):
            if t:  # the contacts of the state at the substep's start
                mujoco.mj_step(m, d)
            n = d.ncon
            g1, g2 = d.contact.geom1[:n], d.contact.geom2[:n]
            pairs: dict[tuple[int, int], tuple[float, float]] = {}
            for i in range(n):
                pair = (int(g1[i]), int(g2[i]))
                known = onset.get(pair)
                pairs[pair] = (
                    _approach_speed(m, d, d.contact[i]) if known is None else known
                )
            onset = pairs
            ok = np.flatnonzero(watch[g1] | watch[g2])
            if ok.size == 0:
                continue
            i = int(ok[np.argmin(d.contact.dist[ok])])
            if -d.contact.dist[i] > best["depth_m"]:
                force = np.zeros(6)
                mujoco.mj_contactForce(m, d, i, force)
                pair = (int(g1[i]), int(g2[i]))
                best = {"step": t, "substep": sub, "depth_m": float(-d.contact.dist[i]),
                        "geoms": (names[pair[0]], names[pair[1]]),
                        "approach_speed": onset[pair][0], "speed": onset[pair][1],
                        "normal_force": float(force[0])}  # fmt: skip
    return best


def _approach_speed(
    m: mujoco.MjModel, d: mujoco.MjData, c: mujoco.MjContact
) -> tuple[float, float]:
    """(m/s) how fast contact ``c``'s geoms approach each other along its
    normal at its point (positive: closing), and their relative speed."""
    v = []
    for g in (c.geom1, c.geom2):
        vel = np.zeros(6)  # (angular, linear) at the geom's frame, world axes
        mujoco.mj_objectVelocity(m, d, mujoco.mjtObj.mjOBJ_GEOM, int(g), vel, 0)
        v.append(vel[3:] + np.cross(vel[:3], c.pos - d.geom_xpos[g]))
    # the normal points from geom1 to geom2: closing when geom2 moves against it
    rel = v[1] - v[0]
    return float(-rel @ c.frame[:3]), float(np.linalg.norm(rel))
