"""The optimizer base class: the ask/tell bookkeeping every optimizer shares.

The shape of evosax's ``algorithms/base.py``: :class:`Optimizer` owns what is
the same for every optimizer — the generation counter, the genomes asked and
awaiting their fitness, the best genome and fitness told so far, the
population's fitness (what ``metrics.csv`` summarises), the checkpoint
state's frame and the run's random generator — and an optimizer writes only
what differs:

==================  ====================================================
``_ask()``          the next genomes, an ``(n, P)`` array
``_tell(x, f)``     learn from genomes ``x`` and their fitness ``f``
                    (maximised); may return the population's fitness
                    when it holds more than ``x`` (the RCGA's elites)
``_state()``        its own state as plain arrays (``checkpoint.npz``)
``_set_state(s)``   the inverse of ``_state``
``_stop()``         optional: why it would stop, ``{reason: value}``
``diagnostics()``   optional: extra ``metrics.csv`` columns, ``{name: value}``
==================  ====================================================

An optimizer that needs the genomes' behaviour descriptors too (quality
diversity, :mod:`.qd`) names them in ``descriptor_names`` and writes
``_tell_described(x, f, d)`` in place of ``_tell``; :meth:`Optimizer.tell`
then takes ``descriptors=`` ``(n, len(descriptor_names))``. The others are
told fitness alone, as before.

A ``_set_state`` whose state holds the best genome so far restores it with
``_set_best``; the base keeps it up to date on every :meth:`Optimizer.tell`.

Its settings are a frozen dataclass (``Params``) with a ``kind`` (its name in
``config.toml``'s ``[optimizer]`` table and on ``--optimizer``) and a
``population``. Every optimizer is constructed as ``cls(num_params, params,
seed)``; every random choice comes from ``self.rng``, seeded from ``seed``,
so the same seed gives the same genomes bit for bit. The state is plain
arrays, never a pickle.
"""

from __future__ import annotations

import json
import math
import numbers
from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from locustjump.ranges import Range

#: Most genomes a generation may hold: a bound on the setting itself (the paper
#: has 50); whether a population fits this machine's memory is checked before
#: training (:func:`locustjump.sim.resources.require_memory`).
MAX_POPULATION = 1_000_000
#: ``population``, every optimizer's: genomes per generation
POPULATION = Range(2, MAX_POPULATION, integer=True)
#: Bound on every gene-scale setting (an initial spread, a mutation's sigma):
#: a tanh network saturates long before.
MAX_GENE_SCALE = 1.0e6
#: the seed of an optimizer (and of a run)
SEED = Range(0, 2**63 - 1, integer=True)


@runtime_checkable
class OptimizerParams(Protocol):
    """Settings of an optimizer: a frozen dataclass (fields are the TOML keys),
    made from its settings by name (``population`` among them)."""

    kind: ClassVar[str]

    def __init__(self, *, population: int = ..., **settings: Any) -> None: ...

    @property
    def population(self) -> int: ...

    def replace(self, **changes: Any) -> OptimizerParams: ...


def check_fitness(fitness: np.ndarray, n: int) -> np.ndarray:
    """``fitness`` as a float64 (n,) array; ``ValueError`` if it is not one."""
    f = np.asarray(fitness, dtype=np.float64).reshape(-1)
    if f.shape[0] != n:
        raise ValueError(f"got {f.shape[0]} fitness values for {n} genomes")
    if np.isnan(f).any():
        raise ValueError("fitness contains NaN")
    return f


def check_descriptors(descriptors: np.ndarray, n: int, d: int) -> np.ndarray:
    """``descriptors`` as a finite float64 ``(n, d)`` array; ``ValueError`` if
    it is not one."""
    m = np.asarray(descriptors, dtype=np.float64)
    if m.shape != (n, d):
        raise ValueError(f"got descriptors of shape {m.shape}, expected {(n, d)}")
    if not np.isfinite(m).all():
        raise ValueError("descriptors are not finite")
    return m


def rng_state(rng: np.random.Generator) -> np.ndarray:
    """A generator's state as a 0-d string array (JSON), for an ``.npz``."""

    return np.array(json.dumps(rng.bit_generator.state))


def rng_from_state(text: Any) -> np.random.Generator:
    """Inverse of :func:`rng_state`."""

    s = json.loads(str(text))
    kind = getattr(np.random, str(s["bit_generator"]), None)
    if not (isinstance(kind, type) and issubclass(kind, np.random.BitGenerator)):
        raise ValueError(f"unknown bit generator {s['bit_generator']!r}")
    bg = kind()
    bg.state = s
    return np.random.Generator(bg)


def _plain(value: Any) -> bool | int | float | str:
    """A stop reason's value as a JSON scalar (pycma gives NumPy numbers)."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real) and math.isfinite(value):
        return float(value)
    return str(value)


class Optimizer(ABC):
    """An ask/tell optimizer; fitness is **maximised**.

    Constructed as ``cls(num_params, params, seed)``. The trainer calls
    :meth:`ask` for genomes, evaluates them, and :meth:`tell` s their fitness
    in the same order; :meth:`ask` again before :meth:`tell` returns the same
    genomes, :meth:`tell` without a pending :meth:`ask` is a ``RuntimeError``.

    Attributes after each :meth:`tell`: ``generation`` (completed tells),
    ``fitness`` (the current population's, what ``metrics.csv`` summarises),
    :attr:`best` and :attr:`best_fitness` (the best genome told so far).

    Args:
      num_params: genes per genome (``P``).
      params: the settings, an instance of ``cls.Params``.
      seed: the run's seed; ``self.rng`` is ``numpy.random.default_rng(seed)``.
    """

    Params: ClassVar[type[OptimizerParams]]
    num_params: int
    params: Any  # a Params; each optimizer names its own
    seed: int

    def __init__(self, num_params: int, params: Any, seed: int = 0) -> None:
        self.num_params = Range(1, None, integer=True).check("num_params", num_params)
        self.params = params
        self.seed = SEED.check("seed", seed)
        self._restart()

    def _restart(self) -> None:
        """Generation 0: nothing told, ``self.rng`` fresh from the seed."""
        self.rng = np.random.default_rng(self.seed)
        self.generation = 0
        self.fitness = np.empty(0)
        self._best = np.zeros(self.num_params)
        self._best_fitness = -np.inf
        self._asked: np.ndarray | None = None

    # -- what an optimizer writes ----------------------------------------------

    @abstractmethod
    def _ask(self) -> np.ndarray:
        """The next genomes to evaluate, ``(n, num_params)``."""

    @abstractmethod
    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> np.ndarray | None:
        """Learn from ``genomes`` (the last ``_ask()``) and their ``fitness``
        (checked: float64, no NaN). Returns the population's fitness if it
        holds more than ``genomes`` (elites kept with their fitness), else
        ``None`` (the population is what was told)."""

    @abstractmethod
    def _state(self) -> dict[str, np.ndarray]:
        """Arrays that, with ``generation``, restore the optimizer exactly."""

    @abstractmethod
    def _set_state(self, state: Mapping[str, np.ndarray]) -> None:
        """Inverse of :meth:`_state` (``ValueError`` on inconsistent data);
        ``self.generation`` is already ``state["generation"]``."""

    @property
    def descriptor_names(self) -> tuple[str, ...]:
        """The behaviour descriptors each :meth:`tell` needs, by name (the
        task computes them); empty, the default: none."""
        return ()

    def _tell_described(
        self, genomes: np.ndarray, fitness: np.ndarray, descriptors: np.ndarray
    ) -> np.ndarray | None:
        """:meth:`_tell` with the genomes' ``descriptors`` (checked: float64
        ``(n, len(descriptor_names))``, finite), for an optimizer that names
        some in :attr:`descriptor_names`."""
        raise NotImplementedError(f"{type(self).__name__} takes no descriptors")

    def _stop(self) -> Mapping[str, Any]:
        """Why the optimizer would stop before the budget: reason -> value
        (default: never)."""
        return {}

    def diagnostics(self) -> dict[str, float]:
        """Numbers that show the optimizer's own state, one ``metrics.csv``
        column each (e.g. CMA-ES's step size). The same names from
        construction on, values of the last :meth:`tell`; default: none."""
        return {}

    # -- the bookkeeping -------------------------------------------------------

    def ask(self) -> np.ndarray:
        """Genomes to evaluate next, ``(n, num_params)``; the same ones until
        :meth:`tell`."""
        if self._asked is None:
            x = np.asarray(self._ask(), dtype=np.float64)
            if x.ndim != 2 or x.shape[0] < 1 or x.shape[1] != self.num_params:
                raise ValueError(
                    f"{type(self).__name__}._ask() gave shape {x.shape}, "
                    f"expected (n, {self.num_params})"
                )
            self._asked = x
        return self._asked.copy()

    def tell(self, fitness: np.ndarray, descriptors: np.ndarray | None = None) -> None:
        """Fitness ``(n,)`` of the genomes of the last :meth:`ask`, same order;
        ``descriptors`` ``(n, d)`` their behaviour descriptors, for an
        optimizer that names ``d`` in :attr:`descriptor_names` (and only then)."""
        if self._asked is None:
            raise RuntimeError(
                f"tell() without a pending ask() (generation {self.generation} "
                "is told; each ask() is told once)"
            )
        x = self._asked
        f = check_fitness(fitness, x.shape[0])
        names = self.descriptor_names
        if names:
            if descriptors is None:
                raise ValueError(
                    f"{type(self).__name__} needs the descriptors "
                    f"{', '.join(names)} with the fitness"
                )
            m = check_descriptors(descriptors, x.shape[0], len(names))
            population = self._tell_described(x, f, m)
        elif descriptors is not None:
            raise ValueError(f"{type(self).__name__} takes no descriptors")
        else:
            population = self._tell(x, f)
        i = int(np.argmax(f))
        if self.generation == 0 or f[i] > self._best_fitness:
            self._set_best(x[i], f[i])
        self.fitness = f if population is None else population
        self._asked = None
        self.generation += 1

    @property
    def best(self) -> np.ndarray:
        """The best genome told so far, ``(num_params,)``."""
        return self._best.copy()

    @property
    def best_fitness(self) -> float:
        """Its fitness (``-inf`` before the first :meth:`tell`)."""
        return self._best_fitness

    def _set_best(self, genome: np.ndarray, fitness: float) -> None:
        """Restore the best genome so far (from a state that holds it)."""
        self._best = np.array(genome, dtype=np.float64)
        self._best_fitness = float(fitness)
        if self._best.shape != (self.num_params,):
            raise ValueError(f"best genome has shape {self._best.shape}")
        if not np.isfinite(self._best).all() or np.isnan(self._best_fitness):
            raise ValueError("best genome or its fitness is not finite")

    def stop(self) -> dict[str, bool | int | float | str]:
        """Why the optimizer stops before the budget, as pycma's ``stop()``:
        ``{reason: value}`` with JSON values, empty while it goes on."""
        return {str(k): _plain(v) for k, v in self._stop().items()}

    def state(self) -> dict[str, np.ndarray]:
        """Arrays that restore this optimizer exactly (``checkpoint.npz``),
        between generations only (``RuntimeError`` with a pending ask)."""
        if self._asked is not None:
            raise RuntimeError("checkpoint between generations (after tell())")
        return {"generation": np.array(self.generation), **self._state()}

    def load_state(self, state: Mapping[str, np.ndarray]) -> None:
        """Inverse of :meth:`state` (``ValueError`` or ``KeyError`` on bad data)."""
        self._asked = None
        self.generation = int(state["generation"])
        self._set_state(state)

    @classmethod
    def from_state(
        cls,
        num_params: int,
        params: Any,
        state: Mapping[str, np.ndarray],
        seed: int = 0,
    ) -> Optimizer:
        """An optimizer restored from :meth:`state`."""
        opt = cls(num_params, params, seed)
        opt.load_state(state)
        return opt
