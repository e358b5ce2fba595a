"""``scripts/study_pairing.py``: each comparison's scores paired by seed,
their correlation and the width a paired interval would have."""

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy.stats")

REPO = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location(
    "study_pairing", REPO / "scripts" / "study_pairing.py"
)
pairing = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pairing)


def _table(a, b, *, seeds_b=None):
    """A table.json of arms x (label X) and y (label Y), scored at 3 substeps."""
    runs = [{"arm": "x", "seed": s, "at": {"3": {"score": v}}} for s, v in enumerate(a)]
    runs += [
        {"arm": "y", "seed": s, "at": {"3": {"score": v}}}
        for s, v in zip(seeds_b or range(len(b)), b, strict=True)
    ]
    return {
        "runs": runs,
        "arms": {"x": {"label": "X"}, "y": {"label": "Y"}},
        "pairs": {"3": [{"a": "X", "b": "Y"}]},
    }


def test_scores_go_together_only_on_shared_seeds():
    a = [1.0, 2.0, 3.0, 4.0, 5.0]
    b = [2.0, 4.1, 5.9, 8.2, 9.8, 100.0]  # seed 6 has no partner in arm x
    (row,) = pairing.pairing_rows(_table(a, b, seeds_b=[0, 1, 2, 3, 4, 6]))
    assert (row["a"], row["b"], row["n"]) == ("X", "Y", 5)
    assert row["r"] == pytest.approx(np.corrcoef(a, b[:5])[0, 1])
    assert row["low"] < row["r"] < row["high"]
    assert row["rho"] == pytest.approx(1.0)
    d = np.subtract(a, b[:5])
    assert row["ratio"] == pytest.approx(
        d.std(ddof=1) / math.sqrt(np.var(a, ddof=1) + np.var(b[:5], ddof=1))
    )
    assert row["ratio"] < 0.5  # together: a paired interval is far narrower


def test_uncorrelated_scores_gain_nothing_by_pairing():
    a, b = [1.0, -1.0, 1.0, -1.0], [1.0, 1.0, -1.0, -1.0]  # r = 0 exactly
    (row,) = pairing.pairing_rows(_table(a, b))
    assert row["r"] == pytest.approx(0.0, abs=1e-12)
    assert row["ratio"] == pytest.approx(1.0)


def test_too_few_seeds_or_no_spread_give_no_correlation():
    for a, b in (([1.0, 2.0], [3.0, 4.0]), ([1.0, 1.0, 1.0], [1.0, 2.0, 3.0])):
        (row,) = pairing.pairing_rows(_table(a, b))
        assert "r" not in row
        assert "too few seeds or no spread" in pairing.render([row])


def test_the_shipped_debris_study(capsys):
    d = REPO / "results" / "studies" / "debris-composition-5seeds"
    assert pairing.main([str(d)]) == 0
    out = capsys.readouterr().out.splitlines()
    table = json.loads((d / "table.json").read_text())
    assert len(out) == 2 + sum(len(p) for p in table["pairs"].values())
    assert out[2].startswith("| 3 | the paper's pipeline on debris - one network | 5 |")


def test_a_missing_table_is_one_line_and_exit_2(tmp_path, capsys):
    assert pairing.main([str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "no such table" in err
