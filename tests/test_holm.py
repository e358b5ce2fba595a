"""``present.stats.holm`` and ``family_table``: a study table's comparisons
taken as one family (Holm-Bonferroni adjusted p values)."""

from hypothesis import given
from hypothesis import strategies as st

from locustjump.present.stats import family_table, holm


def test_holm_on_a_worked_example():
    # sorted 0.01, 0.03, 0.04: 3 x 0.01, 2 x 0.03, then 1 x 0.04 lifted to
    # the 0.06 before it (adjusted p values never fall with rank)
    assert holm([0.01, 0.04, 0.03]) == [0.03, 0.06, 0.06]
    assert holm([0.5, 0.01]) == [0.5, 0.02]
    assert holm([0.6, 0.7]) == [1.0, 1.0]  # capped at 1
    assert holm([0.02]) == [0.02] and holm([]) == []
    # the issue #45 table's four p values: none holds at 0.05 together
    got = holm([0.0367, 0.0502, 0.389, 0.126])
    assert [round(q, 4) for q in got] == [0.1468, 0.1506, 0.389, 0.252]


def _rejected(p, alpha):
    """Holm's step-down rule itself: reject the k-th smallest p while it is
    at most alpha / (m - k + 1); stop at the first that is not."""
    out = set()
    for k, i in enumerate(sorted(range(len(p)), key=lambda j: p[j])):
        if p[i] > alpha / (len(p) - k):
            break
        out.add(i)
    return out


@given(
    st.lists(st.floats(0, 1), max_size=12),
    st.sampled_from([0.01, 0.05, 0.1, 0.5]),
)
def test_adjusted_p_values_reject_what_the_step_down_rule_rejects(p, alpha):
    adjusted = holm(p)
    assert {i for i, q in enumerate(adjusted) if q <= alpha} == _rejected(p, alpha)
    assert all(p_i <= q <= 1.0 for p_i, q in zip(p, adjusted, strict=True))


def _row(a, p):
    return {"a": a, "b": "ref", "p": p}


def test_family_table_rows_and_text():
    named = [("3 substeps", _row("x", 0.01)), ("12 substeps", _row("x", None)),
             ("3 substeps, height term", _row("y", 0.04))]  # fmt: skip
    text, rows = family_table(named)
    # a comparison without a p (too few runs) is not in the family
    assert rows == [
        {"a": "x", "b": "ref", "where": "3 substeps", "p": 0.01, "p_holm": 0.02,
         "holds": True},
        {"a": "y", "b": "ref", "where": "3 substeps, height term", "p": 0.04,
         "p_holm": 0.04, "holds": True},
    ]  # fmt: skip
    lines = text.splitlines()
    assert lines[0] == (
        "All 2 comparisons above as one family (Holm–Bonferroni; a comparison "
        "holds at a family-wise error rate of 0.05 where its adjusted p is at "
        "most that):"
    )
    assert lines[2:] == [
        "| pair | scores | Mann–Whitney p | Holm p | holds |",
        "| --- | --- | --- | --- | --- |",
        "| x - ref | 3 substeps | 0.01 | 0.02 | yes |",
        "| y - ref | 3 substeps, height term | 0.04 | 0.04 | yes |",
    ]
    assert lines[1] == ""
    text, strict = family_table(named, alpha=0.03)
    assert [r["holds"] for r in strict] == [True, False]
    last = "| y - ref | 3 substeps, height term | 0.04 | 0.04 | no |"
    assert text.splitlines()[-1] == last
    _, edge = family_table([("s", _row("x", 0.025)), ("t", _row("y", 0.5))])
    assert edge[0]["p_holm"] == 0.05 and edge[0]["holds"]  # at most alpha holds
