"""``present.ranktests``: the exact null distributions, Mann–Whitney,
Hodges–Lehmann and TOST, each against a count by hand or SciPy's exact test."""

import itertools

import numpy as np
import pytest

from helpers import HW_X, HW_Y
from locustjump.present.ranktests import (
    EXACT_MAX,
    _u_cdf,
    hodges_lehmann,
    mann_whitney,
    tost,
    u_null_distribution,
)

scipy_stats = pytest.importorskip("scipy.stats")


def _brute_u(m: int, n: int) -> np.ndarray:
    """P(U = u) by listing every placement of a's m values among m + n ranks."""
    counts = np.zeros(m * n + 1)
    for ranks in itertools.combinations(range(m + n), m):
        # an a at pooled rank r (0-based) with i a's below it beats r - i b's
        counts[sum(r - i for i, r in enumerate(ranks))] += 1
    return counts / counts.sum()


@pytest.mark.parametrize("m,n", [(1, 1), (2, 3), (4, 4), (5, 3), (6, 7), (10, 5)])
def test_u_null_distribution_is_the_counted_one(m, n):
    np.testing.assert_allclose(u_null_distribution(m, n), _brute_u(m, n), rtol=1e-12)


@pytest.mark.parametrize("m,n", [(2, 2), (3, 5), (6, 6), (7, 4), (9, 12), (20, 15)])
def test_u_null_distribution_gives_scipys_exact_p_values(m, n):
    rng = np.random.default_rng(m * 100 + n)
    cdf = np.cumsum(u_null_distribution(m, n))
    for _ in range(5):
        a, b = rng.normal(size=m), rng.normal(0.5, size=n)  # no ties
        u = int(scipy_stats.mannwhitneyu(a, b, method="exact").statistic)
        above = 1 - cdf[u - 1] if u else 1.0
        for alternative, ours in (("less", cdf[u]), ("greater", above)):
            theirs = scipy_stats.mannwhitneyu(
                a, b, alternative=alternative, method="exact"
            ).pvalue
            assert ours == pytest.approx(theirs, rel=1e-9, abs=1e-15)


def test_hodges_lehmann_by_hand():
    # a - b = 10 i - j for a = 10 i, b = j (i, j = 1..6): 36 distinct
    # differences in blocks of six, D(1..6) = 4..9, D(7..12) = 14..19, ...,
    # D(31..36) = 54..59. Median: (D(18) + D(19)) / 2 = (29 + 34) / 2 = 31.5.
    # U's null distribution for 6 vs 6 (C(12, 6) = 924 placements): P(U = u)
    # = partitions of u into at most 6 parts of at most 6, for u = 0..6:
    # 1, 1, 2, 3, 5, 7, 11, so P(U <= 5) = 19/924 = 0.0206 < 0.025 <=
    # P(U <= 6) = 30/924 = 0.0325: k = 6, the interval is [D(6), D(31)] =
    # [9, 54], its coverage 1 - 2 * 19/924 = 0.959.
    a, b = [10, 20, 30, 40, 50, 60], [1, 2, 3, 4, 5, 6]
    assert hodges_lehmann(a, b) == (31.5, 9.0, 54.0)
    assert hodges_lehmann(b, a) == (-31.5, -54.0, -9.0)
    # 4 vs 5 (126 placements): P(U <= u) = 1, 2, 4 /126 for u = 0, 1, 2
    # (partitions of u into at most 4 parts of at most 5), so P(U <= 1) =
    # 0.0159 < 0.025 <= 0.0317: k = 2, [D(2), D(19)] of the 20 differences
    # 10 i - j (i = 1..4, j = 1..5), blocks 5..9, 15..19, 25..29, 35..39:
    # D(2) = 6, D(19) = 38; median (D(10) + D(11)) / 2 = (19 + 25) / 2 = 22
    assert hodges_lehmann([10, 20, 30, 40], [1, 2, 3, 4, 5]) == (22.0, 6.0, 38.0)


def test_the_interval_is_the_shifts_the_exact_test_keeps():
    # Bauer (1972): the interval holds exactly the shifts d for which the
    # exact two-sided test of a - d against b does not reject at 5 %
    shift, low, high = hodges_lehmann(HW_X, HW_Y)
    d = np.unique(np.subtract.outer(HW_X, HW_Y))
    mids = (d[1:] + d[:-1]) / 2  # between differences: no ties
    for t in mids:
        p = scipy_stats.mannwhitneyu(np.array(HW_X) - t, HW_Y, method="exact").pvalue
        assert (p >= 0.05) == (low < t < high), t


@pytest.mark.parametrize("d", [-3.0, 0.0, 0.7, 25.0])
def test_a_pure_shift_lies_in_its_interval(d):
    rng = np.random.default_rng(7)
    for m, n in ((5, 5), (8, 12), (60, 55)):  # exact, exact, normal approximation
        b = rng.gamma(2.0, size=n)
        a = rng.choice(b, size=m) + d + rng.normal(0, 1e-9, size=m)
        shift, low, high = hodges_lehmann(a, b)
        assert low <= d <= high and low <= shift <= high
        # a sample against itself shifted: the estimate is the shift itself
        assert hodges_lehmann(b + d, b)[0] == pytest.approx(d)


def test_tost():
    rng = np.random.default_rng(3)
    a = rng.normal(10, 1, size=40)
    assert tost(a, a.copy(), 1.0) < 1e-4  # identical: equivalent within 1 sd
    assert tost(a, a + 5, 1.0) > 0.5  # 5 apart: not within 1
    # a 1.5 shift is outside +-1 on one side only: that side decides
    p = tost(a + 1.5, a, 1.0)
    exact = scipy_stats.mannwhitneyu(a + 0.5, a, alternative="less", method="exact")
    assert p == pytest.approx(exact.pvalue, rel=1e-12, abs=0) and p > 0.9


def _brute_p(x, y, alternative):
    """p of the rank sum of ``x`` over every split of the pooled midranks."""
    both = np.concatenate([x, y])
    r = scipy_stats.rankdata(both)
    obs = r[: len(x)].sum()
    sums = np.array([r[list(c)].sum() for c in itertools.combinations(
        range(both.size), len(x))])  # fmt: skip
    low, high = np.mean(sums <= obs + 1e-9), np.mean(sums >= obs - 1e-9)
    return {"greater": high, "less": low, "two-sided": min(1, 2 * min(low, high))}[
        alternative
    ]


@pytest.mark.parametrize("alternative", ["two-sided", "greater", "less"])
def test_mann_whitney_is_exact_given_the_ties(alternative):
    """Every split of the pooled values counted, ties taking their midrank;
    without ties SciPy's exact test; U as SciPy counts it."""
    rng = np.random.default_rng(7)
    for m, n in ((2, 3), (3, 3), (4, 5), (6, 4), (7, 7)):
        tied = rng.integers(0, 4, m).astype(float), rng.integers(0, 4, n).astype(float)
        u, p = mann_whitney(*tied, alternative)
        assert p == pytest.approx(_brute_p(*tied, alternative), rel=1e-12, abs=1e-15)
        assert u == scipy_stats.mannwhitneyu(*tied, alternative=alternative).statistic
        x, y = rng.normal(size=m), rng.normal(size=n)
        theirs = scipy_stats.mannwhitneyu(x, y, alternative=alternative, method="exact")
        assert mann_whitney(x, y, alternative) == pytest.approx(
            (theirs.statistic, theirs.pvalue), rel=1e-12
        )


@pytest.mark.parametrize("alternative", ["two-sided", "greater", "less"])
def test_mann_whitney_is_exact_up_to_exact_max_and_scipys_approximation_beyond(
    alternative,
):
    """At EXACT_MAX values a sample SciPy's exact test (no ties); one more,
    SciPy's normal approximation with its tie correction (ties here)."""
    rng = np.random.default_rng(11)
    x, y = rng.normal(size=EXACT_MAX), rng.normal(0.3, 1, size=EXACT_MAX)
    theirs = scipy_stats.mannwhitneyu(x, y, alternative=alternative, method="exact")
    assert mann_whitney(x, y, alternative) == pytest.approx(
        (theirs.statistic, theirs.pvalue), rel=1e-9
    )
    x, y = rng.integers(0, 30, EXACT_MAX + 1), rng.integers(2, 32, EXACT_MAX + 1)
    theirs = scipy_stats.mannwhitneyu(
        x, y, alternative=alternative, method="asymptotic"
    )
    assert mann_whitney(x, y, alternative) == (theirs.statistic, theirs.pvalue)
    exact = mann_whitney(x[:EXACT_MAX], y[:EXACT_MAX], alternative)[1]
    assert exact == pytest.approx(
        _perm_p(x[:EXACT_MAX], y[:EXACT_MAX], alternative), abs=0.02
    )


def _perm_p(x, y, alternative, n=4000):
    """A Monte Carlo check of an exact p too large to count (seeded)."""
    rng = np.random.default_rng(0)
    both = np.concatenate([x, y]).astype(float)
    r = scipy_stats.rankdata(both)
    obs = r[: len(x)].sum()
    sums = np.array([rng.permutation(r)[: len(x)].sum() for _ in range(n)])
    low, high = np.mean(sums <= obs + 1e-9), np.mean(sums >= obs - 1e-9)
    return {"greater": high, "less": low, "two-sided": min(1, 2 * min(low, high))}[
        alternative
    ]


def test_the_normal_approximation_beyond_exact_max_matches_the_count():
    # 60 vs 55 is past EXACT_MAX: the interval comes from the normal
    # approximation; its index k must agree with the exact count's to +-1.
    # a_i = 1000 i, b_j = j: every difference distinct, their order known
    a, b = 1000.0 * np.arange(1, 61), np.arange(1.0, 56)
    d = np.sort(np.subtract.outer(a, b).ravel())
    _, low, high = hodges_lehmann(a, b)
    k = int(np.searchsorted(d, low)) + 1
    assert d[d.size - k] == high  # symmetric order statistics
    exact = int(np.count_nonzero(np.cumsum(u_null_distribution(60, 55)) < 0.025))
    assert abs(k - exact) <= 1 and exact > 1000


def test_the_null_cdf_is_exact_up_to_exact_max_and_close_beyond():
    """P(U <= u) for u = 0 ... m*n: counted up to EXACT_MAX values a group,
    beyond it the normal approximation with its continuity correction,
    within 0.001 of the count (without the correction, or with it on the
    wrong side, 0.003)."""
    assert np.array_equal(_u_cdf(EXACT_MAX, 3), np.cumsum(u_null_distribution(50, 3)))
    for m, n in ((EXACT_MAX + 1, EXACT_MAX + 1), (60, 55)):
        approx, exact = _u_cdf(m, n), np.cumsum(u_null_distribution(m, n))
        assert approx.shape == exact.shape == (m * n + 1,)
        assert np.abs(approx - exact).max() < 0.001
