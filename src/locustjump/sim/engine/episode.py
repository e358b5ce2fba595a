"""One episode on one ``MjData``: the engine's control step, unbatched, and the
plain reference loop the engine is tested against (bit for bit). It shares the
engine's inputs (:func:`~.job.observer`), records (:class:`~.job.Recorder`)
and unstable rule (:func:`~.job.went_unstable`); only the stepping is its own."""

from __future__ import annotations

import mujoco
import numpy as np

from locustjump.sim import actuation
from locustjump.sim import model as lm
from locustjump.sim.engine.job import (
    Recorder,
    RolloutJob,
    RolloutResult,
    StartStates,
    depth,
    observer,
    record_shapes,
    records_contacts,
    went_unstable,
)
from locustjump.sim.scene import Flat, Scene


class Episode:
    """One episode on one ``MjData``: the engine's control step, unbatched.

    The same operations, in the same order, as a row of the engine, so the
    results are bit-identical to it. Used by :func:`reference_rollout`, the
    Gymnasium environments (:mod:`locustjump.envs`) and the viewer::

        ep = Episode(LocustParams())
        obs = ep.reset(starts, 0)            # (1, 9)
        obs = ep.step(deltas)                # deltas (1, 4), radians
        ep.unstable                          # the simulation went unstable

    With ``contacts``, it also keeps :data:`~.job.CONTACT_RECORDS` of the
    last control step, read from MuJoCo's contacts after every substep (not
    from the contact sensors the engine reads): :attr:`penetration` (m) and
    :attr:`wall_contact` (1.0 or 0.0).
    """

    def __init__(
        self,
        model_params: lm.LocustParams = lm.LocustParams(),
        scene: Scene = Flat(),
        *,
        contacts: bool = False,
    ):
        self.params = model_params
        self.model = lm.load_model(model_params, scene)
        self.data = mujoco.MjData(self.model)
        self.index = lm.ModelIndex.of(self.model)
        self._observe = observer(self.index, model_params)
        self._touch = self.data.sensordata.copy()  # sensordata, max over substeps
        self.unstable = False
        self.contacts = contacts
        self.penetration = self.wall_contact = 0.0

    def reset(self, starts: StartStates, i: int = 0) -> np.ndarray:
        """Start from state ``i`` of ``starts``; the (1, 9) inputs there."""
        m, d = self.model, self.data
        mujoco.mj_resetData(m, d)
        d.qpos[:], d.qvel[:], d.ctrl[:] = starts.qpos[i], starts.qvel[i], starts.ctrl[i]
        mujoco.mj_forward(m, d)
        self._touch[:] = d.sensordata
        self.unstable = False
        if self.contacts:
            dist, wall = self._contacts()
            self.penetration, self.wall_contact = float(depth(dist)), float(wall)
        return self.observe()

    def _contacts(self) -> tuple[float, bool]:
        """(smallest signed distance (m), 0 without a contact; whether one is
        with a wall) of the contacts MuJoCo found last."""
        c = self.data.contact
        n = self.data.ncon
        dist = float(c.dist[:n].min()) if n else 0.0
        geoms = np.concatenate([c.geom1[:n], c.geom2[:n]])
        wall = bool(np.isin(geoms, self.index.wall_geoms).any())
        return dist, wall

    def observe(self) -> np.ndarray:
        """The (1, 9) paper inputs now (touch: over the last control step)."""
        return self._observe(self.data.qpos[None], self._touch[None])

    def step(self, deltas: np.ndarray) -> np.ndarray:
        """One control step with target changes ``deltas`` (1, 4); the inputs
        after it. Sets :attr:`unstable` (the state is then meaningless)."""
        m, d = self.model, self.data
        d.ctrl[:] = actuation.apply_deltas(d.ctrl[None], deltas, self.index.ranges)[0]
        touch = self._touch
        touch[:] = -np.inf
        error = None
        dist, wall = np.inf, False
        try:
            for _ in range(self.params.substeps):
                mujoco.mj_step(m, d)
                np.maximum(touch, d.sensordata, out=touch)
                if self.contacts:
                    here, at_wall = self._contacts()
                    dist, wall = min(dist, here), wall or at_wall
        except mujoco.FatalError:
            error = np.array([0])
        if self.contacts:
            self.penetration, self.wall_contact = float(depth(dist)), float(wall)
        failed = went_unstable(d.qpos[None], d.warning.number[None], error)[0]
        self.unstable = self.unstable or bool(failed)
        return self.observe()


def reference_rollout(job: RolloutJob) -> RolloutResult:
    """The plain, obviously-correct loop: one ``MjData`` per episode.

    Slow; kept to test the engine against (same results, bit for bit).
    """
    ep = Episode(job.model_params, job.scene, contacts=records_contacts(job))
    ctl = job.controller
    parts = []
    for e in range(job.n_episodes):
        obs = ep.reset(job.starts, e)
        d = ep.data
        prepared = ctl.prepare(job.params[e : e + 1])
        memory = np.zeros((1, ctl.memory_size))
        rec = Recorder(
            job.record, 1, job.n_steps, record_shapes(ep.model.nq, ctl.memory_size)
        )
        rec.write(0, d.qpos[None], obs, d.ctrl[None], memory)
        rec.write_contacts(0, 0, ep.penetration, ep.wall_contact)
        steps = job.n_steps
        for t in range(job.n_steps):
            deltas, memory = ctl.act(prepared, memory, obs, d.ctrl[None], t)
            obs = ep.step(deltas)
            if ep.unstable:
                steps = t + 1
                rec.fill_from(t + 1)
                break
            rec.write(t + 1, d.qpos[None], obs, d.ctrl[None], memory)
            rec.write_contacts(t + 1, 0, ep.penetration, ep.wall_contact)
        parts.append(
            RolloutResult(rec.arrays, np.array([ep.unstable]), np.array([steps]), steps)
        )
    return RolloutResult.concat(parts)
