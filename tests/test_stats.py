"""``present.stats``: comparisons, power, verdicts and tables, on the rank
tests of ``present.ranktests`` (tested in ``tests/test_ranktests.py``)."""

import json
import math

import numpy as np
import pytest

from helpers import HW_X, HW_Y
from locustjump.present.ranktests import (
    Sample,
    hodges_lehmann,
    mann_whitney,
    tost,
    u_null_distribution,
)
from locustjump.present.stats import (
    Comparison,
    compare_samples,
    p_text,
    pairs_table,
    pooled_spread,
    seeds_for_power,
    verdict,
)

scipy_stats = pytest.importorskip("scipy.stats")


def test_hodges_lehmann_on_hollander_and_wolfe():
    # SAS NPAR1WAY prints for these data the shift 0.305 (term - early) and
    # the exact two-sided Mann-Whitney p 0.2544; its (asymptotic) 95 % limits
    # are [-0.17, 0.76]. The exact interval: U of 10 vs 5 (C(15, 5) = 3003
    # placements) counts partitions of u into at most 5 parts: 1, 1, 2, 3, 5,
    # 7, 10, 13, 18, 23 for u = 0..9, so P(U <= 8) = 60/3003 = 0.0200 < 0.025
    # <= P(U <= 9) = 83/3003 = 0.0276: k = 9, [D(9), D(42)] of the 50 sorted
    # differences (-0.48, -0.42, -0.41, -0.38, -0.35, -0.32, -0.17, -0.17,
    # -0.15, ..., 0.74, 0.76, 0.76, 0.90, 0.99, 1.01, 1.01, 1.03, 1.15, 1.17)
    # = [-0.15, 0.76], coverage 1 - 2 * 60/3003 = 0.96. R's
    # wilcox.test(x, y, conf.int = TRUE) takes the same k = qwilcox(0.025,
    # 10, 5), the smallest u with P(U <= u) >= 0.025 (not run here: no R).
    cdf = np.cumsum(u_null_distribution(10, 5))
    assert np.round(cdf[:10] * 3003).tolist() == [1, 2, 4, 7, 12, 19, 29, 42, 60, 83]
    assert cdf[8] < 0.025 <= cdf[9]
    shift, low, high = hodges_lehmann(HW_X, HW_Y)
    assert (shift, low, high) == pytest.approx((0.305, -0.15, 0.76))
    c = compare_samples(HW_X, HW_Y)
    assert (c.u, c.p) == pytest.approx((35, 0.2544), abs=1e-4)


def test_no_interval_where_too_few_values():
    # 3 vs 3: P(U = 0) = 1/20 > 0.025, even [D(1), D(9)] covers only 90 %
    assert hodges_lehmann([1, 2, 3], [4, 5, 6]) == (-3.0, -math.inf, math.inf)
    # at 80 %: P(U = 0) = 0.05 < 0.1 <= P(U <= 1) = 0.1 (equal: k = 1, as
    # R's qwilcox), so [D(1), D(9)] = [1 - 6, 3 - 4]
    assert hodges_lehmann([1, 2, 3], [4, 5, 6], confidence=0.8) == (-3.0, -5.0, -1.0)
    c = compare_samples([1, 2], [5, 6])
    assert c.verdict == (
        "no evidence either way: too few runs for a 95 % interval (2 and 2)"
    )
    assert c.row()["low"] is None and c.row()["high"] is None


def test_the_p_value_and_the_interval_agree():
    """9 against 12 without ties: the interval excludes 0, so p < 0.05 (SciPy's
    default, the normal approximation above 8 a sample, says 0.0507); 3
    against 3 with a tie cannot reach p < 0.05 (the approximation: 0.038)."""
    x = [0, 1, 2, 3, 4, 5, 8, 19, 20]
    y = [6, 7, *range(9, 19)]
    c = compare_samples(x, y)
    assert c.high < 0 and c.p == pytest.approx(0.0490729085156, rel=1e-9)
    assert tost([0, 0, 1], [0, 0.5, 1], 5.0) == pytest.approx(0.05)
    assert compare_samples([0, 0, 1], [0, 0.5, 1], margin=5.0).verdict.startswith(
        "no evidence either way"
    )


def test_seeds_for_power_by_hand():
    # z(0.975) + z(0.8) = 1.959964 + 0.841621 = 2.801585, squared 7.848879;
    # spread 1, delta 1: 2 * 7.848879 / (3/pi = 0.954930) = 16.439 -> 17
    # plus the small-sample term z(0.975)^2 / 4 = 0.960: 17.40 -> 18
    assert seeds_for_power(1.0, 1.0) == 18
    assert seeds_for_power(2.0, 1.0) == 67  # 4 * 16.439 + 0.960 = 66.72
    assert seeds_for_power(1.0, 2.0) == 6  # 16.439 / 4 + 0.960 = 5.07
    # never below 4: 3 against 3 cannot reach p = 0.05 (its least p is 0.1)
    assert seeds_for_power(0.01, 1.0) == 4
    assert seeds_for_power(0.0, 1.0) is None
    # alpha 0.01, power 0.9: (2.575829 + 1.281552)^2 = 14.879 -> 31.16,
    # + 2.575829^2 / 4 = 1.659 -> 32.82 -> 33; at least 5 (2 / C(10, 5) < 0.01)
    assert seeds_for_power(1.0, 1.0, alpha=0.01, power=0.9) == 33
    assert seeds_for_power(0.01, 1.0, alpha=0.01) == 5
    # "reach alpha" is to get below it: 3 v 3's least p, 0.1, does not reach
    # 0.1; 2 v 2's, 1/3, reaches 0.4
    assert seeds_for_power(0.01, 1.0, alpha=0.1) == 4
    assert seeds_for_power(0.01, 1.0, alpha=0.4) == 2
    # the small-sample term is z^2 / 4 (0.960), not 2z / 4 (0.980): a base of
    # 17.03 gives 17.99, so 18 seeds (17.03 + 0.980 = 18.01 would give 19)
    z = 1.959963984540054 + 0.8416212335729143
    assert seeds_for_power(math.sqrt(17.03 / (2 * z**2 / (3 / math.pi))), 1.0) == 18
    with pytest.raises(ValueError, match="delta"):
        seeds_for_power(1.0, 0.0)


def _c(low, high, p_eq=None, margin=None) -> Comparison:
    c = Comparison("cma", "rcga", 10, 10, (low + high) / 2, low, high, 0.95,
                   0.5, 50.0, margin, p_eq, None, "")  # fmt: skip
    return c


def test_each_verdict():
    assert verdict(_c(0.5, 2.0)) == "cma better than rcga"
    assert verdict(_c(-2.0, -0.5)) == "rcga better than cma"
    assert verdict(_c(-0.2, 0.3, 0.01, 1.0)) == "equivalent within ±1"
    # equivalence is not read off the interval but needs the test
    assert verdict(_c(-0.2, 0.3, 0.2, 1.0)) == (
        "no evidence either way: interval [-0.2, 0.3]"
    )
    assert verdict(_c(-0.2, 0.3)) == "no evidence either way: interval [-0.2, 0.3]"
    assert verdict(_c(0.0, 3.14159)) == "no evidence either way: interval [0, 3.14]"
    # a difference, and equivalent by the margin too: both are said
    assert verdict(_c(0.1, 0.3, 0.01, 1.0)) == "cma better than rcga, by less than 1"
    assert verdict(_c(-0.3, -0.1, 0.01, 1.0)) == (
        "rcga better than cma, by less than 1"
    )
    assert verdict(_c(0.1, 0.3, 0.2, 1.0)) == "cma better than rcga"


def test_compare_samples_end_to_end():
    rng = np.random.default_rng(0)
    base = rng.normal(100, 5, size=12)
    better = compare_samples(Sample("new", base + 30), Sample("old", base))
    assert (better.a, better.b, better.n_a) == ("new", "old", 12)
    assert better.verdict == "new better than old" and better.p < 1e-4
    assert better.margin is better.p_equivalence is better.seeds_for_power is None
    worse = compare_samples(base - 30, base, names=("x", "y"))
    assert worse.verdict == "y better than x"
    other = base + rng.normal(0, 0.1, 12)
    same = compare_samples(base, other, margin=5.0)
    assert same.verdict == "equivalent within ±5" and same.p_equivalence < 0.05
    pooled = math.sqrt((np.var(base, ddof=1) + np.var(other, ddof=1)) / 2)
    assert same.seeds_for_power == seeds_for_power(pooled, 5.0)
    row = same.row()
    assert set(row) == {f.name for f in Comparison.__dataclass_fields__.values()}
    assert json.loads(json.dumps(row, allow_nan=False)) == row
    text = pairs_table([better, same])
    lines = text.splitlines()
    assert lines[0] == (
        "| pair | n | HL shift [95 % CI] | Mann–Whitney p | TOST p vs ±5 | "
        "seeds for 80 % power | verdict |"
    )
    assert lines[2].startswith("| new - old | 12, 12 | 30 [") and lines[2].endswith(
        "| - | - | new better than old |"
    )
    assert lines[3].endswith(f"| {same.seeds_for_power} | equivalent within ±5 |")


def test_pooled_spread_feeds_the_power():
    a, b = np.array([1.0, 2, 3, 4, 5]), np.array([2.0, 4, 6, 8, 10, 12, 14])
    # variances 2.5 (4 dof) and 18.667 (6 dof): pooled (10 + 112) / 10 = 12.2;
    # 2 * 7.848879 * 12.2 / 2^2 / 0.954930 = 50.14, + 0.960 = 51.10 -> 52
    c = compare_samples(a, b, margin=2.0)
    assert c.seeds_for_power == seeds_for_power(math.sqrt(12.2), 2.0) == 52


def test_bad_input_names_the_culprit():
    with pytest.raises(ValueError, match="'lone'.*at least 2"):
        compare_samples(Sample("lone", [1.0]), Sample("many", [1.0, 2.0]))
    with pytest.raises(ValueError, match="'B'.*at least 2"):
        compare_samples([1.0, 2.0], [3.0])
    with pytest.raises(ValueError, match="'b'"):
        hodges_lehmann([1.0, 2.0], [])
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError, match="margin"):
            compare_samples([1.0, 2.0], [3.0, 4.0], margin=bad)
        with pytest.raises(ValueError, match="margin"):
            tost([1.0, 2.0], [3.0, 4.0], bad)
    with pytest.raises(ValueError, match="'a'.*not finite"):
        hodges_lehmann([1.0, math.nan], [1.0, 2.0])


def test_values_become_one_flat_float_array():
    s = Sample("s", [[1, 2], [3, 5]])
    assert s.values.dtype == np.float64 and s.values.tolist() == [1.0, 2.0, 3.0, 5.0]
    assert (s.n, s.median, s.low, s.high) == (4, 2.5, 1.0, 5.0)
    c = compare_samples([1, 2, 3], [4, 5, 6])
    assert isinstance(c.shift, float) and c.shift == -3.0
    # one outcome per seed (did it recover?) compares as 0 and 1
    assert hodges_lehmann([True, True, True], [False, True, False])[0] == 1.0


def test_the_default_names_and_the_confidence_reach_the_comparison():
    c = compare_samples(HW_X, HW_Y)
    assert (c.a, c.b, c.confidence) == ("A", "B", 0.95)
    # at 80 % the interval is the one hodges_lehmann gives at 80 %, narrower
    c80 = compare_samples(HW_X, HW_Y, confidence=0.8)
    assert (c80.shift, c80.low, c80.high) == hodges_lehmann(HW_X, HW_Y, 0.8)
    assert c.low < c80.low < c80.high < c.high and c80.confidence == 0.8
    # a margin below 1 is a margin like any other
    assert compare_samples(HW_X, HW_Y, margin=0.5).margin == 0.5


def test_the_row_keeps_every_finite_value():
    c = compare_samples(HW_X, HW_Y, margin=0.5)
    row = c.row()
    assert row == {k: getattr(c, k) for k in row}
    assert row["n_a"] == 10 and row["low"] == pytest.approx(-0.15)


def test_verdicts_at_their_boundaries():
    # an interval that reaches 0 is not evidence; a TOST p of exactly alpha
    # is not below it
    assert verdict(_c(-2.0, 0.0)) == "no evidence either way: interval [-2, 0]"
    assert verdict(_c(-0.2, 0.3, 0.05, 1.0)).startswith("no evidence either way")
    assert verdict(_c(-0.2, 0.3, 0.0499, 1.0)) == "equivalent within ±1"


def test_p_text():
    assert p_text(0.012345) == "0.0123"
    assert p_text(1.0) == "1"
    assert p_text(None) == p_text(math.nan) == "-"


def test_pairs_table_headers_and_cells():
    base = compare_samples(HW_X, HW_Y, margin=0.5)
    lines = pairs_table([base]).splitlines()
    assert lines[0] == (
        "| pair | n | HL shift [95 % CI] | Mann–Whitney p | TOST p vs ±0.5 | "
        "seeds for 80 % power | verdict |"
    )
    assert lines[1] == "| --- | --- | --- | --- | --- | --- | --- |"
    assert lines[2] == (
        f"| A - B | 10, 5 | 0.305 [-0.15, 0.76] | {p_text(base.p)} | "
        f"{p_text(base.p_equivalence)} | {base.seeds_for_power} | {base.verdict} |"
    )
    # no comparison: the default level; several levels or margins: each row
    # says its margin, the header names neither
    assert "HL shift [95 % CI]" in pairs_table([]).splitlines()[0]
    other = compare_samples(HW_X, HW_Y, margin=0.25, confidence=0.8)
    lines = pairs_table([base, other]).splitlines()
    assert "| HL shift [CI] |" in lines[0] and "| TOST p vs ±margin |" in lines[0]
    assert f"| {p_text(base.p_equivalence)} (±0.5) |" in lines[2]
    assert f"| {p_text(other.p_equivalence)} (±0.25) |" in lines[3]
    plain = compare_samples(HW_X, HW_Y)
    assert "| - | - |" in pairs_table([plain, base]).splitlines()[2]


def test_each_function_names_its_bad_sample_or_parameter():
    for f in (tost, pooled_spread, mann_whitney):
        args = (1.0,) if f is tost else ()
        with pytest.raises(ValueError, match="sample 'a' needs"):
            f([1.0], [1.0, 2.0], *args)
        with pytest.raises(ValueError, match="sample 'b' needs"):
            f([1.0, 2.0], [1.0], *args)
    with pytest.raises(ValueError, match="sample 'A' needs"):
        compare_samples([1.0], [1.0, 2.0])
    for bad in (0.0, 1.0, 1.5):
        with pytest.raises(
            ValueError, match=f"confidence must be in \\(0, 1\\), got {bad}"
        ):
            hodges_lehmann(HW_X, HW_Y, bad)
    for bad in (-1.0, math.nan):
        with pytest.raises(
            ValueError, match=f"spread must be a finite number >= 0, got {bad}"
        ):
            seeds_for_power(bad, 1.0)
    for name in ("alpha", "power"):
        for bad in (0.0, 1.0, 1.5):
            with pytest.raises(
                ValueError, match=f"{name} must be in \\(0, 1\\), got {bad}"
            ):
                seeds_for_power(1.0, 1.0, **{name: bad})
    with pytest.raises(
        ValueError, match="alternative must be two-sided, greater or less, got 'up'"
    ):
        mann_whitney(HW_X, HW_Y, "up")


def test_without_scipy_the_rank_tests_say_what_to_install(monkeypatch):
    import sys

    from locustjump.errors import UserError

    monkeypatch.setitem(sys.modules, "scipy", None)  # import scipy fails
    with pytest.raises(UserError) as e:
        compare_samples(HW_X, HW_Y, margin=1.0)  # the power needs SciPy
    assert str(e.value) == (
        "the rank tests need SciPy: pip install -e '.[study]' in the clone"
    )
