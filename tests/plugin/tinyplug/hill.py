"""A hill climber: Gaussian samples around the best genome so far. Its module
registers it, so that ``--plugin tinyplug.hill`` finds it too; its entry
point names the class (``hillclimb = tinyplug.hill:HillClimb``)."""

import dataclasses
from typing import Any, ClassVar

import numpy as np

from locustjump.evo import Optimizer, register, rng_from_state, rng_state


@dataclasses.dataclass(frozen=True)
class HillClimbParams:
    kind: ClassVar[str] = "hillclimb"
    population: int = 8
    step: float = 0.1

    def replace(self, **changes: Any) -> "HillClimbParams":
        return dataclasses.replace(self, **changes)


@register
class HillClimb(Optimizer):
    Params = HillClimbParams

    def _ask(self) -> np.ndarray:
        n = (self.params.population, self.num_params)
        return self.best + self.rng.normal(0, self.params.step, n)

    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> None:
        pass  # the base keeps the best so far

    def _state(self) -> dict[str, np.ndarray]:
        return {"best": self.best, "best_fitness": np.array(self.best_fitness),
                "rng": rng_state(self.rng)}  # fmt: skip

    def _set_state(self, s) -> None:
        self._set_best(s["best"], float(s["best_fitness"]))
        self.rng = rng_from_state(s["rng"])
