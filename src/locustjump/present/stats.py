"""Two samples compared as far as the data allow: a shift, its interval, tests.

A sample is one value per seed (a run's best fitness, in fitness units).
Fitness is maximised, so a positive shift ``a - b`` means ``a`` is better.
``compare_samples(a, b)`` gives, for ``a - b``:

- the Hodges–Lehmann shift (the median of the ``m * n`` pairwise differences)
  with its distribution-free 95 % interval (Hollander & Wolfe,
  *Nonparametric Statistical Methods*, the two-sample location problem;
  Bauer 1972, *JASA* 67:687): exact without ties up to :data:`EXACT_MAX`
  runs a sample, conservative with ties, the interval of R's
  ``wilcox.test(a, b, conf.int=TRUE)`` in the exact case;
- the two-sided Mann–Whitney U test, exact up to :data:`EXACT_MAX` runs a
  sample (given the ties: the permutation distribution of the midrank sum),
  so that its p and the interval never disagree;
- with a declared equivalence margin ``M`` (fitness units): the two
  one-sided tests of equivalence within ``±M`` (TOST, Schuirmann 1987, with
  Mann–Whitney tests), and the seeds per arm that would give about 80 %
  power to detect a shift of ``M`` at the observed spread;
- a verdict whose words follow the interval, never the p value alone.

SciPy is the optional extra ``locustjump[study]``; the exact null
distributions are computed here, with NumPy (SciPy's ``mannwhitneyu`` takes
the normal approximation above 8 runs a sample or with any tie, where its p
could say "significant" beside an interval that covers 0, or the reverse).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass
from types import ModuleType
from typing import Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike

from locustjump.errors import UserError

#: the level of the two one-sided tests of equivalence
ALPHA = 0.05
#: the largest group for which the null distribution of U is counted exactly
#: (the recurrence costs ~ m^2 n^2 / 2 additions: milliseconds at 50 x 50)
EXACT_MAX = 50
#: asymptotic relative efficiency of Mann-Whitney to the t test, normal data
ARE = 3 / math.pi


def _scipy_stats() -> ModuleType:
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


@dataclass(frozen=True)
class Comparison:
    """``a - b`` for two samples; fitness is maximised (higher is better).

    ``shift`` is the Hodges–Lehmann estimate, ``[low, high]`` its interval at
    level ``confidence`` (``-inf, inf`` where the samples are too small for
    one), ``p`` and ``u`` the two-sided Mann–Whitney test (U of ``a``),
    ``margin`` the declared equivalence margin (fitness units) or None,
    ``p_equivalence`` the TOST p against ``±margin``, ``seeds_for_power`` the
    seeds per arm for 80 % power against a shift of ``margin``.
    """

    a: str
    b: str
    n_a: int
    n_b: int
    shift: float
    low: float
    high: float
    confidence: float
    p: float
    u: float
    margin: float | None
    p_equivalence: float | None
    seeds_for_power: int | None
    verdict: str

    def row(self) -> dict[str, Any]:
        """Every field, JSON-able: a bound that does not exist (infinite) or
        a p that is undefined (NaN) is None."""
        return {
            k: (None if isinstance(v, float) and not math.isfinite(v) else v)
            for k, v in dataclasses.asdict(self).items()
        }


def _values(x: SampleLike, name: str) -> np.ndarray:
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
    cdf: np.ndarray = _scipy_stats().norm.cdf((u + 0.5 - m * n / 2) / sigma)
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
    x, y = _values(a, "a"), _values(b, "b")
    if alternative not in ("two-sided", "greater", "less"):
        raise ValueError(
            f"alternative must be two-sided, greater or less, got {alternative!r}"
        )
    m, n = x.size, y.size
    if max(m, n) > EXACT_MAX:
        r = _scipy_stats().mannwhitneyu(
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
    x, y = _values(a, "a"), _values(b, "b")
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
    x, y = _values(a, "a"), _values(b, "b")
    above = mann_whitney(x + margin, y, alternative="greater")[1]
    below = mann_whitney(x - margin, y, alternative="less")[1]
    return max(above, below)


def pooled_spread(a: SampleLike, b: SampleLike) -> float:
    """The pooled standard deviation of two samples (each variance with
    ddof=1, weighted by its degrees of freedom), in their units."""
    x, y = _values(a, "a"), _values(b, "b")
    ss = (x.size - 1) * x.var(ddof=1) + (y.size - 1) * y.var(ddof=1)
    return float(math.sqrt(ss / (x.size + y.size - 2)))


def seeds_for_power(
    spread: float, delta: float, alpha: float = 0.05, power: float = 0.8
) -> int | None:
    """Seeds per arm for a two-sided Mann–Whitney test at level ``alpha`` to
    detect a shift ``delta`` with probability ``power``, where values spread
    with standard deviation ``spread`` (same units as ``delta``).

    An approximation: the normal approximation of the two-sample t test,
    divided by the Mann–Whitney test's asymptotic relative efficiency 3/pi
    (normal data), plus Guenther's small-sample term z(1 - alpha/2)^2 / 4:
    ``n = ceil(2 (z(1 - alpha/2) + z(power))^2 spread^2 / delta^2 / (3/pi)
    + z(1 - alpha/2)^2 / 4)``, and at least the smallest ``n`` whose exact
    two-sided test can reach ``alpha`` at all (4 at 0.05: 3 against 3 never
    gets below p = 0.1). None where ``spread`` is 0 (no spread to go by).
    """
    if not (math.isfinite(delta) and delta > 0):
        raise ValueError(f"delta must be a finite number > 0, got {delta}")
    if not (math.isfinite(spread) and spread >= 0):
        raise ValueError(f"spread must be a finite number >= 0, got {spread}")
    for name, v in (("alpha", alpha), ("power", power)):
        if not 0 < v < 1:
            raise ValueError(f"{name} must be in (0, 1), got {v}")
    if spread == 0:
        return None
    norm = _scipy_stats().norm
    z_alpha: float = norm.ppf(1 - alpha / 2)
    z: float = z_alpha + norm.ppf(power)
    n = math.ceil(2 * (z * spread / delta) ** 2 / ARE + z_alpha**2 / 4)
    return max(n, _smallest_n(alpha))


def _smallest_n(alpha: float) -> int:
    """The smallest ``n`` whose ``n`` against ``n`` exact two-sided test can
    reach ``alpha``: its smallest p, ``2 / C(2n, n)``, is below it."""
    n = 2
    while 2 / math.comb(2 * n, n) >= alpha:
        n += 1
    return n


def _g(x: float) -> str:
    return f"{x:.3g}"


def _percent(confidence: float) -> str:
    return f"{confidence * 100:g} %"


def verdict(c: Comparison) -> str:
    """The words for ``c``, chosen by its interval (fitness is maximised):
    ``A better than B`` where the interval lies above 0, ``B better than
    A`` below, each followed by ``, by less than M`` where, with a margin,
    the TOST p is below :data:`ALPHA` too (a difference, but within what
    the margin declares negligible); else, with a margin, ``equivalent
    within ±M`` where the TOST p is below :data:`ALPHA`; else ``no evidence
    either way`` with the interval (or with why there is none)."""
    within = (
        c.p_equivalence is not None and c.p_equivalence < ALPHA and c.margin is not None
    )
    small = f", by less than {_g(c.margin)}" if within and c.margin else ""
    if c.low > 0:
        return f"{c.a} better than {c.b}{small}"
    if c.high < 0:
        return f"{c.b} better than {c.a}{small}"
    if within and c.margin is not None:
        return f"equivalent within ±{_g(c.margin)}"
    if not (math.isfinite(c.low) and math.isfinite(c.high)):
        return (
            f"no evidence either way: too few runs for a {_percent(c.confidence)} "
            f"interval ({c.n_a} and {c.n_b})"
        )
    return f"no evidence either way: interval [{_g(c.low)}, {_g(c.high)}]"


def compare_samples(
    a: SampleLike, b: SampleLike, *, names: tuple[str, str] | None = None,
    margin: float | None = None, confidence: float = 0.95,
) -> Comparison:  # fmt: skip
    """``a - b`` as a :class:`Comparison`: the Hodges–Lehmann shift and its
    interval, the two-sided Mann–Whitney test and, with ``margin`` (> 0,
    fitness units), the TOST p and the seeds for 80 % power against a
    shift of ``margin`` at the samples' pooled spread; and the verdict.

    ``a`` and ``b`` are :class:`Sample` s or numbers; ``names`` label them
    (default: the samples' labels, else ``A`` and ``B``). ValueError naming
    a sample of fewer than 2 values, or a margin not > 0 (:func:`tost`).
    """
    if names is None:
        names = (
            a.label if isinstance(a, Sample) else "A",
            b.label if isinstance(b, Sample) else "B",
        )
    x, y = _values(a, names[0]), _values(b, names[1])
    shift, low, high = hodges_lehmann(x, y, confidence)
    u, p = mann_whitney(x, y)
    c = Comparison(
        a=names[0], b=names[1], n_a=x.size, n_b=y.size,
        shift=shift, low=low, high=high, confidence=confidence,
        p=p, u=u, margin=margin,
        p_equivalence=None if margin is None else tost(x, y, margin),
        seeds_for_power=(
            None if margin is None else seeds_for_power(pooled_spread(x, y), margin)
        ),
        verdict="",
    )  # fmt: skip
    return dataclasses.replace(c, verdict=verdict(c))


def interval_text(c: Comparison) -> str:
    """``shift [low, high]`` to 4 significant figures, or ``shift (no
    interval)`` where the samples are too small for one."""
    if not (math.isfinite(c.low) and math.isfinite(c.high)):
        return f"{c.shift:.4g} (no interval)"
    return f"{c.shift:.4g} [{c.low:.4g}, {c.high:.4g}]"


def p_text(p: float | None) -> str:
    """A p value to 3 significant figures, ``-`` where there is none."""
    return "-" if p is None or not math.isfinite(p) else f"{p:.3g}"


def pairs_table(comparisons: Sequence[Comparison]) -> str:
    """A Markdown table, a row per comparison ``a - b``: the pair, the runs
    of each, the Hodges–Lehmann shift with its interval, the two-sided
    Mann–Whitney p, the TOST p against ``±margin`` and the seeds per arm for
    80 % power against a shift of ``margin`` (``-`` without a margin), and
    the verdict."""
    levels = {c.confidence for c in comparisons} or {0.95}
    level = f"{_percent(levels.pop())} CI" if len(levels) == 1 else "CI"
    margins = {c.margin for c in comparisons if c.margin is not None}
    m = f"±{_g(margins.pop())}" if len(margins) == 1 else "±margin"
    lines = [
        f"| pair | n | HL shift [{level}] | Mann–Whitney p | TOST p vs {m} | "
        "seeds for 80 % power | verdict |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for c in comparisons:
        tost_p = p_text(c.p_equivalence)
        if c.margin is not None and m == "±margin":
            tost_p += f" (±{_g(c.margin)})"
        power = "-" if c.seeds_for_power is None else str(c.seeds_for_power)
        lines.append(
            f"| {c.a} - {c.b} | {c.n_a}, {c.n_b} | {interval_text(c)} | "
            f"{p_text(c.p)} | {tost_p} | {power} | {c.verdict} |"
        )
    return "\n".join(lines)
