"""What an optimizer is: one small ask/tell object (the trainer's only view).

An optimizer proposes genomes (:meth:`Optimizer.ask`, an ``(n, P)`` array),
is told their fitness (:meth:`Optimizer.tell`, **maximised**, same order),
keeps the best genome it has seen, may say why it would stop
(:meth:`Optimizer.stop`), and saves and restores its whole state as plain
arrays (:meth:`Optimizer.state` / :meth:`Optimizer.load_state`) that go into
the run's ``checkpoint.npz``, never a pickle.

Its settings are a frozen dataclass with a ``kind`` (its name in
``config.toml``'s ``[optimizer]`` table and on ``--optimizer``) and a
``population``; every random choice comes from the run's seed, so the same
seed gives the same genomes bit for bit.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class OptimizerParams(Protocol):
    """Settings of an optimizer: a frozen dataclass (fields are the TOML keys)."""

    kind: ClassVar[str]
    population: int

    def replace(self, **changes: Any) -> OptimizerParams: ...


@runtime_checkable
class Optimizer(Protocol):
    """The ask/tell protocol the trainer drives.

    Constructed as ``cls(num_params, params, seed)``. Attributes after each
    :meth:`tell`: ``generation`` (completed tells), ``fitness`` (the current
    population's fitness, what ``metrics.csv`` summarises), ``best`` and
    ``best_fitness`` (the best genome told so far).
    """

    Params: ClassVar[type]
    generation: int
    fitness: np.ndarray

    def ask(self) -> np.ndarray: ...

    def tell(self, fitness: np.ndarray) -> None: ...

    @property
    def best(self) -> np.ndarray: ...

    @property
    def best_fitness(self) -> float: ...

    def stop(self) -> str | None: ...

    def state(self) -> dict[str, np.ndarray]: ...

    def load_state(self, state: Mapping[str, np.ndarray]) -> None: ...


def check_fitness(fitness: np.ndarray, n: int) -> np.ndarray:
    """``fitness`` as a float64 (n,) array; ``ValueError`` if it is not one."""
    f = np.asarray(fitness, dtype=np.float64).reshape(-1)
    if f.shape[0] != n:
        raise ValueError(f"got {f.shape[0]} fitness values for {n} genomes")
    if np.isnan(f).any():
        raise ValueError("fitness contains NaN")
    return f


def rng_state(rng: np.random.Generator) -> np.ndarray:
    """A generator's state as a 0-d string array (JSON), for an ``.npz``."""

    return np.array(json.dumps(rng.bit_generator.state))


def rng_from_state(text: Any) -> np.random.Generator:
    """Inverse of :func:`rng_state`."""

    s = json.loads(str(text))
    bg = getattr(np.random, s["bit_generator"])()
    bg.state = s
    return np.random.Generator(bg)


class BestSoFar:
    """Bookkeeping shared by optimizers that sample a fresh population each
    generation: the pending ``ask``, the best genome told so far, the counters.
    A subclass makes genomes in :meth:`_sample` and may act on a tell in
    :meth:`_learn`."""

    def _reset(self, num_params: int) -> None:
        self.generation = 0
        self.fitness = np.empty(0)
        self._best = np.zeros(num_params)
        self._best_fitness = -np.inf
        self._asked: np.ndarray | None = None

    def _sample(self) -> np.ndarray:
        raise NotImplementedError

    def _learn(self, x: np.ndarray, f: np.ndarray) -> None:
        """What the optimizer does with a told generation (default: nothing)."""

    def ask(self) -> np.ndarray:
        """Genomes to evaluate next, (n, num_params)."""
        if self._asked is None:
            self._asked = self._sample()
        return self._asked.copy()

    def tell(self, fitness: np.ndarray) -> None:
        """Fitness (n,) of the genomes of the last :meth:`ask`, same order."""
        if self._asked is None:
            raise RuntimeError("tell() without a pending ask()")
        f = check_fitness(fitness, self._asked.shape[0])
        self._learn(self._asked, f)
        i = int(np.argmax(f))
        if f[i] > self._best_fitness:
            self._best, self._best_fitness = self._asked[i].copy(), float(f[i])
        self.fitness, self._asked = f, None
        self.generation += 1

    @property
    def best(self) -> np.ndarray:
        return self._best.copy()

    @property
    def best_fitness(self) -> float:
        return self._best_fitness

    def _check_between_generations(self) -> None:
        if self._asked is not None:
            raise RuntimeError("checkpoint between generations (after tell())")
