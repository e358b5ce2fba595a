"""Reading a run never writes into the shipped runs (``results/``, tracked in
git): evaluate, sweep-getup, report and replay of a shipped run put what they
derive under ``runs/shipped/<same path>/`` or where ``--out`` says, and a
run of one's own gets its derived files beside it, as before."""

import shutil

import pytest

from helpers import main_while_held
from locustjump import rundir
from locustjump.cli import main
from locustjump.rundir import layout


@pytest.fixture
def shipped_here(shipped, tmp_path, monkeypatch):
    """A checkout in ``tmp_path``: its ``results/quick-seed0`` (without the
    videos) is the shipped one, its ``runs/shipped/`` where derived files go."""
    results = tmp_path / "results"
    shutil.copytree(shipped, results / "quick-seed0",
                    ignore=shutil.ignore_patterns("*.mp4"))  # fmt: skip
    monkeypatch.setattr(layout, "SHIPPED", results)
    monkeypatch.setattr(layout, "SHIPPED_DERIVED", tmp_path / "runs" / "shipped")
    monkeypatch.chdir(tmp_path)
    return results


def _files(d):
    return {p: p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def test_reading_the_shipped_runs_writes_nothing_into_them(shipped_here, capsys):
    before = _files(shipped_here)
    repro = shipped_here / "quick-seed0"
    derived = shipped_here.parent / "runs" / "shipped" / "quick-seed0"
    assert main(["evaluate", str(repro / "kick")]) == 0
    assert main(["sweep-getup", str(repro / "getup"), "--step-deg", "90"]) == 0
    assert main(["report", str(repro)]) == 0
    assert main(["report", str(repro / "return-legs")]) == 0
    assert main(["replay", str(repro), "--out", "rp"]) == 0
    out = capsys.readouterr().out
    assert _files(shipped_here) == before  # nothing changed, nothing added
    assert (derived / "kick" / "eval" / "kick_vs_rules.png").is_file()
    assert (derived / "getup" / "sweep" / "sweep.csv").is_file()
    assert (derived / "report.html").is_file()
    assert f"wrote {derived / 'report.html'}" in out
    # report writes only its page: the run's evaluation went to a temporary dir
    assert sorted(p.name for p in (derived / "return-legs").iterdir()) == [
        "report.html"
    ]
    assert (shipped_here.parent / "rp" / "composed" / "composed.png").is_file()


def test_out_says_where(shipped_here, tmp_path, capsys):
    kick = shipped_here / "quick-seed0" / "kick"
    assert main(["evaluate", str(kick), "--out", "ev"]) == 0
    assert (tmp_path / "ev" / "kick_vs_rules.png").is_file()
    assert main(["evaluate", str(kick), "--out", "ev"]) == 2  # not empty
    assert "--force" in capsys.readouterr().err
    assert main(["evaluate", str(kick), "--out", "ev", "--force"]) == 0
    assert main(["report", str(kick), "--out", "k.html"]) == 0
    assert main(["report", str(kick), "--out", "k.html"]) == 2  # exists
    assert main(["report", str(kick), "--out", "k.html", "--force"]) == 0
    assert not (tmp_path / "runs").exists()


def test_a_run_of_ones_own_gets_its_derived_files_beside_it(shipped, tmp_path):
    run = shutil.copytree(shipped / "kick", tmp_path / "kick",
                          ignore=shutil.ignore_patterns("*.mp4", "eval"))  # fmt: skip
    assert rundir.derived_dir(run) == run
    assert main(["evaluate", str(run)]) == 0
    assert main(["report", str(run)]) == 0
    assert (run / "eval" / "kick_vs_rules.png").is_file()
    assert (run / "report.html").is_file()


@pytest.mark.parametrize(
    "argv",
    [["evaluate", "kick"], ["sweep-getup", "getup", "--step-deg", "90"],
     ["report", "kick"]],
)  # fmt: skip
def test_one_writer_of_a_shipped_runs_derived_files(shipped_here, capsys, argv):
    """Two commands deriving from one shipped run would write the same files
    under ``runs/shipped/``: the second is told who holds them."""
    run = shipped_here / "quick-seed0" / argv[1]
    derived = rundir.derived_dir(run)
    derived.mkdir(parents=True)
    cmd = [argv[0], str(run), *argv[2:], "--threads", "1"]
    code, err, pid = main_while_held(derived, cmd, capsys)
    assert code == 2 and f"is in use by process {pid}" in err, err
    assert len(err.strip().splitlines()) == 1, err
    assert list(derived.iterdir()) == []


def test_a_failed_derivation_removes_only_what_it_made(shipped_here):
    """A command that fails removes the derived directory it made, before it
    lets go of its lock; one that was there before, with what it held, stays."""
    run = shipped_here / "quick-seed0" / "kick"
    derived = rundir.derived_dir(run)
    with pytest.raises(RuntimeError):
        with rundir.deriving(run) as d:
            assert d == derived
            (d / "half.csv").write_text("x")
            assert rundir.in_use(d) is None  # held by this process
            raise RuntimeError
    assert not derived.exists() and derived.parent.is_dir()
    derived.mkdir()
    (derived / "kept.csv").write_text("y")
    with pytest.raises(RuntimeError):
        with rundir.deriving(run):
            raise RuntimeError
    assert (derived / "kept.csv").read_text() == "y"
