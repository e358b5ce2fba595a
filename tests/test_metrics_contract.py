"""metrics.csv's contract, function by function (rundir/metrics.py): what a
well-formed file reads as, the one-line error for each way a file is wrong,
and what truncate_metrics keeps when a run resumes from its checkpoint.

Written against the mutants the suite let through (issue #48,
scripts/mutation.py): duplicate header names, a row with too many cells
escaping as a ValueError, negative counts, metrics ahead of the checkpoint,
the checkpoint row's width.
"""

import os
import re

import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.rundir import metrics
from locustjump.rundir.layout import METRICS_COLUMNS

HEADER = ",".join(METRICS_COLUMNS)


def row(g, best=1.5, evaluations=10, steps=300, *extra):
    return metrics.metrics_line(
        [g, best, 0.5, 0.25, evaluations, steps], 1.23456, 99.94, extra
    )


def write(path, text):
    path.write_text(text)
    return path


def exactly(message):
    return "^" + re.escape(message) + "$"


def test_a_row_is_written_with_its_wall_time_and_rate_rounded():
    assert row(3) == "3,1.5,0.5,0.25,1.2346,10,300,99.9\n"
    assert (
        row(3, 1.5, 10, 300, 0.125, 7) == "3,1.5,0.5,0.25,1.2346,10,300,99.9,0.125,7\n"
    )


def test_a_file_reads_as_one_typed_record_per_generation(tmp_path):
    p = write(
        tmp_path / "m.csv",
        HEADER
        + ",sigma\n"
        + row(1, 2.0, 10, 300, 0.5)
        + "\n"
        + row(2, 3.0, 20, 600, 0.25),
    )
    m = metrics.read_metrics(p)
    assert m.dtype.names == (*METRICS_COLUMNS, "sigma")
    assert m["generation"].dtype == np.int64 and m["evaluations"].dtype == np.int64
    assert m["control_steps"].dtype == np.int64 and m["best"].dtype == np.float64
    np.testing.assert_array_equal(m["generation"], [1, 2])
    np.testing.assert_array_equal(m["best"], [2.0, 3.0])
    np.testing.assert_array_equal(m["sigma"], [0.5, 0.25])
    assert metrics.generations_done(tmp_path) == 0  # no metrics.csv there
    write(tmp_path / "metrics.csv", p.read_text())
    assert metrics.generations_done(tmp_path) == 2


def test_absent_or_header_only_is_empty_and_a_cut_short_last_line_is_left_out(tmp_path):
    assert len(metrics.read_metrics(tmp_path / "none.csv")) == 0
    m = metrics.read_metrics(write(tmp_path / "h.csv", HEADER + "\n"))
    assert len(m) == 0 and m.dtype.names == METRICS_COLUMNS
    cut = write(tmp_path / "c.csv", HEADER + "\n" + row(1) + row(2)[:-1])
    np.testing.assert_array_equal(metrics.read_metrics(cut)["generation"], [1])
    assert len(metrics.read_metrics(write(tmp_path / "e.csv", ""))) == 0
    assert len(metrics.read_metrics(write(tmp_path / "x.csv", HEADER))) == 0


def test_the_memory_check_asks_for_16_times_the_file(tmp_path, monkeypatch):
    asked = []
    monkeypatch.setattr(
        metrics, "require_memory", lambda n, what: asked.append((n, what))
    )
    p = write(tmp_path / "m.csv", HEADER + "\n")
    metrics.read_metrics(p)
    assert asked == [(16 * len(HEADER + "\n"), str(p))]


@pytest.mark.parametrize(
    "text, message",
    [
        # the header
        (
            "generation,best\n",
            "line 1 must name the columns {h} (then the optimizer's), "
            "got 'generation,best'",
        ),
        (
            "{h},s,s\n",
            "line 1 must name the columns {h} (then the optimizer's), got '{h},s,s'",
        ),
        (
            "{h},best\n",
            "line 1 must name the columns {h} (then the optimizer's), got '{h},best'",
        ),
        # the rows
        (
            "{h}\n1,1,1,1,1,1,1,1,1\n",
            "line 2: 9 columns, the header names 8: '1,1,1,1,1,1,1,1,1'",
        ),
        (
            "{h}\n1,1,1,1,1,1,1\n",
            "line 2: 7 columns, the header names 8: '1,1,1,1,1,1,1'",
        ),
        (
            "{h}\n1.5,1,1,1,1,1,1,1\n",
            "line 2: generation must be an integer, got '1.5'",
        ),
        ("{h}\n1,x,1,1,1,1,1,1\n", "line 2: best must be a number, got 'x'"),
        ("{h}\n1,inf,1,1,1,1,1,1\n", "line 2: best must be finite, got 'inf'"),
        ("{h},sigma\n1,1,1,1,1,1,1,1,y\n", "line 2: sigma must be a number, got 'y'"),
        ("{h}\n1,1,1,1,1,-1,1,1\n", "line 2: evaluations must be >= 0, got -1"),
        ("{h}\n1,1,1,1,1,1,-5,1\n", "line 2: control_steps must be >= 0, got -5"),
        ("{h}\n2,1,1,1,1,1,1,1\n", "line 2: generation 2, expected 1"),
        (
            "{h}\n1,1,1,1,1,1,1,1\n\n1,1,1,1,1,1,1,1\n",
            "line 4: generation 1, expected 2",
        ),
    ],
)
def test_each_malformed_file_is_one_line_naming_file_line_and_cell(
    tmp_path, text, message
):
    p = write(tmp_path / "m.csv", text.replace("{h}", HEADER))
    with pytest.raises(
        UserError, match=exactly(f"{p}: " + message.replace("{h}", HEADER))
    ):
        metrics.read_metrics(p)


def test_counts_of_zero_and_optimizer_columns_that_are_not_finite_are_fine(tmp_path):
    p = write(tmp_path / "m.csv", HEADER + ",sigma\n1,1,1,1,1,0,0,1,nan\n")
    m = metrics.read_metrics(p)
    assert m["evaluations"][0] == 0 and np.isnan(m["sigma"][0])


def test_a_file_that_is_not_a_metrics_file(tmp_path):
    with pytest.raises(
        UserError,
        match=exactly(
            f"{tmp_path}: is a directory, not a regular file; expected a metrics file"
        ),
    ):
        metrics.read_metrics(tmp_path)
    p = tmp_path / "b.csv"
    p.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(
        UserError, match=exactly(f"{p}: not a metrics file (not UTF-8 text)")
    ):
        metrics.read_metrics(p)


def test_parse_row_checks_the_generation_only_when_asked():
    names = METRICS_COLUMNS
    assert metrics.parse_row("4,1,2,3,4,5,6,7\n", names, "w") == (
        4,
        1.0,
        2.0,
        3.0,
        4.0,
        5,
        6,
        7.0,
    )
    with pytest.raises(UserError, match=exactly("w: generation 4, expected 3")):
        metrics.parse_row("4,1,2,3,4,5,6,7", names, "w", 3)


def test_extra_columns_are_read_from_a_complete_header(tmp_path):
    assert metrics.metrics_extra_columns(
        write(tmp_path / "a.csv", HEADER + ",s,c\n")
    ) == (
        "s",
        "c",
    )
    assert metrics.metrics_extra_columns(write(tmp_path / "b.csv", HEADER + "\n")) == ()
    assert metrics.metrics_extra_columns(write(tmp_path / "c.csv", HEADER)) is None
    assert (
        metrics.metrics_extra_columns(write(tmp_path / "d.csv", "gen,best\n")) is None
    )
    assert metrics.metrics_extra_columns(tmp_path / "none.csv") is None
    bad = tmp_path / "e.csv"
    bad.write_bytes(b"\xff\xfe\n")
    assert metrics.metrics_extra_columns(bad) is None


# --- truncate_metrics: resuming from the checkpoint of generation g ---------------


def test_rows_ahead_of_the_checkpoint_are_refused(tmp_path):
    # the checkpoint is written before its row: more rows than it holds mean
    # it was lost or replaced, and resuming would rewrite the file
    text = HEADER + "\n" + row(1) + row(2) + row(3)
    p = write(tmp_path / "m.csv", text)
    with pytest.raises(
        UserError,
        match=exactly(
            f"{p}: holds 3 generations but checkpoint.npz holds only 2 "
            f"(nothing changed)"
        ),
    ):
        metrics.truncate_metrics(p, 2, row(2))
    assert p.read_text() == text


def test_a_missing_last_row_is_the_checkpoint_s(tmp_path):
    p = write(tmp_path / "m.csv", HEADER + ",sigma\n" + row(1, 1, 10, 300, 0.5) + "2,1")
    metrics.truncate_metrics(p, 2, row(2, 1, 10, 300, 0.25), ("sigma",))
    assert p.read_text() == HEADER + ",sigma\n" + row(1, 1, 10, 300, 0.5) + row(
        2, 1, 10, 300, 0.25
    )
    q = write(tmp_path / "q.csv", "")
    metrics.truncate_metrics(q, 1, row(1))
    assert q.read_text() == HEADER + "\n" + row(1)
    r = write(tmp_path / "r.csv", HEADER + "\n")
    metrics.truncate_metrics(r, 0, "")
    assert r.read_text() == HEADER + "\n"
    s = write(tmp_path / "s.csv", HEADER + "\n" + row(1))
    with pytest.raises(
        UserError,
        match=exactly(
            f"{s}: holds 1 generations but checkpoint.npz is missing (nothing changed)"
        ),
    ):
        metrics.truncate_metrics(s, 0, "")


def test_the_checkpoint_s_row_must_have_the_run_s_columns(tmp_path):
    p = write(tmp_path / "m.csv", HEADER + ",sigma\n" + row(1, 1, 10, 300, 0.5))
    where = f"{p}: the checkpoint's row"
    with pytest.raises(UserError, match=exactly(f"{where} has 8 columns, not 9")):
        metrics.truncate_metrics(p, 2, row(2), ("sigma",))
    with pytest.raises(UserError, match=exactly(f"{where} has 10 columns, not 9")):
        metrics.truncate_metrics(p, 2, row(2, 1, 10, 300, 0.5, 1.0), ("sigma",))
    with pytest.raises(UserError, match=exactly(f"{where}: generation 3, expected 2")):
        metrics.truncate_metrics(p, 2, row(3, 1, 10, 300, 0.5), ("sigma",))
    assert p.read_text() == HEADER + ",sigma\n" + row(1, 1, 10, 300, 0.5)


def test_a_row_that_is_not_the_checkpoint_s_is_another_run_s(tmp_path):
    text = HEADER + "\n" + row(1) + row(2)
    p = write(tmp_path / "m.csv", text)
    metrics.truncate_metrics(p, 2, row(2).replace("1.2346", "7.0"))  # wall time differs
    assert p.read_text() == text
    for other in (row(2, 9.0), row(2, 1.5, 11), row(2, 1.5, 10, 301)):
        with pytest.raises(
            UserError,
            match=exactly(
                f"{p}: the row of generation 2 is not the checkpoint's "
                "(another run's metrics?)"
            ),
        ):
            metrics.truncate_metrics(p, 2, other)
    with pytest.raises(UserError, match="not the checkpoint's"):
        metrics.truncate_metrics(p, 2, "2,1.5,0.5,0.3,1,10,300,1\n")  # std differs
    with pytest.raises(UserError, match="not the checkpoint's"):
        metrics.truncate_metrics(p, 2, "2,1.5,0.6,0.25,1,10,300,1\n")  # mean differs
    assert p.read_text() == text


def test_too_few_rows_for_the_checkpoint_or_other_columns_are_refused(tmp_path):
    p = write(tmp_path / "m.csv", HEADER + "\n" + row(1))
    with pytest.raises(
        UserError,
        match=exactly(f"{p}: holds 1 rows for the 3 generations of the checkpoint"),
    ):
        metrics.truncate_metrics(p, 3, row(3))
    with pytest.raises(
        UserError,
        match=exactly(f"{p}: its columns {HEADER} are not the run's {HEADER},sigma"),
    ):
        metrics.truncate_metrics(p, 1, row(1, 1.5, 10, 300, 0.5), ("sigma",))
    assert p.read_text() == HEADER + "\n" + row(1)


def test_a_last_line_ending_in_a_lone_carriage_return_is_cut_short(tmp_path):
    # CRLF lines read as lines; a write cut between \r and \n is cut short
    p = write(tmp_path / "m.csv", "")
    p.write_bytes(
        (HEADER + "\r\n" + row(1)[:-1] + "\r\n" + row(2)[:-1] + "\r").encode()
    )
    np.testing.assert_array_equal(metrics.read_metrics(p)["generation"], [1])


def test_a_path_that_cannot_be_read_says_why(tmp_path):
    p = write(tmp_path / "file", "") / "metrics.csv"  # under a file: absent
    assert len(metrics.read_metrics(p)) == 0
    q = write(tmp_path / "q.csv", HEADER + "\n")
    q.chmod(0)
    if os.access(q, os.R_OK):  # root reads it all the same
        return
    with pytest.raises(UserError, match=re.escape(f"{q}: cannot be read")):
        metrics.read_metrics(q)


def test_long_cells_and_lines_are_quoted_to_40_and_80_characters(tmp_path):
    long = "9" * 100
    p = write(tmp_path / "a.csv", f"{long}\n")
    with pytest.raises(UserError, match=re.escape(f"got {long[:80]!r}")):
        metrics.read_metrics(p)
    q = write(tmp_path / "b.csv", f"{HEADER}\n{long},{long}\n")
    message = (
        f"{q}: line 2: 2 columns, the header names 8: {(long + ',' + long)[:80]!r}"
    )
    with pytest.raises(UserError, match=exactly(message)):
        metrics.read_metrics(q)
    r = write(tmp_path / "c.csv", f"{HEADER}\n1,{'x' * 50},1,1,1,1,1,1\n")
    message = f"{r}: line 2: best must be a number, got {'x' * 40!r}"
    with pytest.raises(UserError, match=exactly(message)):
        metrics.read_metrics(r)


def test_generations_done_is_the_last_row_s(tmp_path):
    write(tmp_path / "metrics.csv", HEADER + "\n" + row(1) + row(2) + row(3))
    assert metrics.generations_done(tmp_path) == 3


def test_a_header_longer_than_4096_characters_is_not_read_for_its_columns(tmp_path):
    extra = ",c" * 3000
    line = (HEADER + extra)[:4096]
    assert len(line) == 4096
    p = write(tmp_path / "m.csv", line + "\n")
    assert metrics.metrics_extra_columns(p) is None
    q = write(tmp_path / "n.csv", line[:4095] + "\n")
    assert metrics.metrics_extra_columns(q) == tuple(line[:4095].split(",")[8:])


def test_a_metrics_path_that_is_not_a_file_is_named_as_one(tmp_path):
    (tmp_path / "m.csv").mkdir()
    message = (
        f"{tmp_path / 'm.csv'}: is a directory, not a regular file; "
        "expected a metrics file"
    )
    with pytest.raises(UserError, match="^" + re.escape(message) + "$"):
        metrics.metrics_extra_columns(tmp_path / "m.csv")
