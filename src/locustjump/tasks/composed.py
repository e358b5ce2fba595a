"""Behaviour Composed: successive jumping by switching the three frozen simple
behaviours (paper §4, Fig. 11–12).

* controller: a 9-10-3 *switcher* network (sigmoid outputs in [0, 1]); every
  ``SWITCH_EVERY`` = 120 control steps (1 s) the simple behaviour with the
  largest output takes control until the next switch. The three simple 9-10-4
  networks (kick, getup, return-legs, in that output order) are frozen; servo
  targets carry over across switches (each network changes the targets it
  finds);
* start: lying on its side, the get-up start state rolled 90 deg (Fig. 11),
  settled on the flat floor; on a terrain the same state, at rest in the
  clearing kept free around the start, touching no rubble
  (``tests/test_debris.py``), so every terrain starts alike;
* episode: 3000 control steps (25 s);
* fitness (Eq. 4): ``E = sum_{t=1..3000} z_t``, the body centre's height above
  the floor in metres, summed over control steps (unit: m x steps; divide by
  3000 for the mean height). On the flat floor that is all: the paper's.
* fitness on a terrain (``debris``), successive jumping *across* it:
  ``E = sum_{t=1..3000} (z_t - h(x_t, y_t)) + W (x_3000 - x_0)``. The first
  term is Eq. 4 above the ground under the body centre (``h``: the top of the
  rubble there, 0 between boxes): perching on a box earns nothing over lying
  on the floor, only time in the air (successive jumps, and getting up to
  jump again) does. The second rewards forward progress, in metres (negative
  backwards), with ``W = PROGRESS_WEIGHT`` = 200 control steps: travelling as
  far as the rule-based jumper does on the flat floor (9 m in 25 s) earns
  about as much as its height does there (Eq. 4: 1888). Without it, evolution
  found hopping in place in the clearing around the start, away from the
  rubble (docs/science.md).

:mod:`.monolithic` adds the baseline beyond the paper on the same episode
and fitness (``Successive``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from locustjump.ranges import Range, check_settings
from locustjump.sim import model as lm
from locustjump.sim.analysis import clearance, find_jumps
from locustjump.sim.controller import MLP, Controller, KernelSpec, MLPWeights
from locustjump.sim.engine.job import RolloutResult, StartStates
from locustjump.sim.kernels import soa
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.base import Behaviour, CommonOptions, StepReward, option
from locustjump.tasks.getup import SUCCESS_UZ, rolled_starts
from locustjump.tasks.reference import RulesRun

#: The simple behaviours, in the order of the switcher's outputs.
SIMPLE = ("kick", "getup", "return-legs")
#: Control steps between two decisions of the switcher (paper: 120).
SWITCH_EVERY = 120
#: Fig. 11: the start lies on its side (get-up start state rolled 90 deg).
START_ROLL = 90.0
#: U_z below this counts as overturned (on its side or back).
OVERTURNED_UZ = 0.0
#: (Control steps) weight of forward progress (m) in the fitness on a terrain.
PROGRESS_WEIGHT = 200.0


def successive_fitness(
    qpos: np.ndarray, p: lm.LocustParams, scene: Scene = Flat()
) -> np.ndarray:
    """The fitness of successive-jumping trajectories ``qpos (..., T + 1, nq)``
    (the start, then every control step) in ``scene``: Eq. 4 on the flat floor;
    on a terrain, Eq. 4 above the ground under the body plus
    ``PROGRESS_WEIGHT`` times the forward progress (module docstring)."""
    height, distance = successive_terms(qpos, p, scene)
    if scene.is_flat:
        return height
    fitness: np.ndarray = height + distance
    return fitness


def successive_terms(
    qpos: np.ndarray, p: lm.LocustParams, scene: Scene = Flat()
) -> tuple[np.ndarray, np.ndarray]:
    """The two terms of :func:`successive_fitness` of trajectories ``qpos
    (..., T + 1, nq)``, which it adds: Eq. 4's sum of the body centre's height
    above the ground under it (m x steps), and ``PROGRESS_WEIGHT`` times the
    forward progress (m x steps; 0 on the flat floor, where the fitness is
    Eq. 4 alone)."""
    height = clearance(qpos, p, scene)[..., 1:].sum(axis=-1)
    if scene.is_flat:
        return height, np.zeros_like(height)
    return height, PROGRESS_WEIGHT * (qpos[..., -1, 0] - qpos[..., 0, 0])


@dataclass(frozen=True)
class SwitchOptions(CommonOptions):
    """The composed behaviour's settings beyond the paper (``[options]``)."""

    #: control steps between two decisions of the switcher (paper: 120); at
    #: most one episode's
    switch_every: int = option(
        SWITCH_EVERY,
        "control steps between two decisions of the switcher (default "
        f"{SWITCH_EVERY}, the paper's; beyond the paper, recorded in config.toml)",
        "STEPS",
        Range(1, 3000, integer=True, unit="control steps"),
    )

    def __post_init__(self) -> None:
        super().__post_init__()
        check_settings(self)


@dataclass(frozen=True, eq=False)
class SwitchingController:
    """The switcher over frozen simple networks, batched over episodes.

    ``params`` (n, 133) are switcher genomes; ``simple`` (3, 144) the frozen
    networks' genomes in :data:`SIMPLE` order. Memory per episode: the index of
    the selected simple behaviour (recorded as the behaviour timeline).
    ``networks``: how many frozen networks it switches among, its output
    layer's size (3; a repertoire's composition, :mod:`.repertoire`, more).
    """

    simple: np.ndarray
    every: int = SWITCH_EVERY
    network: MLP = MLP()
    networks: int = len(SIMPLE)

    @property
    def switcher(self) -> MLP:
        """The switcher network: one sigmoid output per frozen network."""
        return MLP(n_out=self.networks, output="sigmoid")

    def __post_init__(self) -> None:
        shape = (self.networks, self.network.num_params)
        if np.shape(self.simple) != shape:
            raise ValueError(
                f"simple genomes have shape {np.shape(self.simple)}, expected {shape}"
            )
        if self.every < 1:
            raise ValueError(f"every must be >= 1, got {self.every}")

    @property
    def num_params(self) -> int:
        return self.switcher.num_params

    @property
    def memory_size(self) -> int:
        return 1

    def prepare(self, params: np.ndarray) -> tuple[MLPWeights, MLPWeights]:
        return self.switcher.prepare(params), self.network.prepare(self.simple)

    def kernel(self, prepared: tuple[MLPWeights, MLPWeights]) -> KernelSpec:
        """The compiled path's form of ``act`` (:func:`~.kernels.switch`):
        the switcher's and the simple networks' weights episode-last."""
        switcher, simple = prepared
        n = switcher.w1.shape[0]
        # (3, ..., n): every episode holds each simple network
        nets = tuple(
            np.ascontiguousarray(np.broadcast_to(w[..., None], (*w.shape, n)))
            for w in simple
        )
        return ("switch", tuple(soa(w) for w in switcher), nets, self.every)

    def select(self, switcher: MLPWeights, obs: np.ndarray) -> np.ndarray:
        """(n,) index of the simple behaviour with the largest switcher output."""
        index: np.ndarray = np.argmax(self.switcher.apply(switcher, obs), axis=1)
        return index

    def act(
        self,
        prepared: tuple[MLPWeights, MLPWeights],
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        switcher, simple = prepared
        if step % self.every == 0:
            memory = self.select(switcher, obs).astype(np.float64)[:, None]
        chosen = memory[:, 0].astype(np.intp)
        # each row runs its selected network: the same per-row arithmetic as the
        # simple behaviour's own rollout
        weights = MLPWeights(*(w[chosen] for w in simple))
        return self.network.apply(weights, obs), memory


def overturns(uz: np.ndarray) -> tuple[int, int]:
    """(times overturned, times recovered) of one episode's U_z (T,).

    Overturned: U_z drops below ``OVERTURNED_UZ`` after having been upright
    (U_z >= ``SUCCESS_UZ``); recovered: upright again after that.
    """
    over = rec = 0
    upright = bool(uz[0] >= SUCCESS_UZ)
    for u in uz[1:]:
        if upright and u < OVERTURNED_UZ:
            upright, over = False, over + 1
        elif not upright and u >= SUCCESS_UZ:
            upright = True
            rec += 1 if over else 0
    return over, rec


class HeightReward(StepReward):
    """Dense :func:`successive_fitness`: ``z_t`` (m) on the flat floor (Eq. 4);
    on a terrain ``z_t - h(x_t, y_t) + PROGRESS_WEIGHT (x_t - x_{t-1})``,
    whose sum over the episode is the fitness there."""

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        self._x = float(qpos[0])

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        scene = self.behaviour.scene
        if scene.is_flat:
            return float(qpos[2])
        x, self._x = self._x, float(qpos[0])
        height = float(clearance(qpos[None], self.p, scene)[0])
        return height + PROGRESS_WEIGHT * (self._x - x)


class Successive(Behaviour):
    """Shared by the composed and the monolithic behaviour: start, episode,
    fitness and metrics."""

    n_steps = 3000
    reference_steps = n_steps
    record = ("qpos",)
    worst_fitness = 0.0
    eval_record: ClassVar[tuple[str, ...]] = ("qpos", "obs", "ctrl", "memory")

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return rolled_starts(p, (START_ROLL,))  # on any terrain: module docstring

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return successive_fitness(res["qpos"], p, self.scene)

    def episode_terms(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        """``height`` (Eq. 4 above the ground) and ``distance`` (200 x forward
        progress): :func:`successive_terms`."""
        height, distance = successive_terms(res["qpos"], p, self.scene)
        return {"height": height, "distance": distance}

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        reference: RulesRun | None = None,
    ) -> dict[str, Any]:
        """Jumps and their apexes, distance, overturns, and each jump's apex
        over the rule-based jumps' mean apex (paper: > 2x at every jump;
        ``reference``: :meth:`reference`, simulated here if not given; no
        ``rules_*`` keys for a behaviour that compares with none)."""
        qpos, uz = res["qpos"][0], res["obs"][0, :, 8]
        height = clearance(qpos, p, self.scene)
        jumps = find_jumps(qpos, p, self.scene)
        rules = self.reference(p) if reference is None else reference
        rule_apex = [] if rules is None else [j.apex_height for j in rules.jumps]
        over, rec = overturns(uz)
        out: dict[str, Any] = {
            "fitness": float(self.fitness(res, p)[0]),
            "mean_height_m": float(height[1:].mean()),
            "jumps": len(jumps),
            "apex_heights_m": [round(j.apex_height, 4) for j in jumps],
            "distance_m": float(qpos[-1, 0] - qpos[0, 0]),
            "overturned": over,
            "recovered": rec,
            "final_up_z": float(uz[-1]),
        }
        if rules is not None:  # reference_steps = 0: compares with none
            out["rules_jumps"] = len(rule_apex)
            out["rules_mean_apex_height_m"] = (
                float(np.mean(rule_apex)) if rule_apex else None
            )
            out["rules_fitness"] = float(successive_fitness(rules.qpos, p, self.scene))
        out["unstable"] = bool(res.unstable[0])
        if rule_apex:
            ratios = [j.apex_height / float(np.mean(rule_apex)) for j in jumps]
            out["apex_ratios_to_rules"] = [round(r, 3) for r in ratios]
            out["min_apex_ratio_to_rules"] = min(ratios) if ratios else None
        if "memory" in res.records:
            sel = res["memory"][0, 1:, 0].astype(int)
            labels = self.memory_labels or SIMPLE
            out["selected_steps"] = {
                name: int((sel == i).sum()) for i, name in enumerate(labels)
            }
        return out

    def reward(self, p: lm.LocustParams) -> StepReward:
        return HeightReward(self, p)


class Composed(Successive):
    """The paper's Behaviour Composed; builds on the three simple runs."""

    name = "composed"
    requires = SIMPLE
    memory_labels: tuple[str, ...] | None = SIMPLE
    Options = SwitchOptions

    @property
    def controller(self) -> Controller:
        if self.frozen is None:
            raise ValueError(
                "the composed behaviour needs the three simple behaviours' genomes "
                "(kick, getup, return-legs)"
            )
        return SwitchingController(self.frozen, every=self.options.switch_every)


__all__ = [
    "SIMPLE",
    "Successive",
    "SWITCH_EVERY",
    "Composed",
    "SwitchingController",
    "overturns",
    "successive_fitness",
    "successive_terms",
    "PROGRESS_WEIGHT",
]
