"""CMA-ME, covariance matrix adaptation MAP-Elites (Fontaine et al. 2020), on
pyribs (extra ``locustjump[qd]``).

Each of ``emitters`` emitters is a CMA-ES (pyribs' ``EvolutionStrategyEmitter``
with its ``cma_es``) that starts at the origin with step ``sigma0`` and ranks
its genomes by what they did to the archive (pyribs' ``2imp`` ranker: new
cells first, then improvements, by how much); when none of its genomes
entered the archive it restarts from an elite picked at random. The archive,
seeds and state (the evolution strategies are replayed, never pickled):
:mod:`.qd`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from locustjump.evo.base import MAX_GENE_SCALE
from locustjump.evo.qd import EMITTERS, QDOptimizer, QDParams, import_ribs
from locustjump.ranges import Range, setting


@dataclass(frozen=True)
class CMAMEParams(QDParams):
    """Settings of CMA-ME (the shared ones: :class:`~.qd.QDParams`)."""

    kind: ClassVar[str] = "cma-me"
    #: a CMA-ES needs two genomes a generation to rank
    min_batch: ClassVar[int] = 2
    #: CMA-ES emitters (Fontaine et al.: 15 of 37 genomes)
    emitters: int = setting(5, EMITTERS)
    #: initial step size of each (as the cma optimizer's)
    sigma0: float = setting(0.5, Range(0.0, MAX_GENE_SCALE, lo_open=True))


class CMAME(QDOptimizer):
    """Ask/tell CMA-ME over a pyribs grid archive. Maximises."""

    Params: ClassVar[type] = CMAMEParams

    def _emitters(self, archive: Any, seeds: list[int]) -> list[Any]:
        ribs = import_ribs()
        p = self.params
        return [
            ribs.emitters.EvolutionStrategyEmitter(
                archive,
                x0=np.zeros(self.num_params),
                sigma0=p.sigma0,
                ranker="2imp",
                es="cma_es",
                selection_rule="filter",
                restart_rule="no_improvement",
                batch_size=n,
                seed=seed,
            )  # fmt: skip
            for n, seed in zip(p.batch_sizes(), seeds, strict=True)
        ]
