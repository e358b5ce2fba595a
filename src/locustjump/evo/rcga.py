"""A real-coded genetic algorithm (RCGA) with an ask/tell interface (paper §3).

The paper names elitism, crossover and mutation but not the operators; our
defaults (SPEC "RCGA") and why:

* **elitism**: the ``elite`` best individuals survive unchanged *with their
  fitness* (the simulation is deterministic, so they are never re-simulated:
  :meth:`RCGA.ask` returns only the new children);
* **selection**: tournaments of ``tournament_size`` = 3 drawn with
  replacement; rank-based, so the scale of the fitness does not matter;
* **crossover**: BLX-alpha (Eshelman & Schaffer 1993), alpha = 0.5: each gene
  of the child is uniform on the parents' interval widened by alpha times its
  width on each side. Child mean = parents' mean, child variance =
  ``(1 + 2 alpha)^2 d^2 / 12`` for parent distance ``d``. Alternatives: SBX
  (Deb & Agrawal 1995, distribution index ``sbx_eta``) and UNDX (Ono &
  Kobayashi 1997, ``undx_sigma_xi``, ``undx_sigma_eta``);
* **mutation**: each gene of a child is perturbed, with probability
  ``mutation_rate``, by Gaussian noise of standard deviation ``mutation_sigma``.

Fitness is maximised. All randomness comes from one ``numpy.random.Generator``
seeded from the run's seed, so a run is reproduced exactly from its seed and can
be checkpointed (:meth:`RCGA.state` / :meth:`RCGA.from_state`). The ask/tell
bookkeeping is :class:`~locustjump.evo.base.Optimizer`'s.

Example::

    ga = RCGA(num_params=10, params=RCGAParams(population=50), seed=0)
    for _ in range(200):
        x = ga.ask()
        ga.tell(-np.sum(x**2, axis=1))
    print(ga.best_fitness)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray

from locustjump.evo.base import (
    MAX_GENE_SCALE,
    MAX_POPULATION,
    POPULATION,
    Optimizer,
    rng_from_state,
    rng_state,
)
from locustjump.ranges import Range, SettingValueError, check_settings, setting

Crossover = Literal["blx", "sbx", "undx"]
CROSSOVERS: tuple[Crossover, ...] = ("blx", "sbx", "undx")
F64 = NDArray[np.float64]

#: a probability
_RATE = Range(0.0, 1.0)
#: a gene-scale setting (alpha, eta, sigma, the initial spread)
_GENE_SCALE = Range(0.0, MAX_GENE_SCALE)


@dataclass(frozen=True)
class RCGAParams:
    """Settings of the RCGA; the defaults are the project's (module docstring).
    Each numeric field's range is declared beside it (:mod:`locustjump.ranges`)."""

    kind: ClassVar[str] = "rcga"
    #: individuals per generation (paper: 50)
    population: int = setting(50, POPULATION)
    #: best individuals copied unchanged into the next generation (< population)
    elite: int = setting(2, Range(0, MAX_POPULATION - 1, integer=True))
    #: entrants of a selection tournament (drawn with replacement)
    tournament_size: int = setting(3, Range(1, MAX_POPULATION, integer=True))
    crossover: Crossover = "blx"
    #: else the child is a copy of its first parent
    crossover_rate: float = setting(1.0, _RATE)
    blx_alpha: float = setting(0.5, _GENE_SCALE)
    #: small eta: children spread far from the parents
    sbx_eta: float = setting(2.0, _GENE_SCALE)
    undx_sigma_xi: float = setting(0.5, _GENE_SCALE)
    #: divided by sqrt(num_params) (Ono & Kobayashi)
    undx_sigma_eta: float = setting(0.35, _GENE_SCALE)
    mutation_rate: float = setting(0.1, _RATE)  # per gene
    mutation_sigma: float = setting(0.1, _GENE_SCALE)
    #: initial genes uniform in [-init_scale, init_scale]
    init_scale: float = setting(1.0, _GENE_SCALE)

    def __post_init__(self) -> None:
        check_settings(self)
        if self.elite >= self.population:
            raise SettingValueError(
                "elite", f"less than population ({self.population})", self.elite
            )
        if self.crossover not in CROSSOVERS:
            raise SettingValueError(
                "crossover", f"one of {', '.join(CROSSOVERS)}", self.crossover
            )

    def replace(self, **changes: Any) -> RCGAParams:
        return dataclasses.replace(self, **changes)


# --- operators: pure functions of (parents, rng) ------------------------------


def blx_alpha(a: F64, b: F64, alpha: float, rng: np.random.Generator) -> F64:
    """One BLX-alpha child per row of parents ``a``, ``b`` (n, P)."""
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    d = hi - lo
    return rng.uniform(lo - alpha * d, hi + alpha * d)


def sbx(a: F64, b: F64, eta: float, rng: np.random.Generator) -> F64:
    """One simulated-binary-crossover child per row (unbounded SBX).

    The spread factor beta has density ~ beta^eta below 1 and beta^-(eta+2)
    above; each gene takes either of the two symmetric children at random, so
    the child mean is the parents' mean.
    """
    u = rng.random(a.shape)
    beta = np.where(
        u <= 0.5,
        (2.0 * u) ** (1.0 / (eta + 1.0)),
        (1.0 / (2.0 * (1.0 - u))) ** (1.0 / (eta + 1.0)),
    )
    sign = np.where(rng.random(a.shape) < 0.5, 1.0, -1.0)
    return 0.5 * (a + b) + sign * 0.5 * beta * (b - a)


def undx(
    a: F64,
    b: F64,
    c: F64,
    sigma_xi: float,
    sigma_eta: float,
    rng: np.random.Generator,
) -> F64:
    """Unimodal normal distribution crossover, one child per row.

    ``child = m + xi * (b - a) + eta``: ``m`` the midpoint of ``a`` and ``b``,
    ``xi ~ N(0, sigma_xi^2)`` along the primary axis, ``eta`` normal with
    standard deviation ``sigma_eta / sqrt(P) * D`` in the subspace orthogonal to
    it, ``D`` the distance of the third parent ``c`` from the line ``a``–``b``.
    """
    n, P = a.shape
    m = 0.5 * (a + b)
    d = b - a
    dn2 = np.einsum("ij,ij->i", d, d)
    safe = np.where(dn2 > 0, dn2, 1.0)
    rel = c - a
    along = (np.einsum("ij,ij->i", rel, d) / safe)[:, None] * d
    D = np.linalg.norm(rel - along, axis=1)
    xi = rng.normal(0.0, sigma_xi, size=(n, 1))
    eta = rng.normal(0.0, 1.0, size=(n, P)) * (sigma_eta / np.sqrt(P) * D)[:, None]
    eta -= (np.einsum("ij,ij->i", eta, d) / safe)[:, None] * d
    child: F64 = m + xi * d + eta
    return child


def gaussian_mutation(
    x: F64, rate: float, sigma: float, rng: np.random.Generator
) -> F64:
    """Each gene perturbed with probability ``rate`` by ``N(0, sigma^2)``."""
    mask = rng.random(x.shape) < rate
    mutated: F64 = x + mask * rng.normal(0.0, sigma, size=x.shape)
    return mutated


def tournament(
    fitness: F64, n: int, k: int, rng: np.random.Generator
) -> NDArray[np.int64]:
    """Indices of the winners of ``n`` size-``k`` tournaments, entrants drawn
    with replacement; a tie goes to the first entrant drawn."""
    entrants = rng.integers(0, fitness.shape[0], size=(n, k))
    winner = np.argmax(fitness[entrants], axis=1)
    winners: NDArray[np.int64] = entrants[np.arange(n), winner]
    return winners


# --- the algorithm ------------------------------------------------------------


class RCGA(Optimizer):
    """Ask/tell real-coded GA. Maximises.

    ``ask()`` returns the genomes to evaluate: the whole initial population in
    the first generation, afterwards only the ``population - elite`` new
    children (the elites keep their fitness). ``tell(fitness)`` takes their
    fitness, in the same order. ``population`` and ``fitness`` are then the
    whole population, sorted best first.

    Args:
      num_params: genes per genome.
      params: the settings.
      seed: the seed of ``self.rng``, which makes every random choice.
      init: optional (population, num_params) initial population; default
        uniform in ``[-init_scale, init_scale]``.
    """

    Params: ClassVar[type[RCGAParams]] = RCGAParams
    params: RCGAParams

    def __init__(
        self,
        num_params: int,
        params: RCGAParams = RCGAParams(),
        seed: int = 0,
        init: np.ndarray | None = None,
    ):
        super().__init__(num_params, params, seed)
        self.population = np.empty((0, self.num_params))
        self._init = None if init is None else np.array(init, dtype=np.float64)
        if self._init is not None and self._init.shape != (
            params.population,
            num_params,
        ):
            raise ValueError(
                f"init has shape {self._init.shape}, expected "
                f"({params.population}, {num_params})"
            )

    def _ask(self) -> np.ndarray:
        p = self.params
        if self.generation > 0:
            return self._children(p.population - p.elite)
        if self._init is not None:
            return self._init.copy()
        s = abs(p.init_scale)  # -0.0 is in range; uniform(0.0, -0.0) refuses it
        return self.rng.uniform(-s, s, size=(p.population, self.num_params))

    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> np.ndarray:
        e = self.params.elite if self.generation > 0 else 0
        pop = np.concatenate([self.population[:e], genomes])
        fit = np.concatenate([self.fitness[:e], fitness])
        order = np.argsort(-fit, kind="stable")  # elites win ties: they come first
        self.population = pop[order]
        ranked: np.ndarray = fit[order]
        return ranked

    # -- variation --

    def _children(self, n: int) -> np.ndarray:
        p, rng = self.params, self.rng

        def pick() -> np.ndarray:
            return self.population[tournament(self.fitness, n, p.tournament_size, rng)]

        a, b = pick(), pick()
        if p.crossover == "blx":
            x = blx_alpha(a, b, p.blx_alpha, rng)
        elif p.crossover == "sbx":
            x = sbx(a, b, p.sbx_eta, rng)
        else:
            x = undx(a, b, pick(), p.undx_sigma_xi, p.undx_sigma_eta, rng)
        if p.crossover_rate < 1.0:
            keep = rng.random(n) >= p.crossover_rate
            x[keep] = a[keep]
        return gaussian_mutation(x, p.mutation_rate, p.mutation_sigma, rng)

    # -- checkpointing --

    def _state(self) -> dict[str, np.ndarray]:
        return {
            "population": self.population.copy(),
            "fitness": self.fitness.copy(),
            "rng_state": rng_state(self.rng),
        }

    def _set_state(self, state: Mapping[str, np.ndarray]) -> None:
        self.rng = rng_from_state(state["rng_state"])
        self.population = np.array(state["population"], dtype=np.float64)
        self.fitness = np.array(state["fitness"], dtype=np.float64)
        n = self.params.population
        if self.generation < 1 or self.population.shape != (n, self.num_params):
            raise ValueError(
                f"population has shape {self.population.shape} at generation "
                f"{self.generation}, expected ({n}, {self.num_params})"
            )
        if not np.isfinite(self.population).all():
            raise ValueError("population is not finite")
        if self.fitness.shape != (n,) or np.isnan(self.fitness).any():
            raise ValueError("fitness has the wrong shape or contains NaN")
        # elitism keeps the best so far first (without elites: the best of
        # the last generation, all that the state holds)
        self._set_best(self.population[0], self.fitness[0])
