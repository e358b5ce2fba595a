"""A study file's ``[primary]``: the comparisons declared before the runs,
tested as their own family in the table, the rest apart as secondary
(runs/studyfile.py's ``_primary``, runs/study_pairs.py's ``families``)."""

import pytest

from helpers import user_error
from locustjump.runs import study_table as st
from locustjump.runs.studyfile import Primary, load_study
from test_study_table import _rows, _study


def _with(tmp_path, primary: str):
    path = tmp_path / "t.toml"
    _study(tmp_path)  # writes t.toml
    path.write_text(path.read_text() + "[primary]\n" + primary + "\n")
    return path


def test_a_declared_primary_is_a_family_of_its_own(tmp_path):
    """``_rows`` compares a and c with the reference b (c has no height term,
    so none on it): 3 seeds a side completely apart, Mann–Whitney p 0.1 each."""
    study = load_study(_with(tmp_path, 'pairs = [["b", "a"]]\nsubsteps = 12'))
    assert study.primary == Primary((("b", "a"),), (12,), "full")
    md, data = st.make_table(study, _rows())
    assert "Declared primary (the study file's [primary]): 1 comparison, one " \
        "family (Holm–Bonferroni;" in md  # fmt: skip
    assert "|\n\nThe other 3, secondary, as one family (Holm" in md
    assert "|\n\nDeclared primary (" in md  # each family after a blank line
    assert "as one family (Holm–Bonferroni" in md and "All 4" not in md
    got = [(r["a"], r["where"], r["p_holm"], r["primary"]) for r in data["holm"]]
    assert got == [
        ("arm A", "12 substeps", pytest.approx(0.1), True),  # alone: p itself
        ("arm A", "3 substeps", pytest.approx(0.3), False),  # Holm over 3
        ("arm C", "3 substeps", pytest.approx(0.3), False),
        ("arm C", "12 substeps", pytest.approx(0.3), False),
    ]
    plain, plain_data = st.make_table(_study(tmp_path), _rows())  # none declared
    assert [r["p_holm"] for r in plain_data["holm"]] == [pytest.approx(0.4)] * 4
    assert "primary" not in plain_data["holm"][0] and "All 4 comparisons" in plain


def test_the_plan_says_what_is_primary(tmp_path, monkeypatch):
    import locustjump.runs.study_plan as plan

    monkeypatch.setattr(plan, "throughput", lambda *a, **k: 1000.0)
    path = _with(tmp_path, 'pairs = [["a", "b"], ["c", "b"]]\nscore = "height-term"')
    text = plan.dry_run(load_study(path), backend=None)
    assert "\nDeclared primary: a - b; c - b (3 substeps, the height term); the " \
        "table's other comparisons are secondary." in text  # fmt: skip
    path.write_text(path.read_text().replace('score = "height-term"', "substeps = 12"))
    assert "(12 substeps, the full fitness)" in load_study(path).primary.describe()
    path.write_text(path.read_text().replace("substeps = 12", "substeps = [12, 3]"))
    both = load_study(path).primary
    assert (
        both.substeps == (12, 3) and "(12 and 3 substeps, the full" in both.describe()
    )
    text = plan.dry_run(_study(tmp_path), backend=None)
    assert "\nNo primary comparison declared: the table takes all its " \
        "comparisons as one family." in text  # fmt: skip
    as_trained = Primary((("a", "b"),), (None,))
    assert as_trained.describe() == "a - b (as trained, the full fitness)"


def test_two_primaries_share_their_family_and_order_does_not_matter(tmp_path):
    path = _with(tmp_path, 'pairs = [["a", "b"], ["c", "b"]]')  # first substeps: 3
    md, data = st.make_table(load_study(path), _rows())
    first = [(r["a"], r["where"]) for r in data["holm"] if r["primary"]]
    assert first == [("arm A", "3 substeps"), ("arm C", "3 substeps")]
    assert all(r["p_holm"] == pytest.approx(0.2) for r in data["holm"])
    assert "2 comparisons, one family" in md and "The other 2, secondary" in md


def test_a_primary_at_both_resolutions(tmp_path):
    path = _with(tmp_path, 'pairs = [["a", "b"], ["c", "b"]]\nsubsteps = [3, 12]')
    md, data = st.make_table(load_study(path), _rows())
    assert [r["primary"] for r in data["holm"]] == [True] * 4
    assert "4 comparisons, one family" in md and "secondary" not in md
    rows = [r for r in _rows() if r["arm"] != "c"]  # a and b: with a height term
    path = _with(tmp_path, 'pairs = [["a", "b"]]\nsubsteps = [3, 12]')
    path.write_text(path.read_text().replace("[arms.c]", "[arms.c]\nscore = false"))
    md, data = st.make_table(load_study(path), rows)
    assert "2 comparisons, one family" in md and "The other 2, secondary" in md
    for r in rows:  # none: a - b at 3 and 12 substeps only
        for at in r["at"].values():
            at["height_term"] = None
    path = _with(tmp_path, 'pairs = [["a", "b"]]')
    path.write_text(path.read_text().replace("[arms.c]", "[arms.c]\nscore = false"))
    md, data = st.make_table(load_study(path), rows)
    assert "|\n\nThe other comparison, secondary, alone (Holm" in md
    assert [r["p_holm"] for r in data["holm"]] == [pytest.approx(0.1)] * 2


def test_a_primary_on_the_height_term(tmp_path):
    path = _with(tmp_path, 'pairs = [["a", "b"]]\nscore = "height-term"')
    rows = _rows()
    for r in rows:  # every arm with a height term: a and c's compared on it
        for at in r["at"].values():
            at["height_term"] = at["score"] / 2
    _, data = st.make_table(load_study(path), rows)
    first = [(r["a"], r["where"]) for r in data["holm"] if r["primary"]]
    assert first == [("arm A", "3 substeps, height term")]
    assert len(data["holm"]) == 8


def test_a_primary_the_table_does_not_make_is_said(tmp_path):
    """c has no height term: no comparison on it, so none primary."""
    path = _with(tmp_path, 'pairs = [["c", "b"]]\nscore = "height-term"')
    md, data = st.make_table(load_study(path), _rows())
    assert "|\n\nNo comparison declared primary (the study file's [primary]) " \
        "is in this table: none is tested as such.\n\nAll 4 comparisons above " \
        "as one family (Holm" in md  # fmt: skip
    assert [r["primary"] for r in data["holm"]] == [False] * 4
    assert [r["p_holm"] for r in data["holm"]] == [pytest.approx(0.4)] * 4
    assert data["primary"] == {"pairs": [["c", "b"]], "substeps": [3],
                               "score": "height-term"}  # fmt: skip
    rows = [r for r in _rows() if r["arm"] != "c"]
    for r in rows:  # no height term: a - b at 3 and 12 substeps only
        for at in r["at"].values():
            at["height_term"] = None
    path = _with(tmp_path, 'pairs = [["a", "b"]]\nscore = "height-term"')
    path.write_text(path.read_text().replace("[arms.c]", "[arms.c]\nscore = false"))
    md, data = st.make_table(load_study(path), rows)
    assert "All 2 comparisons above as one family" in md and len(data["holm"]) == 2
    path.write_text(path.read_text().replace("[3, 12]", "[3]"))
    md, data = st.make_table(load_study(path), rows)  # one comparison: no family
    assert "none is tested as such.\n\nHow to read" in md and "holm" not in data


@pytest.mark.parametrize(
    "table, message",
    [
        ("", "[primary] must be a table"),
        ('pairs = [["a", "b"]]\nalpha = 0.01',
         "primary.alpha: unknown key; choose from pairs, substeps, score"),
        ("substeps = 3", "primary.pairs must be a list of arm pairs, e.g. "
         '[["a", "b"]], got None'),
        ("pairs = []", "primary.pairs must be a list of arm pairs, e.g. "
         '[["a", "b"]], got []'),
        ('pairs = ["a", "b"]', "primary.pairs must be a list of arm pairs, e.g. "
         "[[\"a\", \"b\"]], got ['a', 'b']"),
        ('pairs = [["a", "b", "c"]]', "primary.pairs must be a list of arm "
         "pairs, e.g. [[\"a\", \"b\"]], got [['a', 'b', 'c']]"),
        ('pairs = [["a", 2]]', "primary.pairs must be a list of arm pairs, e.g. "
         "[[\"a\", \"b\"]], got [['a', 2]]"),
        ('pairs = [["a", "z"]]', "primary.pairs: 'z' is not a scored arm"),
        ('pairs = [["b", "b"]]', "primary.pairs: 'b' is compared with itself"),
        ('pairs = [["a", "c"]]', "primary.pairs: the table compares each arm "
         "with the reference 'b', not 'a' with 'c'"),
        ('pairs = [["a", "b"]]\nsubsteps = 6', "primary.substeps 6 is not one "
         "the study scores at, or a list of them ([3, 12])"),
        ('pairs = [["a", "b"]]\nsubsteps = true', "primary.substeps True is not "
         "one the study scores at, or a list of them ([3, 12])"),
        ('pairs = [["a", "b"]]\nsubsteps = 3.0', "primary.substeps 3.0 is not "
         "one the study scores at, or a list of them ([3, 12])"),
        ('pairs = [["a", "b"]]\nsubsteps = [3, 6]', "primary.substeps [3, 6] is "
         "not one the study scores at, or a list of them ([3, 12])"),
        ('pairs = [["a", "b"]]\nscore = "distance"', "primary.score 'distance': "
         "choose from full, height-term"),
    ],
)  # fmt: skip
def test_a_wrong_primary_is_named(tmp_path, table, message):
    path = _with(tmp_path, table)
    if not table:  # a key, not a table: before the file's first table
        text = path.read_text().replace("[primary]\n", "")
        path.write_text("primary = 1\n" + text)
    assert user_error(load_study, path) == f"{path}: {message}"


def test_a_study_scored_as_trained_takes_no_substeps(tmp_path):
    path = _with(tmp_path, 'pairs = [["a", "b"]]')
    path.write_text(path.read_text().replace("substeps = [3, 12]\n", ""))
    assert load_study(path).primary == Primary((("a", "b"),), (None,), "full")
    path.write_text(path.read_text() + "substeps = 3\n")
    assert user_error(load_study, path) == (
        f"{path}: primary.substeps 3 is not one the study scores at, or a list "
        "of them (as trained only)"
    )


def test_without_a_reference_any_two_scored_arms(tmp_path):
    _study(tmp_path, reference=None)
    path = tmp_path / "t.toml"
    path.write_text(path.read_text() + '[primary]\npairs = [["a", "c"]]\n')
    md, data = st.make_table(load_study(path), _rows())
    first = [(r["a"], r["b"]) for r in data["holm"] if r["primary"]]
    assert first == [("arm A", "arm C")]
