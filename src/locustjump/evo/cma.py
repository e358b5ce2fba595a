"""CMA-ES (Hansen & Ostermeier 2001) from the ``cma`` library (pycma), behind
the ask/tell protocol (extra ``locustjump[cma]``).

pycma minimises, so it is told ``-fitness``. Its own checkpoint is a pickle,
which this project never loads; instead the state is the run's seed plus every
fitness vector told so far: ask/tell is a deterministic function of them, so
:meth:`CMAES.load_state` rebuilds the strategy and replays ask/tell without
re-simulating (about 5 ms a generation for 144 genes and population 50, measured). All
of pycma's sampling goes through its ``randn`` option, which is given a
``numpy.random.Generator`` seeded from the run's seed: no global random state
is read or written.

pycma's own stopping rules that would end a fixed-budget run early (flat
fitness, the iteration cap, tiny changes) are switched off; those that signal a
numerical breakdown (ill-conditioned covariance, a runaway step size) stay on
and are reported by :meth:`CMAES.stop`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from locustjump.errors import UserError, setting_ref
from locustjump.evo.base import MAX_GENE_SCALE, POPULATION, Optimizer
from locustjump.ranges import Range, check_settings, setting

#: pycma's stop keys that are ours to ignore: the trainer owns the budget
_BUDGET_RULES = {
    "maxiter": float("inf"),
    "tolflatfitness": 10**9,
    "tolfun": 0.0,
    "tolfunhist": 0.0,
    "tolx": 0.0,
    "tolstagnation": 10**9,
}


@dataclass(frozen=True)
class CMAParams:
    """Settings of CMA-ES: the initial mean is 0, the initial step ``sigma0``."""

    kind: ClassVar[str] = "cma"
    #: lambda, genomes per generation (paper's GA: 50)
    population: int = setting(50, POPULATION)
    #: initial step size (genes of the RCGA start in [-1, 1])
    sigma0: float = setting(0.5, Range(0.0, MAX_GENE_SCALE, lo_open=True))

    def __post_init__(self) -> None:
        check_settings(self)

    def replace(self, **changes: Any) -> CMAParams:
        return dataclasses.replace(self, **changes)


def _import_cma() -> Any:  # pycma: untyped
    try:
        import cma
    except ImportError:
        raise UserError(
            f"{setting_ref('optimizer')} cma needs the cma library: "
            "pip install -e '.[cma]' in the clone"
        ) from None
    return cma


class CMAES(Optimizer):
    """Ask/tell CMA-ES over pycma. Maximises.

    Diagnostics (``metrics.csv`` columns): ``sigma``, the step size, and
    ``condition``, the condition number of the covariance matrix C (pycma
    updates its eigendecomposition every few generations; this is the last).
    """

    Params: ClassVar[type[CMAParams]] = CMAParams
    params: CMAParams

    def __init__(self, num_params: int, params: CMAParams = CMAParams(), seed: int = 0):
        super().__init__(num_params, params, seed)
        self._start()

    def _start(self) -> None:
        """pycma at generation 0, sampling from ``self.rng`` (fresh from the seed)."""
        cma = _import_cma()
        self._restart()
        opts = {
            "popsize": self.params.population,
            "seed": np.nan,  # pycma leaves numpy's global generator alone
            "randn": lambda lam, n: self.rng.standard_normal((lam, n)),
            "verbose": -9,
            "verb_log": 0,
            "verb_disp": 0,
            **_BUDGET_RULES,
        }
        self.es = cma.CMAEvolutionStrategy(
            np.zeros(self.num_params), self.params.sigma0, opts
        )
        self.history: list[np.ndarray] = []

    def _ask(self) -> np.ndarray:
        return np.array(self.es.ask(), dtype=np.float64)

    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> None:
        self.es.tell(list(genomes), list(-fitness))  # pycma minimises
        self.history.append(fitness.copy())

    def _stop(self) -> dict[str, Any]:
        return {k: v for k, v in self.es.stop().items() if k not in _BUDGET_RULES}

    def diagnostics(self) -> dict[str, float]:
        return {
            "sigma": float(self.es.sigma),
            "condition": float(self.es.condition_number),
        }

    def _state(self) -> dict[str, np.ndarray]:
        return {
            "seed": np.array(self.seed),
            "fitness_history": np.array(self.history).reshape(
                self.generation, self.params.population
            ),
        }

    def _set_state(self, state: Mapping[str, np.ndarray]) -> None:
        """Rebuild from the seed and replay ask/tell with the recorded fitness."""
        hist = np.asarray(state["fitness_history"], dtype=np.float64)
        if int(state["seed"]) != self.seed:
            raise ValueError(f"state is of seed {int(state['seed'])}, not {self.seed}")
        if hist.shape != (self.generation, self.params.population):
            raise ValueError(f"fitness_history has the wrong shape {hist.shape}")
        self._start()
        for f in hist:
            self.ask()
            self.tell(f)
