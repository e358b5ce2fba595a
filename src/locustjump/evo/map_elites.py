"""MAP-Elites (Mouret & Clune 2015) on pyribs (extra ``locustjump[qd]``).

Each generation, genomes are drawn around elites picked uniformly from the
archive, by one of two variations:

* ``gaussian`` (pyribs' ``GaussianEmitter``): an elite plus Gaussian noise of
  standard deviation ``sigma`` on every gene;
* ``iso-line`` (pyribs' ``IsoLineEmitter``; Vassiliades & Mouret 2018): an
  elite ``x_i`` plus isotropic noise of ``sigma`` plus ``line_sigma`` times a
  Gaussian number times the direction to another elite ``x_j``; genomes of a
  repertoire's elites are correlated, and the line follows them.

The first generation is uniform in ``[-init_scale, init_scale]`` per gene (the
RCGA's start, from the run's generator), each emitter its share. The archive,
seeds and state: :mod:`.qd`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from locustjump.evo.base import MAX_GENE_SCALE
from locustjump.evo.qd import QDOptimizer, QDParams, import_ribs
from locustjump.ranges import Range, setting

Variation = Literal["gaussian", "iso-line"]
VARIATIONS: tuple[str, ...] = ("gaussian", "iso-line")
#: a gene-scale setting (as the RCGA's, but more than 0)
_GENE_SCALE = Range(0.0, MAX_GENE_SCALE, lo_open=True)


@dataclass(frozen=True)
class MapElitesParams(QDParams):
    """Settings of MAP-Elites (the shared ones: :class:`~.qd.QDParams`)."""

    kind: ClassVar[str] = "map-elites"
    variation: Variation = "gaussian"
    #: (gene units) the Gaussian's standard deviation; iso-line: the isotropic part's
    sigma: float = setting(0.1, _GENE_SCALE)
    #: iso-line only: the spread along the line (-)
    line_sigma: float = setting(0.2, _GENE_SCALE)
    #: first genomes uniform in [-init_scale, init_scale]
    init_scale: float = setting(1.0, _GENE_SCALE)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.variation not in VARIATIONS:
            raise ValueError(
                f"variation must be one of {', '.join(VARIATIONS)}, "
                f"got {self.variation!r}"
            )


class MapElites(QDOptimizer):
    """Ask/tell MAP-Elites over a pyribs grid archive. Maximises."""

    Params: ClassVar[type] = MapElitesParams

    def _emitters(self, archive: Any, seeds: list[int]) -> list[Any]:
        ribs = import_ribs()
        p = self.params
        sizes = p.batch_sizes()
        s = p.init_scale
        first = self.rng.uniform(-s, s, size=(p.population, self.num_params))
        starts = np.split(first, np.cumsum(sizes)[:-1])
        if p.variation == "gaussian":
            return [
                ribs.emitters.GaussianEmitter(
                    archive,
                    sigma=p.sigma,
                    initial_solutions=x0s,
                    batch_size=n,
                    seed=seed,
                )  # fmt: skip
                for x0s, n, seed in zip(starts, sizes, seeds, strict=True)
            ]
        return [
            ribs.emitters.IsoLineEmitter(
                archive,
                iso_sigma=p.sigma,
                line_sigma=p.line_sigma,
                initial_solutions=x0s,
                batch_size=n,
                seed=seed,
            )  # fmt: skip
            for x0s, n, seed in zip(starts, sizes, seeds, strict=True)
        ]
