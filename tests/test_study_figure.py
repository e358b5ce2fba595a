"""``scores.png`` (present/study_figure.py): the study's answer drawn from
table.json — every run's score per arm with the arm's median, and each pair's
shift with its interval and the margin — so the figure shows the table's
numbers and no others."""

import pytest

from locustjump.errors import UserError
from locustjump.present.study_figure import draw_scores, scores_figure, shift_rows

A = {"label": "arm A", "runs": 3, "budget": {}, "flat": True}


def _pair(a, b, shift, low, high):
    return {"a": a, "b": b, "shift": shift, "low": low, "high": high}


def _data(margin=50.0):
    """Two arms at two resolutions; the height term compared at 3 substeps."""
    arms = {
        "a": {**A, "3": {"values": [1.0, 3.0, 2.0], "median": 2.0},
              "12": {"values": [5.0, 4.0, 6.0], "median": 5.0}},
        "b": {**A, "label": "arm B", "3": {"values": [11.0, 13.0], "median": 12.0},
              "12": {"values": [7.0, 8.0], "median": 7.5}},
    }  # fmt: skip
    return {
        "study": "t", "margin": margin, "arms": arms,
        "pairs": {"3": [_pair("arm A", "arm B", -10.0, -12.0, -8.0)],
                  "12": [_pair("arm A", "arm B", -2.5, None, None)]},
        "pairs_height_term": {"3": [_pair("arm A", "arm B", -5.0, -6.0, 1.0)]},
    }  # fmt: skip


def test_each_comparison_in_the_tables_order_named_by_the_arms_keys():
    data = _data()
    rows = shift_rows(data)
    assert [label for label, _ in rows] == [
        "a - b, 3 substeps",
        "a - b, 3 substeps, height term",
        "a - b, 12 substeps (no 95 % interval)",
    ]
    assert [r for _, r in rows] == [data["pairs"]["3"][0],
                                    data["pairs_height_term"]["3"][0],
                                    data["pairs"]["12"][0]]  # fmt: skip
    data["pairs"]["3"][0]["high"] = None  # one bound missing is no interval too
    assert shift_rows(data)[0][0] == "a - b, 3 substeps (no 95 % interval)"
    own = {"values": [1.0, 2.0], "median": 1.5}  # scored on each run's own scene
    data = {"study": "t", "margin": None,  # no height term compared: no key
            "arms": {"x": {**A, "None": own}, "y": {**A, "label": "Y", "None": own}},
            "pairs": {"None": [_pair("arm A", "Y", 0.0, -1.0, 1.0)]}}  # fmt: skip
    assert [label for label, _ in shift_rows(data)] == ["x - y, as trained"]


def test_the_figure_draws_the_tables_numbers():
    data = _data()
    fig = draw_scores(data)
    at3, at12, shifts = fig.axes
    for ax, key in ((at3, "3"), (at12, "12")):
        dots = [line.get_ydata().tolist() for line in ax.lines]
        assert dots == [
            data["arms"]["a"][key]["values"],
            data["arms"]["b"][key]["values"],
        ]
        medians = [c.get_segments()[0][:, 1].tolist() for c in ax.collections]
        assert medians == [[data["arms"][a][key]["median"]] * 2 for a in "ab"]
        assert [t.get_text() for t in ax.get_xticklabels()] == ["a", "b"]
        assert key in ax.get_title()
    # each shift a dot on its row; an interval a bar, none where it is infinite
    assert [line.get_xdata().tolist() for line in shifts.lines[1:]] == [
        [-10.0], [-5.0], [-2.5]]  # fmt: skip
    bars = [c.get_segments()[0].tolist() for c in shifts.collections]
    assert bars == [[[-12.0, 0.0], [-8.0, 0.0]], [[-6.0, 1.0], [1.0, 1.0]]]
    assert list(shifts.lines[0].get_xdata()) == [0, 0]  # no shift
    (band,) = shifts.patches  # the margin, +-50
    assert (band.get_x(), band.get_x() + band.get_width()) == (-50.0, 50.0)
    assert "margin, ±50" in shifts.get_xlabel()
    assert not draw_scores(_data(margin=None)).axes[-1].patches


def test_study_writes_it_as_png_and_refuses_a_format_it_cannot(tmp_path):
    path = scores_figure(_data(), tmp_path / "s.png")
    assert path.read_bytes().startswith(b"\x89PNG")
    with pytest.raises(UserError, match="figure"):
        scores_figure(_data(), tmp_path / "s.nope")
    assert not (tmp_path / "s.nope").exists()
