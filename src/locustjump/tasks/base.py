"""What a behaviour is: a task spec. Start states, an episode length, the
controller, a fitness (maximised), its metrics and the per-step reward of its
Gymnasium environment, so that no other module needs to know which behaviour
it runs. How a behaviour is shown (figures, rows of ``results.md``) is the
presentation layer's (:mod:`locustjump.present.stages`)."""

from __future__ import annotations

import copy
import dataclasses
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.controller import MLP, Controller
from locustjump.sim.engine.rollout import (
    DEFAULT_ENGINE,
    RolloutResult,
    StartStates,
    rollout,
)
from locustjump.sim.scene import Scene, Terrains
from locustjump.tasks.descriptors import Descriptor, describe
from locustjump.tasks.options import MAX_SCORE_SUBSTEPS as MAX_SCORE_SUBSTEPS
from locustjump.tasks.options import OPTION_HELP as OPTION_HELP
from locustjump.tasks.options import SCORE_SUBSTEPS as SCORE_SUBSTEPS
from locustjump.tasks.options import CommonOptions as CommonOptions
from locustjump.tasks.options import option as option
from locustjump.tasks.options import option_fields as option_fields
from locustjump.tasks.reference import RulesRun, run_rules

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


class StepReward:
    """Per-step rewards of one episode that add up to the behaviour's fitness.

    The default is sparse: 0 at every step and the episode's fitness
    (``episode_fitness`` of the recorded trajectory) at the last one; a
    behaviour overrides :meth:`Behaviour.reward` with a dense one.
    """

    def __init__(self, behaviour: Behaviour, p: lm.LocustParams):
        self.behaviour, self.p = behaviour, p
        self._rows: dict[str, list[np.ndarray]] = {}

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        """The start state's ``qpos (nq,)`` and inputs ``obs (9,)``."""
        self._rows = {"qpos": [qpos.copy()], "obs": [obs.copy()]}

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        """The reward of the control step that led to ``qpos``, ``obs``."""
        self._rows["qpos"].append(qpos.copy())
        self._rows["obs"].append(obs.copy())
        if len(self._rows["qpos"]) <= self.behaviour.n_steps:
            return 0.0
        res = RolloutResult(
            {k: np.array(v)[None] for k, v in self._rows.items()},
            np.zeros(1, bool),
            np.array([self.behaviour.n_steps]),
        )
        return float(self.behaviour.episode_fitness(res, self.p)[0])


class Behaviour:
    """One experiment: what a subclass sets and may override.

    Required: ``name``, ``n_steps``, ``record`` (what its fitness reads),
    :meth:`start_states`, :meth:`episode_fitness`, :meth:`metrics`. Fitness is
    maximised; an episode whose simulation went unstable gets
    ``worst_fitness``.

    Hooks, each with a default that fits a plain behaviour:

    ==========================  ================================================
    ``requires``                runs whose best genomes it builds on (frozen)
    ``controller``              the evolved network (default: the 9-10-4 MLP)
    ``memory_labels``           what memory[0] indexes (a video's caption)
    ``gym_id``, :meth:`reward`  its Gymnasium environment and per-step reward
    ``Options``                 its settings beyond the paper (a frozen
                                dataclass; ``[options]`` of ``config.toml``;
                                a field declared with :func:`option` is an
                                option of ``train``)
    :meth:`episode_terms`       the named terms its fitness adds up (default:
                                none)
    ``descriptors``,            its behaviour descriptors (quality diversity:
    :meth:`episode_descriptors` :mod:`.descriptors`) and their values per
                                episode; ``default_descriptors`` those a grid
                                archive is over unless a run names others
                                (default: none)
    ==========================  ================================================

    Its figures and rows of ``results.md``: a
    :class:`~locustjump.present.stages.Reporter` registered for it.
    """

    name: ClassVar[str]
    n_steps: ClassVar[int]
    #: control steps of the rule-based reference episode (:meth:`reference`;
    #: 0: none)
    reference_steps: ClassVar[int] = 0
    record: ClassVar[tuple[str, ...]] = ("qpos",)
    #: what ``evaluate_run`` records (its trajectory CSV needs the first three)
    eval_record: ClassVar[tuple[str, ...]] = ("qpos", "obs", "ctrl")
    worst_fitness: ClassVar[float] = 0.0
    requires: ClassVar[tuple[str, ...]] = ()
    #: (an instance may set its own: a repertoire's composition names its elites)
    memory_labels: tuple[str, ...] | None = None
    gym_id: ClassVar[str | None] = None
    Options: ClassVar[type] = CommonOptions
    descriptors: ClassVar[tuple[Descriptor, ...]] = ()
    default_descriptors: ClassVar[tuple[str, ...]] = ()

    def __init__(
        self,
        frozen: np.ndarray | None = None,
        options: Any = None,
        terrains: Terrains | None = None,
    ):
        """``frozen`` (k, P): genomes of the ``requires`` runs, if any;
        ``options``: an instance of ``Options`` (default: its defaults);
        ``terrains``: where it is scored (default: the flat floor)."""
        self.frozen = None if frozen is None else np.asarray(frozen, np.float64)
        self.terrains = Terrains() if terrains is None else terrains
        #: the scene its episodes run in: the first terrain (:meth:`on`)
        self.scene: Scene = self.terrains.scenes[0]
        self.options = self.Options() if options is None else options
        if not isinstance(self.options, self.Options):
            raise TypeError(
                f"{self.name} takes {self.Options.__name__} options, "
                f"got {type(self.options).__name__}"
            )

    def on(self, scene: Scene) -> Behaviour:
        """This behaviour with its episodes in ``scene`` (one terrain)."""
        other = copy.copy(self)
        other.scene, other.terrains = scene, Terrains(scene)
        return other

    @classmethod
    def frozen_elites(cls, options: Any = None) -> dict[str, int]:
        """The runs of ``requires`` that give the best elites of their archive
        (quality diversity) in place of their best genome, and how many, with
        ``options`` (default: none, each gives its best genome)."""
        return {}

    @classmethod
    def frozen_names(cls, options: Any = None) -> tuple[str, ...]:
        """The run each frozen genome comes from, in order: ``requires``, a run
        of :meth:`frozen_elites` once per elite it gives."""
        k = cls.frozen_elites(options)
        return tuple(n for r in cls.requires for n in [r] * k.get(r, 1))

    @classmethod
    def frozen_num_params(cls) -> int:
        """Genes of each frozen genome (the paper's 9-10-4 networks)."""
        return MLP().num_params

    @property
    def controller(self) -> Controller:
        """The evolved network (the paper's 9-10-4 MLP)."""
        return MLP()

    def start_states(self, p: lm.LocustParams) -> StartStates:
        raise NotImplementedError

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        """(n_episodes,) fitness of each episode of ``res``."""
        raise NotImplementedError

    def episode_terms(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        """Named ``(n_episodes,)`` terms that :meth:`episode_fitness` adds up,
        in the order added; empty (the default): no split."""
        return {}

    def episode_descriptors(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        """``(n_episodes,)`` values of each of :attr:`descriptors`, by name,
        from the records its fitness reads (default: none)."""
        return {}

    def reference(
        self,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
        engine: str = DEFAULT_ENGINE,
    ) -> RulesRun | None:
        """The rule-based episode its metrics and figures compare with
        (:attr:`reference_steps` long; simulated once per evaluation;
        ``None``: it compares with none)."""
        if not self.reference_steps:
            return None
        return run_rules(
            steps=self.reference_steps,
            model_params=p,
            backend=backend,
            engine=engine,
            scene=self.scene,
        )

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        reference: RulesRun | None = None,
    ) -> dict[str, Any]:
        """Behaviour metrics of one controller's episodes (JSON-serialisable);
        ``reference``: what :meth:`reference` simulated."""
        return {"fitness": float(self.fitness(res, p)[0])}

    def state_labels(self) -> list[str]:
        """A file-name-safe label per start state."""
        return ["start"]

    def reward(self, p: lm.LocustParams) -> StepReward:
        """Per-step rewards of the Gymnasium environment (sum = fitness)."""
        return StepReward(self, p)

    # -- shared machinery --

    def simulate(
        self,
        genomes: np.ndarray,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
        engine: str = DEFAULT_ENGINE,
        record: tuple[str, ...] | None = None,
        label: str = "",
    ) -> RolloutResult:
        """Every genome from every start state (controller-major episodes),
        unscored; ``label``: a progress bar on a terminal."""
        return rollout(
            self.controller,
            genomes,
            self.start_states(p),
            self.n_steps,
            model_params=p,
            record=self.record if record is None else record,
            backend=backend,
            label=label,
            engine=engine,
            scene=self.scene,
        )

    def fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        """(n_controllers,) fitness: the mean over each controller's start states."""
        f = np.where(res.unstable, self.worst_fitness, self.episode_fitness(res, p))
        k = len(self.start_states(p))
        mean: np.ndarray = f.reshape(-1, k).mean(axis=1)
        return mean

    def fitness_terms(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        """(n_controllers,) each of :meth:`episode_terms`, scored as
        :meth:`fitness` scores the episodes: an unstable episode's first term
        is ``worst_fitness``, its others 0; the mean over start states. They
        add up to :meth:`fitness` (exactly with one start state, else to
        rounding)."""
        k = len(self.start_states(p))
        out = {}
        for i, (name, v) in enumerate(self.episode_terms(res, p).items()):
            v = np.where(res.unstable, self.worst_fitness if i == 0 else 0.0, v)
            out[name] = v.reshape(-1, k).mean(axis=1)
        return out

    def describe(
        self, res: RolloutResult, p: lm.LocustParams, names: tuple[str, ...]
    ) -> np.ndarray:
        """``(n_controllers, len(names))`` the descriptors ``names`` of the
        controllers of ``res`` (what :meth:`evaluate` returned): an unstable
        episode at each descriptor's low bound, the mean over start states
        and terrains (:func:`~.descriptors.describe`)."""
        return describe(
            self.episode_descriptors(res, p) if self.descriptors else {},
            self.descriptors,
            names,
            res.unstable,
            len(self.start_states(p)),
            len(self.terrains.scenes),
        )

    def evaluate(
        self,
        genomes: np.ndarray,
        p: lm.LocustParams,
        *,
        backend: Backend | None = None,
        engine: str = DEFAULT_ENGINE,
        record: tuple[str, ...] | None = None,
        label: str = "",
    ) -> tuple[np.ndarray, RolloutResult]:
        """Simulate genomes (n, P) and score them: their fitness (n,) and the
        rollout it came from (``record``: its fields, default :attr:`record`).

        On each of :attr:`terrains` the fitness is :meth:`fitness` of the
        rollout; with the option ``score_substeps``, the minimum of it and of
        the fitness at each of those resolutions (simulated here too; their
        control steps are added to the rollout's ``control_steps``). The
        terrains' fitness is combined by ``terrains.aggregate``; the rollout is
        theirs concatenated, terrain-major."""
        fits, parts = [], []
        for scene in self.terrains.scenes:
            beh = self if scene == self.scene else self.on(scene)
            fit, res = beh._evaluate_here(genomes, p, backend, engine, record, label)
            fits.append(fit)
            parts.append(res)
        if len(parts) == 1:
            return fits[0], parts[0]
        return self.terrains.combine(np.stack(fits)), RolloutResult.concat(parts)

    def _evaluate_here(
        self,
        genomes: np.ndarray,
        p: lm.LocustParams,
        backend: Backend | None,
        engine: str,
        record: tuple[str, ...] | None,
        label: str,
    ) -> tuple[np.ndarray, RolloutResult]:
        """:meth:`evaluate` on this behaviour's scene alone."""
        res = self.simulate(
            genomes, p, backend=backend, engine=engine, record=record, label=label
        )
        fit = self.fitness(res, p)
        for substeps in self.options.score_substeps:
            q = dataclasses.replace(p, substeps=substeps)
            other = self.simulate(
                genomes, q, backend=backend, engine=engine, record=self.record
            )
            fit = np.minimum(fit, self.fitness(other, q))
            res.control_steps += other.control_steps
        return fit, res
