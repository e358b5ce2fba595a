"""Two samples compared as far as the data allow: a shift, its interval, tests.

A sample is one value per seed (a run's best fitness, in fitness units).
Fitness is maximised, so a positive shift ``a - b`` means ``a`` is better.
``compare_samples(a, b)`` gives, for ``a - b``:

- the Hodges–Lehmann shift with its distribution-free 95 % interval and the
  two-sided Mann–Whitney test, both exact up to
  :data:`~locustjump.present.ranktests.EXACT_MAX` runs a sample
  (:mod:`locustjump.present.ranktests`);
- with a declared equivalence margin ``M`` (fitness units): the two
  one-sided tests of equivalence within ``±M`` (TOST), and the seeds per arm
  that would give about 80 % power to detect a shift of ``M`` at the
  observed spread;
- a verdict whose words follow the interval, never the p value alone.

SciPy is the optional extra ``locustjump[study]``.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from locustjump.present.ranktests import (
    Sample,
    SampleLike,
    hodges_lehmann,
    mann_whitney,
    sample_values,
    scipy_stats,
    tost,
)

#: the level of the two one-sided tests of equivalence
ALPHA = 0.05
#: asymptotic relative efficiency of Mann-Whitney to the t test, normal data
ARE = 3 / math.pi


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


def pooled_spread(a: SampleLike, b: SampleLike) -> float:
    """The pooled standard deviation of two samples (each variance with
    ddof=1, weighted by its degrees of freedom), in their units."""
    x, y = sample_values(a, "a"), sample_values(b, "b")
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
    norm = scipy_stats().norm
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
    x, y = sample_values(a, names[0]), sample_values(b, names[1])
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


def holm(p: Sequence[float]) -> list[float]:
    """Holm–Bonferroni adjusted p values (Holm 1979, step-down): the k-th
    smallest of m p values times m - k + 1, never below an earlier one,
    capped at 1. Each comparison holds at a family-wise error rate ``alpha``
    where its adjusted p is at most ``alpha``; no assumption on how the
    tests depend on each other."""
    out = [1.0] * len(p)
    run = 0.0
    for k, i in enumerate(sorted(range(len(p)), key=lambda j: p[j])):
        run = max(run, min(1.0, (len(p) - k) * p[i]))
        out[i] = run
    return out


def family_table(
    named: Sequence[tuple[str, dict[str, Any]]],
    alpha: float = ALPHA,
    title: str | None = None,
) -> tuple[str, list[dict[str, Any]]]:
    """The comparisons of one table taken as one family: a Markdown table, a
    row per comparison with a Mann–Whitney p (each :meth:`Comparison.row`,
    named by which scores it compared), its Holm-adjusted p and whether it
    holds at family-wise level ``alpha``; and those rows, JSON-able.
    ``title`` names the family (default: all N comparisons above)."""
    tested = [(w, c) for w, c in named if c["p"] is not None]
    adjusted = holm([c["p"] for _, c in tested])
    rows = [
        {
            "a": c["a"],
            "b": c["b"],
            "where": w,
            "p": c["p"],
            "p_holm": q,
            "holds": q <= alpha,
        }
        for (w, c), q in zip(tested, adjusted, strict=True)
    ]
    lines = [
        f"{title or f'All {len(rows)} comparisons above as one family'} "
        "(Holm–Bonferroni; "
        f"a comparison holds at a family-wise error rate of {_g(alpha)} where "
        "its adjusted p is at most that):",
        "",
        "| pair | scores | Mann–Whitney p | Holm p | holds |",
        "| --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        held = "yes" if r["holds"] else "no"
        lines.append(
            f"| {r['a']} - {r['b']} | {r['where']} | {p_text(r['p'])} | "
            f"{p_text(r['p_holm'])} | {held} |"
        )
    return "\n".join(lines), rows
