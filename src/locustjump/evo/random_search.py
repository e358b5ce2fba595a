"""Random search: every generation a fresh uniform sample; the floor that any
optimizer must beat at the same number of evaluations (Bergstra & Bengio 2012
make the case for it as a baseline).

Genes are uniform in ``[-init_scale, init_scale]``, the RCGA's initial
distribution, so generation 1 of both is the same kind of sample.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from locustjump.evo.base import (
    MAX_GENE_SCALE,
    POPULATION,
    Optimizer,
    rng_from_state,
    rng_state,
)
from locustjump.ranges import Range, check_settings, setting


@dataclass(frozen=True)
class RandomSearchParams:
    """Settings of random search."""

    kind: ClassVar[str] = "random"
    population: int = setting(50, POPULATION)  # genomes per generation
    #: genes uniform in [-init_scale, init_scale]
    init_scale: float = setting(1.0, Range(0.0, MAX_GENE_SCALE, lo_open=True))

    def __post_init__(self) -> None:
        check_settings(self)

    def replace(self, **changes: Any) -> RandomSearchParams:
        return dataclasses.replace(self, **changes)


class RandomSearch(Optimizer):
    """Ask/tell random search. Maximises; never stops on its own."""

    Params: ClassVar[type[RandomSearchParams]] = RandomSearchParams
    params: RandomSearchParams

    def __init__(
        self,
        num_params: int,
        params: RandomSearchParams = RandomSearchParams(),
        seed: int = 0,
    ):
        super().__init__(num_params, params, seed)

    def _ask(self) -> np.ndarray:
        s = self.params.init_scale
        return self.rng.uniform(-s, s, size=(self.params.population, self.num_params))

    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> None:
        """Nothing to learn: the next sample does not depend on the last."""

    def _state(self) -> dict[str, np.ndarray]:
        # the best so far cannot be recomputed from the generator: it is saved
        return {
            "fitness": self.fitness.copy(),
            "best": self.best,
            "best_fitness_so_far": np.array(self.best_fitness),
            "rng_state": rng_state(self.rng),
        }

    def _set_state(self, state: Mapping[str, np.ndarray]) -> None:
        self.rng = rng_from_state(state["rng_state"])
        self.fitness = np.array(state["fitness"], dtype=np.float64)
        self._set_best(state["best"], float(state["best_fitness_so_far"]))
        if self.generation < 1:
            raise ValueError("random-search state has the wrong shape")
