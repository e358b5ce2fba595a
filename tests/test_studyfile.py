"""A study file's top level (runs/studyfile.py) stated exactly: each key's
default, each refusal's one line with the file and the key it names, each
bound at its edge, held-out terrains kept unseen, and the order of the runs.
(``tests/test_studyarms.py`` states the arms; ``tests/test_study_cmd.py``
tries study files through the command.)"""

from pathlib import Path

import pytest

from helpers import SIMPLE_ARMS, user_error
from locustjump.runs.studyfile import (
    MAX_SUBSTEPS,
    TOP_KEYS,
    Evaluation,
    load_study,
)

#: the smallest study: two scored arms of a kick, two seeds
BASE = """seeds = "0-1"
[defaults]
behaviour = "kick"
generations = 2
optimizer = { population = 4 }
[arms.a]
[arms.b]
optimizer = { kind = "random" }
"""


def write(tmp_path: Path, top: str = "", rest: str = "", name: str = "s") -> Path:
    """A study file: ``top`` keys before BASE, ``rest`` tables after it."""
    path = tmp_path / f"{name}.toml"
    path.write_text(top + "\n" + BASE + rest)
    return path


def refusal(tmp_path: Path, top: str = "", rest: str = "", **kw) -> str:
    """The error of the study file ``write`` makes, less its file's name."""
    path = write(tmp_path, top, rest)
    message = user_error(load_study, path, **kw)
    assert message.startswith(f"{path}"), message
    return message[len(str(path)) :]


def test_the_defaults_of_the_top_level(tmp_path):
    s = load_study(write(tmp_path, name="mine"))
    assert s.name == "mine" and s.source == tmp_path / "mine.toml"
    assert s.root == Path("runs/studies/mine") and s.out == s.root
    assert s.seeds == (0, 1) and s.currency == "evaluations"
    assert (s.margin, s.reference, s.flat_gain) == (None, None, None)
    assert s.evaluation == Evaluation() == Evaluation(None, (None,))
    assert list(s.arms) == ["a", "b"] and [a.name for a in s.scored] == ["a", "b"]
    a = s.arms["a"].base  # [defaults] under every arm
    assert (a.behaviour, a.generations, a.optimizer.population) == ("kick", 2, 4)


def test_a_study_without_defaults(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('seeds = "0"\n[arms.a]\ngenerations = 3\n')
    assert load_study(path).arms["a"].base.generations == 3


def test_an_arms_error_names_the_file_and_the_arm(tmp_path):
    assert refusal(tmp_path, rest="[arms.c]\nscore = 1\n") == (
        " [arms.c]: score must be true or false, got 1"
    )


def test_every_top_level_key_is_read(tmp_path):
    s = load_study(write(tmp_path, """name = "n"
root = "r"
out = "o"
currency = "control-steps"
margin = 0.5
reference = "b"
flat_gain = 1.0""", '[evaluation]\nterrain_seeds = "7,9"\nsubsteps = 12'))  # fmt: skip
    assert (s.name, s.root, s.out, s.currency) == ("n", Path("r"), Path("o"),
                                                   "control-steps")  # fmt: skip
    assert (s.margin, s.reference, s.flat_gain) == (0.5, "b", 1.0)
    assert s.evaluation == Evaluation((7, 9), (12,))
    assert s.arms["a"].path == "r/a/seed-{seed}"


def test_a_file_that_is_not_a_toml_study_file(tmp_path):
    assert user_error(load_study, tmp_path / "s.json") == (
        f"{tmp_path / 's.json'}: a study file is a .toml file"
    )
    assert user_error(load_study, tmp_path / "s.toml") == (
        f"{tmp_path / 's.toml'}: no such study file"
    )
    (tmp_path / "link.toml").symlink_to(tmp_path / "gone.toml")  # read, and named
    assert "link.toml" in user_error(load_study, tmp_path / "link.toml")
    (tmp_path / "dir.toml").mkdir()
    assert user_error(load_study, tmp_path / "dir.toml").endswith(
        "expected a study file"
    )


def test_an_unknown_key_names_the_first_and_what_a_study_file_holds(tmp_path):
    assert refusal(tmp_path, "zz = 1\nmargn = 1") == (
        ": unknown key 'margn'; a study file holds " + ", ".join(TOP_KEYS)
    )


@pytest.mark.parametrize("key", ["name", "root", "out"])
@pytest.mark.parametrize("value, shown", [('" "', "' '"), ("3", "3"), ('""', "''")])
def test_names_and_directories_are_non_empty_strings(tmp_path, key, value, shown):
    got = refusal(tmp_path, f"{key} = {value}")
    assert got == f": {key} must be a non-empty string, got {shown}"


@pytest.mark.parametrize(
    "value, message",
    [
        ("[]", "seeds must be a non-empty list of integers"),
        ("[0, true]", "seeds must be a non-empty list of integers"),
        ("[0, 1.0]", "seeds must be a non-empty list of integers"),
        ("3", 'seeds must be like "0-4" or [0, 1], got 3'),
        ('"2-1"', "seeds '2-1': the range 2-1 is empty"),
    ],
)
def test_seeds_a_list_or_a_range(tmp_path, value, message):
    path = tmp_path / "s.toml"
    path.write_text(BASE.replace('seeds = "0-1"', f"seeds = {value}"))
    assert user_error(load_study, path) == f"{path}: {message}"


def test_seeds_as_a_list_and_missing(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(BASE.replace('seeds = "0-1"', "seeds = [4, 2]"))
    assert load_study(path).seeds == (4, 2)
    path.write_text(BASE.replace('seeds = "0-1"', ""))
    assert user_error(load_study, path) == (
        f'{path}: seeds is missing (e.g. seeds = "0-4")'
    )


def test_seeds_narrowed_to_the_studys_own(tmp_path):
    path = write(tmp_path, rest="")
    path.write_text(path.read_text().replace('"0-1"', '"0-3"'))
    assert load_study(path, seeds="3,1").seeds == (3, 1)
    assert load_study(path, seeds=None).seeds == (0, 1, 2, 3)
    assert user_error(load_study, path, seeds="6,2-5") == (
        "seeds: seed 4 is not one of the study's"
    )
    assert user_error(load_study, path, seeds="x").startswith("seeds: 'x': expected")


def test_the_currency(tmp_path):
    assert refusal(tmp_path, 'currency = "steps"') == (
        ": currency 'steps': choose from evaluations, control-steps"
    )


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("margin", "0", "margin must be a finite number > 0, got 0"),
        ("margin", "inf", "margin must be a finite number > 0, got inf"),
        ("flat_gain", "0.0", "flat_gain must be in (0, 1], got 0.0"),
        ("flat_gain", "1.0000001", "flat_gain must be in (0, 1], got 1.0000001"),
    ],
)
def test_margin_and_flat_gain_at_their_edges(tmp_path, key, value, message):
    assert refusal(tmp_path, f"{key} = {value}") == f": {message}"


def test_the_smallest_margin_and_flat_gain_are_taken(tmp_path):
    s = load_study(write(tmp_path, "margin = 1e-300\nflat_gain = 1e-300"))
    assert s.margin == 1e-300 and s.flat_gain == 1e-300


def test_the_reference_is_a_scored_arm(tmp_path):
    assert refusal(tmp_path, 'reference = "c"') == ": reference 'c' is not a scored arm"
    rest = "[arms.c]\nscore = false\n"
    assert refusal(tmp_path, 'reference = "c"', rest) == (
        ": reference 'c' is not a scored arm"
    )
    assert load_study(write(tmp_path, 'reference = "a"', rest)).reference == "a"


def test_a_study_scores_an_arm(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        BASE.replace("[arms.a]", "[arms.a]\nscore = false").replace(
            'optimizer = { kind = "random" }', "score = false"
        )
    )
    assert user_error(load_study, path) == (
        f"{path}: no arm is scored (every arm says score = false)"
    )
    path.write_text(BASE.replace("[arms.a]", "[arms.a]\nscore = false"))
    assert [a.name for a in load_study(path).scored] == ["b"]


@pytest.mark.parametrize(
    "table, message",
    [
        ("evaluation = 3", "[evaluation] must be a table"),
        ("[evaluation]\nsubsteps = 3\nz = 1\ny = 2",
         "evaluation.y: unknown key; choose from terrain_seeds, substeps"),
        ('[evaluation]\nterrain_seeds = ""',
         "evaluation.terrain_seeds '': expected seeds like 0-9 or 0,3,7 "
         "(non-negative integers and ranges), not ''"),
    ],
)  # fmt: skip
def test_the_evaluation_table(tmp_path, table, message):
    if table.startswith("evaluation"):
        assert refusal(tmp_path, table) == f": {message}"
    else:
        assert refusal(tmp_path, rest=table) == f": {message}"


@pytest.mark.parametrize(
    "value", ["0", str(MAX_SUBSTEPS + 1), "[]", "[3, 3]", "[true]", '"3"', "[3.0]"]
)
def test_substeps_are_distinct_integers_in_range(tmp_path, value):
    got = refusal(tmp_path, rest=f"[evaluation]\nsubsteps = {value}\n")
    assert got.startswith(
        f": evaluation.substeps must be distinct integers in 1..{MAX_SUBSTEPS}, got "
    )


def test_substeps_at_their_edges(tmp_path):
    path = write(tmp_path, rest=f"[evaluation]\nsubsteps = [1, {MAX_SUBSTEPS}]\n")
    assert load_study(path).evaluation.substeps == (1, MAX_SUBSTEPS)
    assert MAX_SUBSTEPS == 96


DEBRIS = 'scene = { kind = "debris", seed = 10, terrains = 2 }\n'


def test_a_held_out_terrain_a_run_trains_on_is_named(tmp_path):
    """Seed 1 of an arm with stride 2 trains on terrains 12 and 13."""
    path = tmp_path / "s.toml"
    text = BASE.replace("[arms.a]", "[arms.a]\n" + DEBRIS + "terrain_stride = 2")
    path.write_text(text + '[evaluation]\nterrain_seeds = "13-20"\n')
    assert user_error(load_study, path) == (
        f"{path}: evaluation terrain 13 is a training terrain of arm 'a', seed 1: "
        "held-out terrains must be unseen"
    )
    path.write_text(text + '[evaluation]\nterrain_seeds = "14-20,8,9"\n')
    assert load_study(path).evaluation.terrain_seeds == (14, *range(15, 21), 8, 9)
    # the first of several seen is named
    path.write_text(text + '[evaluation]\nterrain_seeds = "13,11,10"\n')
    assert "evaluation terrain 10 is a training terrain of arm 'a', seed 0" in (
        user_error(load_study, path)
    )


def test_a_flat_floor_has_no_terrain_to_hold_out(tmp_path):
    """The flat floor's seed is 0 (it has none): held-out seed 0 is no clash."""
    path = write(tmp_path, rest='[evaluation]\nterrain_seeds = "0-3"\n')
    assert load_study(path).evaluation.terrain_seeds == (0, 1, 2, 3)


def test_the_runs_seed_by_seed_each_arm_after_those_it_builds_on(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        """seeds = "3,1"
[defaults]
generations = 2
optimizer = { population = 4 }
[arms.composed]
behaviour = "composed"
frozen = { kick = "kick", getup = "getup", return-legs = "legs" }
"""
        + SIMPLE_ARMS
    )
    s = load_study(path)
    assert [(a.name, seed) for a, seed in s.runs()] == [
        ("kick", 3), ("getup", 5), ("legs", 3), ("composed", 3),
        ("kick", 1), ("legs", 1), ("composed", 1),
    ]  # fmt: skip
    assert [a.name for a in s.scored] == ["composed"]


def test_two_runs_of_one_directory_are_refused(tmp_path):
    path = tmp_path / "s.toml"
    text = BASE.replace("[arms.a]", '[arms.a]\npath = "same"')
    path.write_text(text.replace("[arms.b]", '[arms.b]\npath = "same"'))
    assert user_error(load_study, path) == (
        f"{path}: arm 'b', seed 0 and arm 'a', seed 0 are one directory (same): "
        "each run needs its own"
    )
    text = BASE.replace("[arms.a]", '[arms.a]\npath = "./x/../a-{seed}"')
    path.write_text(text.replace("[arms.b]", '[arms.b]\npaths = { "1" = "a-0" }'))
    assert user_error(load_study, path) == (
        f"{path}: arm 'b', seed 1 and arm 'a', seed 0 are one directory (a-0): "
        "each run needs its own"
    )
    path.write_text(BASE.replace("[arms.a]", '[arms.a]\npath = "a"'))  # per seed?
    assert user_error(load_study, path).endswith(
        "arm 'a', seed 1 and arm 'a', seed 0 are one directory (a): each run "
        "needs its own"
    )


def test_an_arm_of_a_fixed_seed_is_one_run_for_every_seed(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(BASE + '[arms.c]\nscore = false\nseed = 5\npath = "c"\n')
    s = load_study(path)
    assert s.arms["c"].run_dir(0) == s.arms["c"].run_dir(1) == Path("c")


@pytest.mark.parametrize(
    "path",
    sorted((Path(__file__).resolve().parents[1] / "studies").glob("*.toml")),
    ids=lambda p: p.stem,
)
def test_every_shipped_study_file_loads(path):
    study = load_study(path)
    assert study.name == path.stem and study.scored
