"""Two samples' rank tests, computed exactly: Mann–Whitney, Hodges–Lehmann, TOST.

A sample is one value per seed (a run's best fitness, in fitness units).
For ``a - b`` (fitness is maximised, so a positive shift means ``a`` is
better):

- :func:`hodges_lehmann`: the median of the ``m * n`` pairwise differences
  with its distribution-free interval (Hollander & Wolfe, *Nonparametric
  Statistical Methods*, the two-sample location problem; Bauer 1972,
  *JASA* 67:687): exact without ties up to :data:`EXACT_MAX` runs a sample,
  conservative with ties, the interval of R's ``wilcox.test(a, b,
  conf.int=TRUE)`` in the exact case;
- :func:`mann_whitney`: the Mann–Whitney U test, exact up to
  :data:`EXACT_MAX` runs a sample (given the ties: the permutation
  distribution of the midrank sum), so that its p and the interval never
  disagree;
- :func:`tost`: the two one-sided tests of equivalence within ``±M``
  (Schuirmann 1987, with Mann–Whitney tests).

The exact null distributions are computed here, with NumPy: SciPy's
``mannwhitneyu`` takes the normal approximation above 8 runs a sample or
with any tie, where its p could say "significant" beside an interval that
covers 0, or the reverse. SciPy (the optional extra ``locustjump[study]``)
gives the normal approximation beyond :data:`EXACT_MAX`.
:mod:`locustjump.present.stats` puts these together into a comparison and
its words.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from types import ModuleType
from typing import TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from locustjump.errors import UserError

#: the largest group for which the null distribution of U is counted exactly
#: (the recurrence costs ~ m^2 n^2 / 2 additions: milliseconds at 50 x 50)
EXACT_MAX = 50


def scipy_stats() -> ModuleType:
    try:
        from scipy import stats
    except ImportError:
        raise UserError(
            "the rank tests need SciPy: pip install -e '.[study]' in the clone"
        ) from None
    return stats


@dataclass(frozen=True)
class Sample:
    """One group's values, one per seed (or run), in fitness units."""

    label: str
    values: np.ndarray

    def __post_init__(self) -> None:
        values = np.asarray(self.values, dtype=float).ravel()
        object.__setattr__(self, "values", values)

    @property
    def n(self) -> int:
        return int(self.values.size)

    @property
    def median(self) -> float:
        return float(np.median(self.values))

    @property
    def low(self) -> float:
        return float(self.values.min())

    @property
    def high(self) -> float:
        return float(self.values.max())


#: a :class:`Sample`, or numbers (one per seed)
SampleLike: TypeAlias = Sample | ArrayLike


def sample_values(x: SampleLike, name: str) -> np.ndarray:
    """``x`` (a :class:`Sample` or numbers) as a float array of at least two
    finite values; ValueError naming ``name`` otherwise."""
    if isinstance(x, Sample):
        name, x = x.label, x.values
    v = np.asarray(x, dtype=float).ravel()
    if v.size < 2:
        raise ValueError(f"sample {name!r} needs at least 2 values, got {v.size}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"sample {name!r} holds a value that is not finite")
    return v


@functools.lru_cache(maxsize=64)
def u_null_distribution(m: int, n: int) -> np.ndarray:
    """P(U = u), u = 0 ... m*n, for U = #{(i, j): a_i > b_j} of samples of
    sizes ``m`` and ``n`` from one continuous distribution (no ties).

    Counted by the recurrence on the largest of the ``m + n`` values: it is
    an ``a`` with probability ``m / (m + n)``, and then beats all ``n``
    values of ``b``: ``P[m, n](u) = m/(m+n) P[m-1, n](u - n) + n/(m+n)
    P[m, n-1](u)``, ``P[0, n] = P[m, 0] = [1]``. Probabilities rather than
    counts, so that nothing overflows. Read only (cached)."""
    if m < 0 or n < 0:
        raise ValueError(f"sample sizes must be >= 0, got {m} and {n}")
    prev = [np.ones(1)] * (n + 1)  # m = 0: U is 0
    for i in range(1, m + 1):
        cur = [np.ones(1)]
        for j in range(1, n + 1):
            p = np.zeros(i * j + 1)
            p[j:] += i / (i + j) * prev[j]  # the largest is an a: U += j
            p[: i * (j - 1) + 1] += j / (i + j) * cur[j - 1]
            cur.append(p)
        prev = cur
    out = prev[n]
    out.flags.writeable = False
    return out


def _u_cdf(m: int, n: int) -> np.ndarray:
    """P(U <= u), u = 0 ... m*n: exact up to :data:`EXACT_MAX` per group,
    else the normal approximation with continuity correction."""
    if max(m, n) <= EXACT_MAX:
        return np.cumsum(u_null_distribution(m, n))
    sigma = math.sqrt(m * n * (m + n + 1) / 12)
    u = np.arange(m * n + 1)
    cdf: np.ndarray = scipy_stats().norm.cdf((u + 0.5 - m * n / 2) / sigma)
    return cdf


def _rank_sum_null(ranks2: np.ndarray, m: int) -> np.ndarray:
    """P(R = r), r = 0 ... sum(ranks2), for R the sum of ``m`` of the doubled
    midranks ``ranks2`` (integers) drawn without replacement: the exact null
    distribution of an ``m``-sample's rank sum given the ties. Counted by
    the subset-sum recurrence over the values, in floats (C(100, 50) < 1e30)."""
    top = int(np.sort(ranks2)[ranks2.size - m :].sum())
    c = np.zeros((m + 1, top + 1))
    c[0, 0] = 1.0
    for r in ranks2.tolist():
        c[1:, r:] = c[1:, r:] + c[:-1, : top + 1 - r]
    out: np.ndarray = c[m] / c[m].sum()
    return out


def mann_whitney(
    a: SampleLike, b: SampleLike, alternative: str = "two-sided"
) -> tuple[float, float]:
    """The Mann–Whitney U of ``a`` (pairs ``a_i > b_j``, ties counting a
    half) and its p against ``b``: ``alternative`` ``two-sided``,
    ``greater`` (``a`` shifted up) or ``less``. Exact up to
    :data:`EXACT_MAX` values a sample (the permutation distribution of the
    midrank sum, which takes the ties as they are; two-sided: twice the
    smaller tail, at most 1, as SciPy's exact test), SciPy's normal
    approximation with its tie correction beyond."""
    x, y = sample_values(a, "a"), sample_values(b, "b")
    if alternative not in ("two-sided", "greater", "less"):
        raise ValueError(
            f"alternative must be two-sided, greater or less, got {alternative!r}"
        )
    m, n = x.size, y.size
    if max(m, n) > EXACT_MAX:
        r = scipy_stats().mannwhitneyu(
            x, y, alternative=alternative, method="asymptotic"
        )
        return float(r.statistic), float(r.pvalue)
    # doubled midranks: the values of a tie share the mean of their ranks
    _, group, counts = np.unique(
        np.concatenate([x, y]), return_inverse=True, return_counts=True
    )
    ranks2 = (2 * (np.cumsum(counts) - counts) + counts + 1)[group]
    r2 = int(ranks2[:m].sum())
    u = (r2 - m * (m + 1)) / 2
    dist = _rank_sum_null(ranks2, m)
    low, high = float(dist[: r2 + 1].sum()), float(dist[r2:].sum())
    p = {"greater": high, "less": low}.get(alternative, 2 * min(low, high))
    return u, min(1.0, p)


def hodges_lehmann(
    a: SampleLike, b: SampleLike, confidence: float = 0.95
) -> tuple[float, float, float]:
    """The Hodges–Lehmann shift of ``a - b`` and its distribution-free
    interval: ``(shift, low, high)``, in the samples' units.

    The shift is the median of the ``m * n`` differences ``a_i - b_j``. The
    interval is ``[D(k), D(m*n + 1 - k)]`` of their order statistics
    ``D(1) <= ... <= D(m*n)``: ``D(k) <= shift < D(m*n + 1 - k)`` fails
    exactly when the Mann–Whitney U of ``a - shift`` against ``b`` is below
    ``k`` or above ``m*n - k``, so the interval covers the true shift with
    probability ``1 - 2 P(U <= k - 1)``; ``k`` is the smallest ``u`` with
    ``P(U <= u) >= (1 - confidence) / 2`` (as R's ``qwilcox``), from the
    exact null distribution of U (:func:`u_null_distribution`) up to
    :data:`EXACT_MAX` values per sample, the normal approximation beyond.
    Its coverage is then at least ``confidence`` (exactly so without ties;
    ties make it approximate). Where even ``[D(1), D(m*n)]`` covers less
    (``P(U = 0) > (1 - confidence) / 2``: 2 vs 2, 3 vs 3 at 95 %), no
    interval at the level exists and the bounds are ``-inf, inf``.
    ValueError naming a sample of fewer than 2 values.
    """
    if not 0 < confidence < 1:
        raise ValueError(f"confidence must be in (0, 1), got {confidence}")
    x, y = sample_values(a, "a"), sample_values(b, "b")
    d = np.sort(np.subtract.outer(x, y).ravel())
    shift = float(np.median(d))
    cdf = _u_cdf(x.size, y.size)
    # the relative slack keeps a cdf equal to alpha/2 from rounding below it
    k = int(np.count_nonzero(cdf < (1 - confidence) / 2 * (1 - 1e-9)))
    if k == 0:
        return shift, -math.inf, math.inf
    return shift, float(d[k - 1]), float(d[d.size - k])


def tost(a: SampleLike, b: SampleLike, margin: float) -> float:
    """p of equivalence of ``a`` and ``b`` within ``±margin`` (fitness units):
    the larger p of two one-sided Mann–Whitney tests (:func:`mann_whitney`),
    of H0 shift <= -margin
    (``a + margin`` against ``b``, alternative greater) and of H0 shift >=
    +margin (``a - margin`` against ``b``, alternative less). Below alpha,
    the shift lies within ``±margin`` at level alpha. ValueError unless
    ``margin > 0``."""
    if not (math.isfinite(margin) and margin > 0):
        raise ValueError(f"margin must be a finite number > 0, got {margin}")
    x, y = sample_values(a, "a"), sample_values(b, "b")
    above = mann_whitney(x + margin, y, alternative="greater")[1]
    below = mann_whitney(x - margin, y, alternative="less")[1]
    return max(above, below)
