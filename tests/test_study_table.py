"""The study table from its rows (``make_table``): every cell a number of the
rows put there, the budget note, the pairs compared and when, the reading
note. Rows are made here, so no run is trained or scored: each expected
value is worked out by hand from them."""

from pathlib import Path

import pytest

from locustjump.errors import UserError
from locustjump.runs import study_table as st
from locustjump.runs.studyfile import load_study


def _study(tmp_path: Path, *, reference: str | None = "b", margin: str = "0.5",
           currency: str = "evaluations", seeds: str = "0-2",
           arms: str = "abc", held_out: bool = True,
           flat: str = "") -> object:  # fmt: skip
    head = ['name = "t"', f'root = "{tmp_path}"', f'seeds = "{seeds}"',
            f'currency = "{currency}"']  # fmt: skip
    if margin:
        head.append(f"margin = {margin}")
    if reference:
        head.append(f'reference = "{reference}"')
    if flat:
        head.append(f"flat_gain = {flat}")
    text = "\n".join(head) + '\n[defaults]\nbehaviour = "kick"\n'
    text += "[evaluation]\nsubsteps = [3, 12]\n"
    if held_out:
        text += 'terrain_seeds = "100-103"\n'
    for a in arms:
        text += f'[arms.{a}]\nlabel = "arm {a.upper()}"\n'
    path = tmp_path / "t.toml"
    path.write_text(text)
    return load_study(path)


def _row(arm, seed, *, score, height=None, distance=0.0, gen=10, ev=1000,
         steps=120_000, train=2.0, late=0.1, wall=None, pen=None,
         high=None):  # fmt: skip
    """A row as run_rows makes it; both resolutions score ``score`` and 12
    substeps one more."""
    at = {
        str(sub): {"score": score + (sub == 12), "height_term": height,
                   "distance_term": distance, "distance_m": None, "jumps": None,
                   "wall_contact": wall, "penetration_m": pen, "highest_m": high}
        for sub in (3, 12)
    }  # fmt: skip
    return {"arm": arm, "seed": seed, "path": f"{arm}/{seed}", "generations": gen,
            "evaluations": ev, "control_steps": steps, "train_fitness": train,
            "late_gain": late, "at": at}  # fmt: skip


def _rows(**over):
    rows = []
    for i, s in enumerate((1.0, 3.0, 2.0)):
        rows.append(_row("a", i, score=s, gen=10 + i, ev=1000 + 10 * i,
                         steps=120_000 * (i + 1), train=4.0 + i, late=0.1 * i,
                         height=s / 2, distance=s / 2, wall=0.1 * i,
                         pen=0.001 * i, high=1.0 + i, **over))  # fmt: skip
        rows.append(_row("b", i, score=s + 10, height=s, distance=s + 10,
                         ev=1010, steps=240_000, **over))  # fmt: skip
        rows.append(_row("c", i, score=-s, ev=1000, steps=240_000, **over))
    return rows


def test_the_budget_table_gives_each_arms_medians(tmp_path):
    md, data = st.make_table(_study(tmp_path), _rows())
    # arm a: generations 10, 11, 12; evaluations 1000, 1010, 1020; control
    # steps 0.12, 0.24, 0.36 M; training fitness 4, 5, 6; late gain 0, 10, 20 %
    assert "| arm A | 3 | 11 | 1,010 | 0.24 M | 5 | 10% |" in md
    assert "| arm B | 3 | 10 | 1,010 | 0.24 M | 2 | 10% |" in md
    assert data["arms"]["a"]["budget"] == {
        "generations": 11.0, "evaluations": 1010.0, "control_steps": 240_000.0,
        "train_fitness": 5.0, "late_gain": 0.1}  # fmt: skip
    assert data["arms"]["a"]["label"] == "arm A" and data["arms"]["a"]["runs"] == 3
    assert "3 seeds (0-2); every run's best genome scored on held-out terrains " \
        "100-103" in md  # fmt: skip
    assert "Arms equalised in **evaluations**" in md


def test_the_budget_note_flags_unequal_arms_in_the_declared_currency(tmp_path):
    md, _ = st.make_table(_study(tmp_path), _rows())
    # evaluations: medians 1010, 1010, 1000 -> 1.01, within 2 %; control
    # steps 0.24 M each
    assert ("In evaluations (the declared currency): largest / smallest arm "
            "1.01. In control-steps: largest / smallest arm 1.00.") in md  # fmt: skip
    rows = _rows()
    for r in rows:
        if r["arm"] == "c":
            r["evaluations"], r["control_steps"] = 1100, 250_000
    md, _ = st.make_table(_study(tmp_path), rows)
    # evaluations 1100 / 1010
    assert (
        "In evaluations (the declared currency): largest / smallest arm 1.09"
        " — **not equal**: the arms are not compared at equal budget."
    ) in md
    assert "In control-steps: largest / smallest arm 1.04 — unequal in this " \
        "currency." in md  # fmt: skip
    md, _ = st.make_table(_study(tmp_path, currency="control-steps"), rows)
    assert "In evaluations: largest / smallest arm 1.09 — unequal in this " \
        "currency." in md  # fmt: skip
    assert "In control-steps (the declared currency): largest / smallest arm " \
        "1.04 — **not equal**" in md  # fmt: skip
    # an arm that spent nothing: an infinite ratio, not a division error
    for r in rows:
        r["evaluations"] = 0 if r["arm"] == "c" else r["evaluations"]
    md, _ = st.make_table(_study(tmp_path), rows)
    assert "largest / smallest arm inf — **not equal**" in md


def test_the_budget_note_of_one_arm_is_empty(tmp_path):
    assert st._budget_note(_study(tmp_path), {"a": {}}) == ""


def test_the_scores_table_gives_each_run_and_the_arms_summaries(tmp_path):
    md, data = st.make_table(_study(tmp_path), _rows())
    # arm a at 3 substeps: scores 1, 3, 2; height terms 0.5, 1.5, 1; distance
    # the same; gaps 4-1, 5-3, 6-2 = 3, 2, 4; wall 0, 0.1, 0.2; penetration
    # 0, 0.001, 0.002; highest 1, 2, 3
    assert ("| arm A | 3 | 1, 3, 2 | 2 [1, 3] | 1 | 1 | 3 | 20.0% | 0.0020 | "
            "3.00 |") in md  # fmt: skip
    # at 12 substeps every score is one more: the gap one less
    assert "| arm A | 3 | 2, 4, 3 | 3 [2, 4] | 1 | 1 | 2 | 20.0% |" in md
    # arm c: no diagnostics recorded -> "-"
    assert "| arm C | 3 | -1, -3, -2 | -2 [-3, -1] | - | 0 | 4 | - | - | - |" in md
    a3 = data["arms"]["a"]["3"]
    assert a3 == {"values": [1.0, 3.0, 2.0], "median": 2.0, "min": 1.0,
                  "max": 3.0, "height_term": 1.0, "distance_term": 1.0,
                  "gap": 3.0, "wall_contact": 0.2, "penetration_m": 0.002,
                  "highest_m": 3.0}  # fmt: skip
    assert data["arms"]["c"]["3"]["height_term"] is None
    assert [h.split("\n")[0] for h in md.split("## ")[1:]] == [
        "Budget per run (median over seeds)", "Scores, 3 substeps",
        "Scores, 12 substeps"]  # fmt: skip


def test_each_arm_is_compared_with_the_reference(tmp_path):
    md, data = st.make_table(_study(tmp_path), _rows())
    names = [[p["a"], p["b"]] for p in data["pairs"]["3"]]
    assert names == [["arm A", "arm B"], ["arm C", "arm B"]]
    assert "| arm A - arm B | 3, 3 |" in md and "| arm C - arm B | 3, 3 |" in md
    # the shift of a over b: every score of b is 10 more
    assert data["pairs"]["3"][0]["shift"] == pytest.approx(-10.0)
    _, data = st.make_table(_study(tmp_path, reference=None), _rows())
    assert [[p["a"], p["b"]] for p in data["pairs"]["12"]] == [
        ["arm A", "arm B"], ["arm A", "arm C"], ["arm B", "arm C"]]  # fmt: skip


def test_the_height_term_alone_is_compared_where_the_distance_term_counts(tmp_path):
    study = _study(tmp_path, arms="ab")
    rows = [r for r in _rows() if r["arm"] != "c"]
    md, data = st.make_table(study, rows)
    assert md.count("On the height term alone") == 2  # both resolutions
    assert [[p["a"], p["b"]] for p in data["pairs_height_term"]["3"]] == [
        ["arm A", "arm B"]]  # fmt: skip
    # height terms a 0.5, 1.5, 1 against b 1, 3, 2: the shift is -0.5 .. -1.5
    assert -1.5 <= data["pairs_height_term"]["3"][0]["shift"] <= -0.5
    for r in rows:  # no distance term anywhere: the score is the height term
        for at in r["at"].values():
            at["distance_term"] = 0.0
    md, data = st.make_table(study, rows)
    assert "On the height term alone" not in md and "pairs_height_term" not in data
    rows[0]["at"]["3"]["height_term"] = None  # one run without it: not compared
    rows[0]["at"]["3"]["distance_term"] = 1.0
    md, data = st.make_table(study, rows)
    assert "3" not in data.get("pairs_height_term", {})


def test_an_arm_of_one_run_is_not_compared(tmp_path):
    rows = [r for r in _rows() if not (r["arm"] == "a" and r["seed"] > 0)]
    md, data = st.make_table(_study(tmp_path), rows)
    assert "No comparison: arm A has fewer than 2 runs." in md
    assert md.startswith("# Study t\n") and "## Budget per run" in md
    assert "|\n\nNo comparison: arm A" in md  # a paragraph of its own
    assert data["pairs"]["3"] == [] and "| arm A - arm B |" not in md
    rows = [r for r in rows if r["arm"] == "a" or r["seed"] == 0]
    md, _ = st.make_table(_study(tmp_path), rows)
    assert "No comparison: arm A; arm B; arm C each have fewer than 2 runs." in md


def test_the_reading_names_the_margin_or_its_absence(tmp_path):
    md, data = st.make_table(_study(tmp_path), _rows())
    assert md.endswith(
        "against the declared margin ±0.5; otherwise there is no "
        "evidence either way. Seeds for 80 % power: about how many per arm, "
        "to detect a shift of the margin at the spread observed.\n"
    )
    assert data["margin"] == 0.5 and data["currency"] == "evaluations"
    assert data["study"] == "t" and len(data["runs"]) == 9
    md, data = st.make_table(_study(tmp_path, margin=""), _rows())
    assert "(no equivalence margin declared: 'no difference' cannot be " \
        "concluded)" in md and data["margin"] is None  # fmt: skip
    assert md.startswith("# Study t\n\n")


@pytest.mark.parametrize(("seeds", "text"), [
    ((0, 1, 2, 3, 4), "0-4"), ((3, 4, 5), "3-5"), ((0, 1), "0, 1"),
    ((0, 2, 5), "0, 2, 5"), ((7,), "7")])  # fmt: skip
def test_seeds_are_written_as_a_range_where_they_are_one(seeds, text):
    assert st._seeds_text(seeds) == text


def test_small_formatting_helpers():
    assert st._fmt(None) == "-" and st._fmt(1234.5678) == "1235"
    assert st._fmt(12345.0) == "1.234e+04"
    assert st._fmt(0.25, ".1%") == "25.0%"
    assert st._label(None) == "as trained" and st._label(6) == "6 substeps"
    assert st._med([]) is None and st._med([3.0, 1.0, 2.0]) == 2.0


GOLDEN = Path(__file__).parent / "data" / "study_table.md"


def test_the_whole_table_of_two_arms(tmp_path):
    """Every line of a small table, headers and blank lines included, as
    ``tests/data/study_table.md`` holds it (reviewed by eye: seeds 0-1, arm
    a against the reference b, which scores 10 more on every run)."""
    rows = [r for r in _rows() if r["arm"] != "c" and r["seed"] < 2]
    for r in rows:
        r["control_steps"] = 30_015_000  # 30.02 M, not 30.01 M
    md, _ = st.make_table(_study(tmp_path, seeds="0-1", arms="ab"), rows)
    assert md == GOLDEN.read_text()


def test_two_runs_an_arm_are_compared(tmp_path):
    rows = [r for r in _rows() if r["seed"] < 2]
    md, data = st.make_table(_study(tmp_path, seeds="0-1"), rows)
    assert len(data["pairs"]["3"]) == 2 and "No comparison" not in md
    assert data["pairs"]["3"][0]["margin"] == 0.5  # the study's margin


def test_a_study_scored_on_each_runs_own_scene(tmp_path):
    md, _ = st.make_table(_study(tmp_path, held_out=False), _rows())
    assert "every run's best genome scored on each run's own scene; one" in md


def test_an_episode_without_a_diagnostic_counts_out_of_its_mean_and_max():
    eps = [{"fitness": 1.0, "wall": None}, {"fitness": 3.0, "wall": 0.5},
           {"fitness": 2.0}]  # fmt: skip
    assert st._mean(eps, "fitness") == 2.0 and st._max(eps, "fitness") == 3.0
    assert st._mean(eps, "wall") == 0.5 and st._max(eps, "wall") == 0.5
    assert st._mean(eps, "none") is None and st._max(eps, "none") is None
    assert st._mean([], "fitness") is None


def test_the_declared_flattening_rule_says_which_arms_are_flat(tmp_path):
    # median late gain: arm a 10 % (0, 10, 20 %), b and c 10 % each
    md, data = st.make_table(_study(tmp_path, flat="0.1"), _rows())
    assert ("Flat by the study's declared rule (the median gain in the last "
            "third at most 10.00%): arm A yes (10.00%); arm B yes (10.00%); "
            "arm C yes (10.00%).") in md  # fmt: skip
    assert all(data["arms"][a]["flat"] for a in "abc")
    # the line follows the budget note, the rest of the table as it was
    plain, _ = st.make_table(_study(tmp_path), _rows())
    note = st._budget_note(_study(tmp_path), data["arms"])
    head, tail = plain.split(note + "\n", 1)
    flat_line = md.split(note + "\n\n", 1)[1].split("\n", 1)[0]
    assert flat_line.startswith("Flat by the study's declared rule")
    assert md == head + note + "\n\n" + flat_line + "\n" + tail
    md, data = st.make_table(_study(tmp_path, flat="0.05"), _rows())
    assert "at most 5.00%): arm A no (10.00%); arm B no (10.00%)" in md
    assert not any(data["arms"][a]["flat"] for a in "abc")
    md, data = st.make_table(_study(tmp_path), _rows())  # none declared
    assert "Flat by" not in md and "flat" not in data["arms"]["a"]


@pytest.mark.parametrize("bad", ["0", "-0.1", "1.5", '"5%"', "true", "nan"])
def test_a_flattening_rule_outside_0_to_1_is_named(tmp_path, bad):
    with pytest.raises(UserError, match=r"t.toml: flat_gain must be"):
        _study(tmp_path, flat=bad)
    assert _study(tmp_path, flat="1").flat_gain == 1.0


def test_the_family_section_needs_two_comparisons(tmp_path):
    """Two comparisons (one pair at 3 and 12 substeps, no height term) are a
    family, with their Holm p in table.json; one alone is not."""
    rows = [_row(a, i, score=s + (10 if a == "b" else 0))
            for i, s in enumerate((1.0, 3.0, 2.0)) for a in "ab"]  # fmt: skip
    md, data = st.make_table(_study(tmp_path, arms="ab"), rows)
    assert "All 2 comparisons above as one family" in md
    where = [(r["where"], r["a"], r["b"]) for r in data["holm"]]
    pair = ("arm A", "arm B")
    assert where == [("3 substeps", *pair), ("12 substeps", *pair)]
    path = tmp_path / "t.toml"
    path.write_text(path.read_text().replace("[3, 12]", "[3]"))
    md, data = st.make_table(load_study(path), rows)
    assert "as one family" not in md and "holm" not in data
    assert len(data["pairs"]["3"]) == 1
