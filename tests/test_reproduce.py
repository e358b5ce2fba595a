"""The one-command reproduction (on a tiny budget): every stage, its results
table, continuing, replay and videos, and its bad input."""

import re
import shutil
from pathlib import Path

import pytest

from helpers import TINY_GENERATIONS, assert_same_run
from locustjump import rundir
from locustjump.cli import main
from locustjump.errors import UserError
from locustjump.rundir import MARKER, RESULTS
from locustjump.runs.reproduce import PAPER_STAGES, Budget, replay, reproduce
from locustjump.runs.reproduction import Reproduction

TINY = Budget("tiny", 4, TINY_GENERATIONS)  # that of conftest's tiny_reproduction


@pytest.fixture(scope="module")
def reproduction(tiny_reproduction) -> Path:
    """Seed 0's tiny reproduction, shared with test_multiseed: read-only."""
    return tiny_reproduction(0)


def test_reproduce_writes_every_stage_and_the_results_table(reproduction):
    r = reproduction
    assert (r / MARKER).is_file() and (r / RESULTS).is_file()
    for stage in ("kick", "getup", "return-legs", "composed", "monolithic"):
        assert (r / stage / rundir.BEST).is_file(), stage
        assert (r / stage / "eval" / "metrics.json").is_file(), stage
    assert (r / "getup" / "sweep" / "sweep.csv").is_file()
    text = (r / RESULTS).read_text()
    for claim in ("about 2x", "all 5 training states", "65 of 180", "ready posture",
                  "every composed jump", "does composition help"):  # fmt: skip
        assert claim in text, claim
    for fig in ("rules/trajectory.png", "composed/eval/composed.png"):
        assert f"]({fig})" in text and (r / fig).is_file()
    # the monolithic baseline got the four stages' generations
    m = rundir.read_metrics(r / "monolithic" / rundir.METRICS)
    assert len(m) == sum(TINY.of(s) for s in PAPER_STAGES) == TINY.of("monolithic")


def test_reproduce_continues_and_refuses_other_directories(reproduction, tmp_path):
    logs: list[str] = []
    r = shutil.copytree(reproduction, tmp_path / "r")
    before = (r / "kick" / rundir.CHECKPOINT).read_bytes()
    reproduce(r, budget=TINY, progress=False, log=logs.append, videos=False)
    assert all("done" in s for s in logs if s.startswith("[") and "rules" not in s)
    assert (r / "kick" / rundir.CHECKPOINT).read_bytes() == before
    with pytest.raises(UserError, match="budget"):
        reproduce(r, budget="quick", progress=False, log=lambda s: None)
    other = tmp_path / "other"
    other.mkdir()
    (other / "keep.txt").write_text("mine")
    with pytest.raises(UserError, match="holds no reproduction"):
        reproduce(other, budget=TINY, progress=False, log=lambda s: None)
    assert (other / "keep.txt").read_text() == "mine"


def test_reproduce_without_monolithic_then_adds_it(reproduction, tmp_path):
    # the paper's stages as --no-monolithic leaves them (the shared
    # reproduction, trained in the same order, without its baseline)
    out = shutil.copytree(reproduction, tmp_path / "r")
    shutil.rmtree(out / "monolithic")
    (out / RESULTS).unlink()
    quiet = {"progress": False, "log": lambda s: None, "videos": False}
    reproduce(out, budget=TINY, monolithic=False, **quiet)
    assert not (out / "monolithic").exists()
    text = (out / RESULTS).read_text()
    # its marker is the shared reproduction's, whose command had no flag
    assert "**Not finished:** stage monolithic not run yet" in text
    assert "monolithic stages (not run yet: monolithic)" in text
    assert "| monolithic |" not in text and "![monolithic]" not in text
    assert "| composed | 4 | 1 |" in text  # its wall-time row
    # one started with --no-monolithic records the flag (`make demo` runs one)
    # and says the baseline was left out, not that it is unfinished
    command = Reproduction.open(out, TINY, (0,)).command(monolithic=False)
    assert command == (
        f"locustjump reproduce --budget tiny --seed 0 --no-monolithic --out {out}"
    )
    marker = rundir.read_toml(out / MARKER)
    rundir.write_toml(out / MARKER, {**marker, "command": command})
    from locustjump.present.results import results_markdown

    left = results_markdown(out)
    assert "**Left out:** the monolithic baseline (`--no-monolithic`;" in left
    assert "Not finished" not in left
    reproduce(out, budget=TINY, **quiet)  # the same command without the flag
    text = (out / RESULTS).read_text()
    assert "Not finished" not in text and "the monolithic one's" in text
    assert "![monolithic](monolithic/eval/monolithic.png)" in text
    # the baseline added later is the one a reproduction in one go trains
    assert_same_run(out / "monolithic", reproduction / "monolithic")


def test_results_table_of_an_unfinished_reproduction(reproduction, tmp_path):
    from locustjump.present.results import results_markdown

    d = shutil.copytree(reproduction, tmp_path / "r")
    for stage in ("return-legs", "composed", "monolithic"):
        shutil.rmtree(d / stage)
    text = results_markdown(d)
    assert "stages return-legs, composed, monolithic not run yet" in text
    rows = [ln for ln in text.splitlines() if ln.startswith("| ")]
    legs = next(r for r in rows if "ready posture" in r)
    kick = next(r for r in rows if "about 2x" in r)
    assert legs.endswith("| not run yet | - |") and "not run yet" not in kick
    assert "![kick](kick/eval/kick_vs_rules.png)" in text
    assert "composed/eval/composed.png" not in text
    # a failed claim says what the study measured about why, once; an
    # unfinished one says nothing yet
    whys = [ln for ln in text.splitlines() if ln.startswith("- ")]
    assert ("no" in kick.split("|")[-2]) == any("about 2x" in w for w in whys)
    assert not any("composed jump" in w for w in whys)


def test_replay_resimulates_every_stage(reproduction, tmp_path, capsys):
    out = tmp_path / "replay"
    assert main(["replay", str(reproduction), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.count("matches the record") == 5
    assert (out / "composed" / "composed.png").is_file()
    with pytest.raises(UserError, match="not a reproduction"):
        replay(tmp_path, tmp_path / "x")


@pytest.mark.slow  # a minute on 2 cores (the default run renders two stages:
# test_reproduce_announces_every_phase)
def test_reproduce_renders_a_video_per_stage(reproduction, tmp_path):
    pytest.importorskip("imageio_ffmpeg", reason="extra locustjump[video] missing")
    from locustjump.runs.reproduce import STAGES, render_videos

    logs: list[str] = []
    d = shutil.copytree(reproduction, tmp_path / "r")
    made = render_videos(d, fps=0.5, log=logs.append)  # what is made, not how
    if any(s.startswith("videos skipped") for s in logs):
        pytest.skip(logs[-1])
    assert [p.parent.name for p in made] == list(STAGES)
    assert all(p.stat().st_size > 1000 for p in made)
    assert render_videos(d, fps=0.5, log=logs.append) == []  # kept, not re-made


def test_reproduce_announces_every_phase(reproduction, tmp_path, capsys):
    """Issue #47: after training, a reproduction said nothing for minutes.
    Each phase is announced before it begins: a stage's training and its
    evaluation (stage k of n), each video (k of n, with a bar over its frames
    and tqdm's estimate of the time left), results.md and the report."""
    pytest.importorskip("imageio", reason="extra locustjump[video] not installed")
    from locustjump.runs.reproduce import render_videos

    d = shutil.copytree(reproduction, tmp_path / "r")
    (d / "composed" / "eval" / "metrics.json").unlink()  # to be evaluated again
    logs: list[str] = []
    reproduce(d, budget=TINY, progress=False, log=logs.append, videos=False)
    assert logs[3:5] == [
        "[composed] stage 5 of 6: resuming: 1 generations",
        "[composed] stage 5 of 6: evaluating its best genome",
    ]
    assert logs[5].startswith("[composed] best fitness")
    assert logs[-3] == "writing results.md and report.html"
    for stage in ("rules", "getup", "return-legs", "monolithic"):  # fewer videos
        shutil.rmtree(d / stage)
    logs.clear()
    capsys.readouterr()
    made = render_videos(d, fps=0.5, log=logs.append, progress=True)
    if any(s.startswith("videos skipped") for s in logs):
        pytest.skip(logs[-1])
    assert made == [d / "kick" / rundir.VIDEO, d / "composed" / rundir.VIDEO]
    assert all(p.stat().st_size > 1000 for p in made)
    assert logs == [
        "[kick] rendering video 1 of 2 (re-simulating its best genome first)",
        f"[kick] wrote {d / 'kick' / rundir.VIDEO}",
        "[composed] rendering video 2 of 2 (re-simulating its best genome first)",
        f"[composed] wrote {d / 'composed' / rundir.VIDEO}",
    ]
    bars = capsys.readouterr().err
    assert "video 1 of 2, kick: 100%" in bars and "video 2 of 2, composed" in bars
    # elapsed<left: tqdm's estimate of the time left
    assert re.search(r"\[\d\d:\d\d<\d\d:\d\d, +[\d.]+(frame/s|s/frame)\]", bars)
    assert render_videos(d, fps=0.5, log=logs.append) == []  # kept, not re-made


def test_reproduce_cli_bad_input(tmp_path, capsys):
    with pytest.raises(SystemExit) as e:
        main(["reproduce", "--budget", "huge", "--out", str(tmp_path / "r")])
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--budget" in err
    (tmp_path / "f").write_text("x")
    assert main(["reproduce", "--out", str(tmp_path / "f"), "--quiet"]) == 2
    assert "not a directory" in capsys.readouterr().err
    assert (tmp_path / "f").read_text() == "x"


def test_sign_test_over_seeds():
    from locustjump.present.stages.successive import sign_test

    assert sign_test(0, 5) == sign_test(5, 5) == 2 / 32
    assert sign_test(1, 5) == 2 * 6 / 32
    assert sign_test(2, 4) == 1.0 and sign_test(0, 1) == 1.0
