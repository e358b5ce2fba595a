"""A quality-diversity run: a small MAP-Elites repertoire of the kick trained,
resumed bit for bit, its archive and metrics, one elite re-simulated and
watched, its report, and bad input."""

import json
import shutil

import numpy as np
import pytest

from helpers import assert_same_run, run_cli
from locustjump import rundir
from locustjump.evo import MapElitesParams, RCGAParams
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks import get_behaviour

pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")


@pytest.fixture(scope="module")
def qd_run(tmp_path_factory):
    """A small MAP-Elites repertoire of the kick, trained 2 + resumed 2."""
    out = tmp_path_factory.mktemp("qd") / "run"
    cfg = TrainConfig(generations=4, seed=3, optimizer=MapElitesParams(population=6))
    train(cfg, out, progress=False, stop_after=2)
    train(cfg, out, progress=False, resume=True)
    return out, cfg


def test_a_repertoire_run_resumes_bit_for_bit_on_any_thread_count(qd_run, tmp_path):
    out, cfg = qd_run
    whole = tmp_path / "whole"
    train(cfg, whole, progress=False, backend=ThreadBackend(threads=1))
    assert_same_run(out, whole)
    with np.load(out / rundir.ARCHIVE) as a, np.load(whole / rundir.ARCHIVE) as b:
        assert a.files == b.files
        for k in a.files:
            np.testing.assert_array_equal(a[k], b[k], err_msg=k)


def test_a_resumed_run_rewrites_an_archive_a_kill_left_behind(qd_run, tmp_path):
    """Killed between checkpoint.npz and archive.npz, the archive is a
    generation behind: resuming writes the checkpoint's."""
    out, cfg = qd_run
    run = tmp_path / "run"
    shutil.copytree(out, run)
    (run / rundir.ARCHIVE).unlink()
    train(cfg, run, progress=False, resume=True)  # nothing left to train
    with np.load(out / rundir.ARCHIVE) as a, np.load(run / rundir.ARCHIVE) as b:
        for k in a.files:
            np.testing.assert_array_equal(a[k], b[k], err_msg=k)


def test_a_repertoire_run_keeps_its_archive_and_metrics(qd_run):
    out, cfg = qd_run
    m = rundir.read_metrics(out / rundir.METRICS)
    assert {"qd_score", "coverage", "archive_best"} <= set(m.dtype.names)
    beh = get_behaviour("kick")
    a = rundir.read_archive(out, cfg, beh.controller.num_params)
    assert (
        m["coverage"][-1] == a.coverage and m["archive_best"][-1] == a.objective.max()
    )
    assert m["qd_score"][-1] == pytest.approx(a.qd_score())
    assert np.all(np.diff(m["archive_best"]) >= 0)  # an archive is elitist
    best = rundir.BestGenome.load(out / rundir.BEST)
    assert best.fitness == a.objective.max()
    assert (out / rundir.ARCHIVE_PNG).is_file()
    assert a.names == cfg.optimizer.descriptors and len(a) >= 1


def test_an_elite_re_simulates_to_its_fitness_and_descriptors(qd_run, tmp_path):
    out, cfg = qd_run
    a = rundir.read_archive(out, cfg, get_behaviour("kick").controller.num_params)
    last = len(a) - 1
    cell = ",".join(map(str, a.grid_index()[a.at_rank(last)]))
    r = run_cli("evaluate", str(out), "--cell", cell, "--json")
    assert r.returncode == 0, r.stderr
    ev = json.loads(r.stdout)
    assert ev["fitness"] == ev["recorded_fitness"] == a.objective[a.at_rank(last)]
    assert ev["descriptors"] == ev["recorded_descriptors"]
    assert list(ev["descriptors"].values()) == a.measures[a.at_rank(last)].tolist()
    assert (out / rundir.ELITES / f"cell-{cell.replace(',', '-')}").is_dir()


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (("--elite", "99"), "--elite 99: elite 99 does not exist"),
        (("--cell", "9,9,9"), "the grid has 2 descriptors"),
        (("--cell", "10,0"), "outside the grid"),
        (("--cell", "x"), "--cell must be integers separated by commas"),
        (("--elite", "0", "--cell", "0,0"), "not allowed with"),
    ],
)
def test_an_elite_that_does_not_exist_is_one_line(qd_run, args, needle):
    out, cfg = qd_run
    r = run_cli("evaluate", str(out), *args)
    assert r.returncode == 2 and needle in r.stderr and len(r.stderr.splitlines()) == 1


def test_an_empty_cell_and_a_run_without_archive_are_one_line(qd_run, tmp_path):
    out, cfg = qd_run
    a = rundir.read_archive(out, cfg, get_behaviour("kick").controller.num_params)
    empty = np.flatnonzero(np.isnan(a.heat().ravel()))[0]
    cell = ",".join(map(str, np.unravel_index(empty, a.dims)))
    for cmd in ("evaluate", "render"):
        r = run_cli(cmd, str(out), "--cell", cell)
        assert (
            r.returncode == 2
            and "is empty" in r.stderr
            and len(r.stderr.splitlines()) == 1
        )
    ga = tmp_path / "ga"
    train(TrainConfig(generations=1, optimizer=RCGAParams(population=4)), ga,
          progress=False)  # fmt: skip
    r = run_cli("evaluate", str(ga), "--elite", "0")
    assert r.returncode == 2 and "keeps an archive" in r.stderr
    assert not (ga / rundir.ELITES).exists() and not (out / "elites" / cell).exists()


@pytest.mark.parametrize(
    ("table", "needle"),
    [
        ('descriptors = ["height"]', "unknown descriptor 'height'"),
        ("cells = [4]", "cells has 1 entries for 2 descriptors"),
        ("ranges = [[1.0, 0.0], [0.0, 1.0]]", "ranges must be finite"),
        ("descriptors = [1]", "optimizer.descriptors[0] must be str"),
    ],
)
def test_bad_qd_settings_are_one_line_and_make_nothing(tmp_path, table, needle):
    conf = tmp_path / "c.toml"
    conf.write_text(f'[optimizer]\nkind = "map-elites"\n{table}\n')
    out = tmp_path / "out"
    r = run_cli("train", "kick", "--config", str(conf), "--out", str(out))
    assert r.returncode == 2 and needle in r.stderr and len(r.stderr.splitlines()) == 1
    assert not out.exists()


def test_a_qd_optimizer_on_a_task_without_descriptors_is_one_line(tmp_path):
    out = tmp_path / "out"
    r = run_cli("train", "getup", "--optimizer", "cma-me", "--out", str(out))
    assert r.returncode == 2 and "getup declares none" in r.stderr
    assert len(r.stderr.splitlines()) == 1 and not out.exists()


def test_the_report_shows_the_repertoire(qd_run, tmp_path):
    out, _ = qd_run
    page = tmp_path / "r.html"
    r = run_cli("report", str(out), "--out", str(page))
    assert r.returncode == 0, r.stderr
    text = page.read_text()
    assert "the repertoire" in text and "QD score" in text


def test_the_report_of_a_shipped_repertoire_draws_its_archive(qd_run, tmp_path):
    """A shipped run keeps archive.npz, not archive.png: the page draws it."""
    import shutil

    out, _ = qd_run
    shipped = tmp_path / "shipped"
    shutil.copytree(out, shipped)
    (shipped / "archive.png").unlink()
    page = tmp_path / "r.html"
    r = run_cli("report", str(shipped), "--out", str(page))
    assert r.returncode == 0, r.stderr
    assert "the repertoire: each cell" in page.read_text()
    assert not (shipped / "archive.png").exists()  # nothing written into the run


def test_an_elite_of_a_repertoire_trained_on_several_terrains(tmp_path):
    """Its descriptors, like its fitness, are over every training terrain, as
    recorded (they crashed on the first terrain's episodes alone)."""
    out = tmp_path / "run"
    cfg = TrainConfig(generations=1, seed=1, optimizer=MapElitesParams(population=4),
                      scene=Terrains(Debris(seed=0), count=2))  # fmt: skip
    train(cfg, out, progress=False)
    ev = tmp_path / "ev"
    r = run_cli("evaluate", str(out), "--elite", "0", "--json", "--out", str(ev))
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    assert got["fitness"] == got["recorded_fitness"]
    assert got["descriptors"] == got["recorded_descriptors"]
