"""Reproductions over several seeds: each seed's directory is what a
single-seed reproduction writes, on threads and as Ray tasks; a rerun continues
what is unfinished and keeps what is done; bad --seeds end in one line."""

import shutil
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

from helpers import TINY_GENERATIONS, assert_same_run, exit_status
from locustjump import rundir
from locustjump.errors import UserError
from locustjump.runs.multiseed import parse_seeds, reproduce_seeds
from locustjump.runs.reproduce import TRAINED, Budget

TINY = Budget("tiny", 4, TINY_GENERATIONS)  # that of conftest's tiny_reproduction
QUIET = {"progress": False, "log": lambda s: None, "videos": False}
SEEDS = (0, 1)


def _json_without(path: Path, *keys: str) -> dict:
    d = rundir.read_json(path)
    return {k: v for k, v in d.items() if k not in keys}


def assert_same_reproduction(a: Path, b: Path) -> None:
    """Same files; same genomes, fitness, metrics, evaluations, bit for bit
    (wall times and the recorded command aside)."""
    files = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    assert files == sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    for stage in TRAINED:
        assert_same_run(a / stage, b / stage)
        ev = Path(stage) / rundir.EVAL / rundir.EVAL_METRICS
        # "files" names where each file was written (under a, under b)
        assert _json_without(a / ev, "eval_wall_s", "files") == _json_without(
            b / ev, "eval_wall_s", "files"
        )
    sweep = Path("getup") / rundir.SWEEP / rundir.SWEEP_CSV
    assert (a / sweep).read_bytes() == (b / sweep).read_bytes()
    rules = Path(rundir.RULES_DIR) / rundir.RULES_SUMMARY
    assert _json_without(a / rules, "wall_s") == _json_without(b / rules, "wall_s")
    ma, mb = (rundir.read_toml(d / rundir.MARKER) for d in (a, b))
    ca, cb = ma.pop("command"), mb.pop("command")  # --out differs
    assert ca.split(" --out ")[0] == cb.split(" --out ")[0]
    assert ma == mb


@pytest.fixture(scope="module")
def singles(tiny_reproduction) -> dict[int, Path]:
    """The single-seed reproductions (conftest: shared with test_reproduce)."""
    return {s: tiny_reproduction(s) for s in SEEDS}


@pytest.fixture(scope="module")
def on_ray(tmp_path_factory, local_ray) -> SimpleNamespace:
    """A reproduction over seeds 0 and 1 started on threads in another
    process, killed (kill -9) in the middle of seed 0 (its kick done, getup
    under way), then continued as Ray tasks: seed 1 and the rest of seed 0
    run on Ray. ``kept``: seed 0's kick checkpoint and (bytes, mtime) before
    the continuation."""
    out = tmp_path_factory.mktemp("ray") / "seeds"
    code = (
        "from locustjump.runs.reproduce import Budget\n"
        "from locustjump.runs.multiseed import reproduce_seeds\n"
        f"b = Budget('tiny', 4, {dict(TINY.generations)!r})\n"
        f"reproduce_seeds({str(out)!r}, [0, 1], budget=b, backend='threads', "
        "threads=1, progress=False, videos=False, log=lambda s: None)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", code])
    started = out / "seed-0" / "getup" / rundir.METRICS
    deadline = time.monotonic() + 120
    while not started.exists() and proc.poll() is None:
        assert time.monotonic() < deadline
        time.sleep(0.01)
    proc.kill()
    proc.wait()
    assert not (out / "seed-1" / "kick").exists(), "killed too late to test"
    kept = out / "seed-0" / "kick" / rundir.CHECKPOINT
    before = (kept.read_bytes(), kept.stat().st_mtime_ns)
    reproduce_seeds(out, SEEDS, budget=TINY, backend="ray", **QUIET)
    return SimpleNamespace(out=out, kept=kept, before=before)


def test_each_seed_on_ray_is_the_single_seed_reproduction(on_ray, singles):
    for s in SEEDS:
        assert_same_reproduction(rundir.seed_dir(on_ray.out, s), singles[s])
    text = (on_ray.out / rundir.RESULTS).read_text()
    assert "over 2 seeds" in text and "| kick | 2 of 2 |" in text
    assert "reproduced in |" in text and "0 of 2 seeds" in text
    assert "### Seed 1 ([results](seed-1/results.md))" in text
    assert "does composition help?" in text and "Not finished" not in text
    html = (on_ray.out / rundir.REPORT).read_text()
    assert 'href="seed-1/report.html"' in html and "median [min, max]" in html


def test_seeds_on_threads_are_the_same(tmp_path, singles):
    out = tmp_path / "seeds"
    reproduce_seeds(out, [1], budget=TINY, backend="threads", threads=1, **QUIET)
    assert_same_reproduction(rundir.seed_dir(out, 1), singles[1])


def test_a_rerun_continues_what_is_unfinished_and_keeps_the_rest(
    on_ray, singles, tmp_path, local_ray
):
    out = shutil.copytree(on_ray.out, tmp_path / "seeds")
    # as if killed: seed 1's composed stage never ran, seed 0's monolithic
    # training finished but not its evaluation
    shutil.rmtree(out / "seed-1" / "composed")
    shutil.rmtree(out / "seed-0" / "monolithic" / rundir.EVAL)
    kept = out / "seed-0" / "kick" / rundir.CHECKPOINT
    before = (kept.read_bytes(), kept.stat().st_mtime_ns)
    logs: list[str] = []
    reproduce_seeds(out, SEEDS, budget=TINY, backend="ray",
                    **{**QUIET, "log": logs.append})  # fmt: skip
    assert any("2 stage tasks" in m for m in logs), logs
    assert (kept.read_bytes(), kept.stat().st_mtime_ns) == before
    for s in SEEDS:
        assert_same_reproduction(rundir.seed_dir(out, s), singles[s])
    # a rerun may add a seed; the marker keeps every seed
    with pytest.raises(
        UserError,
        match="holds a reproduction over seeds with budget 'tiny', not 'quick'",
    ):
        reproduce_seeds(out, [2], budget="quick", backend="ray", **QUIET)
    assert rundir.read_toml(out / rundir.SEEDS_MARKER)["seeds"] == [0, 1]


@pytest.mark.parametrize(
    "text,seeds",
    [("0-3", [0, 1, 2, 3]), ("5", [5]), ("0,3,7", [0, 3, 7]), ("0-1, 4", [0, 1, 4])],
)
def test_parse_seeds(text, seeds):
    assert parse_seeds(text) == seeds


@pytest.mark.parametrize(
    "text,message",
    [
        ("", "expected seeds like 0-9"),
        ("0-", "expected seeds like 0-9"),
        ("a-b", "expected seeds like 0-9"),
        ("-3", "expected seeds like 0-9"),
        ("3-1", "the range 3-1 is empty"),
        ("0-3,2", "seed 2 is given twice"),
        ("0,0", "seed 0 is given twice"),
        ("0-99999", "more than 1000 seeds"),
    ],
)
def test_bad_seeds_end_in_one_line_and_write_nothing(tmp_path, capsys, text, message):
    out = tmp_path / "r"
    assert exit_status(["reproduce", "--seeds", text, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and "--seeds" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_seeds_bad_combinations(tmp_path, capsys):
    out = tmp_path / "r"
    seeds = ["reproduce", "--seeds", "0-1", "--out", str(out)]
    assert exit_status([*seeds, "--seed", "3"]) == 2
    assert "not allowed with" in capsys.readouterr().err
    assert exit_status([*seeds, "--actors", "2"]) == 2
    assert "--actors" in capsys.readouterr().err
    assert not out.exists()
    # a single-seed reproduction is not a reproduction over seeds
    single = tmp_path / "single"
    single.mkdir()
    (single / rundir.MARKER).write_text('budget = "quick"\n')
    assert exit_status(["reproduce", "--seeds", "0-1", "--out", str(single)]) == 2
    assert "single-seed reproduction" in capsys.readouterr().err
    assert sorted(p.name for p in single.iterdir()) == [rundir.MARKER]


def test_a_killed_reproduction_continues_where_it_stopped(on_ray):
    """What the killed process finished (seed 0's kick) is kept as it was; the
    continuation is the single seeds' reproduction (the test above)."""
    assert (on_ray.kept.read_bytes(), on_ray.kept.stat().st_mtime_ns) == on_ray.before
