"""Quality diversity: the MAP-Elites and CMA-ME optimizers (pyribs), the
task's behaviour descriptors, the archive in the run directory, picking one
elite, and bad input."""

import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from helpers import assert_same_run, run_cli
from locustjump import rundir
from locustjump.evo import (
    CMAME,
    Archive,
    CMAMEParams,
    MapElites,
    MapElitesParams,
    RCGAParams,
    make_optimizer,
)
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim import model as lm
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.job import RolloutResult
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks import Kick, get_behaviour
from locustjump.tasks.kick import kick_descriptors
from locustjump.tasks.reference import run_rules

pytest.importorskip("ribs", reason="pyribs is not installed (locustjump[qd])")

GRID = {"descriptors": ("a", "b"), "ranges": ((0.0, 1.0), (0.0, 1.0))}
KINDS = {
    "map-elites": MapElitesParams(population=8, cells=(5, 5), **GRID),
    "iso-line": MapElitesParams(
        population=8, cells=(5, 5), variation="iso-line", sigma=0.05, **GRID
    ),
    "cma-me": CMAMEParams(population=8, emitters=2, cells=(5, 5), **GRID),
}


def _problem(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fitness (maximised at 0.3) and two descriptors in [0, 1] of genomes x."""
    return -np.sum((x - 0.3) ** 2, axis=1), np.clip(np.abs(x[:, :2]), 0, 1)


def _run(opt, generations: int) -> list[np.ndarray]:
    asked = []
    for _ in range(generations):
        x = opt.ask()
        asked.append(x)
        opt.tell(*_problem(x))
    return asked


# --- the optimizers -----------------------------------------------------------


@pytest.mark.parametrize("kind", list(KINDS))
def test_resumed_from_its_arrays_it_goes_on_bit_for_bit(kind, tmp_path):
    """N generations in one go equal N/2, a state written to an .npz and read
    back without pickle into a fresh optimizer, then N/2 more."""
    params = KINDS[kind]
    whole = make_optimizer(params, 5, seed=4)
    asked = _run(whole, 12)
    half = make_optimizer(params, 5, seed=4)
    _run(half, 6)
    np.savez(tmp_path / "state.npz", **half.state())
    with np.load(tmp_path / "state.npz", allow_pickle=False) as z:
        state = {k: z[k] for k in z.files}
    resumed = make_optimizer(params, 5, seed=4)
    resumed.load_state(state)
    for a, b in zip(asked[6:], _run(resumed, 6), strict=True):
        np.testing.assert_array_equal(a, b)
    for k in ("index", "solution", "objective", "measures", "generation"):
        np.testing.assert_array_equal(
            getattr(whole.archive(), k), getattr(resumed.archive(), k)
        )
    assert whole.diagnostics() == resumed.diagnostics()
    assert whole.best_fitness == resumed.best_fitness
    # another seed, other genomes
    assert not np.array_equal(make_optimizer(params, 5, 5).ask(), asked[0])


def test_a_state_whose_archive_the_replay_does_not_give_is_refused():
    opt = make_optimizer(KINDS["map-elites"], 5, seed=1)
    _run(opt, 3)
    state = opt.state()
    state["archive_objective"] = state["archive_objective"] + 1e-12
    with pytest.raises(ValueError, match="archive_objective is not what replaying"):
        make_optimizer(KINDS["map-elites"], 5, seed=1).load_state(state)


@pytest.mark.parametrize("kind", ["map-elites", "cma-me"])
def test_the_archive_holds_each_cells_best_as_plain_map_elites_would(kind):
    """pyribs' archive against a plain reference: the best genome told so
    far in each cell of the grid (cells by floor((v - low) / width), the
    edges clipped), with the generation that found it."""
    opt = make_optimizer(KINDS[kind], 5, seed=2)
    best: dict[int, tuple[float, int, np.ndarray]] = {}
    for g in range(1, 16):
        x = opt.ask()
        f, d = _problem(x)
        opt.tell(f, d)
        cells = np.minimum((d * 5 + 1e-6).astype(int), 4)
        for xi, fi, (i, j) in zip(x, f, cells, strict=True):
            c = i * 5 + j
            if c not in best or fi > best[c][0]:
                best[c] = (fi, g, xi)
    a = opt.archive()
    assert sorted(best) == sorted(a.index.tolist())
    for pos, c in enumerate(a.index):
        fi, g, xi = best[int(c)]
        assert a.objective[pos] == fi and a.generation[pos] == g
        np.testing.assert_array_equal(a.solution[pos], xi)
    s = opt.diagnostics()
    assert s["coverage"] == len(best) / 25 == a.coverage
    assert s["archive_best"] == max(v[0] for v in best.values()) == opt.best_fitness
    assert math.isclose(s["qd_score"], sum(v[0] for v in best.values()))


def test_the_first_genomes_are_the_rcgas_uniform_start_and_every_emitter_asks():
    p = MapElitesParams(population=7, emitters=3, **GRID, cells=(2, 2))
    opt = MapElites(4, p, seed=0)
    x = opt.ask()
    assert p.batch_sizes() == [3, 2, 2] and x.shape == (7, 4)
    assert np.abs(x).max() <= p.init_scale
    np.testing.assert_array_equal(x, np.random.default_rng(0).uniform(-1, 1, (7, 4)))


def test_descriptors_go_with_the_tell_and_only_to_an_optimizer_that_needs_them():
    qd = make_optimizer(KINDS["map-elites"], 5, 0)
    x = qd.ask()
    with pytest.raises(ValueError, match="needs the descriptors a, b"):
        qd.tell(_problem(x)[0])
    with pytest.raises(ValueError, match="shape"):
        qd.tell(_problem(x)[0], np.zeros((len(x), 3)))
    with pytest.raises(ValueError, match="not finite"):
        qd.tell(_problem(x)[0], np.full((len(x), 2), np.nan))
    ga = make_optimizer(RCGAParams(population=4), 5, 0)
    assert ga.descriptor_names == ()
    n = len(ga.ask())
    with pytest.raises(ValueError, match="takes no descriptors"):
        ga.tell(np.zeros(n), np.zeros((n, 2)))
    ga.tell(np.zeros(n))  # unchanged for the others


def test_a_qd_optimizer_needs_its_grid_and_cma_me_two_genomes_an_emitter():
    with pytest.raises(ValueError, match="needs its descriptors"):
        CMAME(5, CMAMEParams(), 0)
    message = "^population must be >= 2 per emitter \\(5 emitters: >= 10\\), got 9$"
    with pytest.raises(ValueError, match=message):
        CMAMEParams(population=9, emitters=5)
    with pytest.raises(ValueError, match="at most 10,000"):
        MapElitesParams(cells=(200, 200))
    with pytest.raises(ValueError, match="variation"):
        MapElitesParams(variation="line")


# --- the archive's arrays -----------------------------------------------------


def _archive() -> Archive:
    return Archive(
        ("x", "y"), np.array([0.0, -1.0]), np.array([1.0, 1.0]), (2, 3),
        np.array([5, 0, 3]), np.arange(6.0).reshape(3, 2),
        np.array([0.5, 2.0, 0.5]), np.array([[0.9, 0.9], [0.1, -0.9], [0.6, -0.9]]),
        np.array([1, 1, 2]),
    )  # fmt: skip


def test_an_archive_ranks_its_elites_and_finds_a_cell():
    a = _archive()
    assert a.ranked().tolist() == [1, 2, 0]  # ties: the lower cell first
    assert a.at_rank(0) == 1 and a.at_cell((1, 2)) == 0 and a.at_cell((1, 0)) == 2
    assert a.grid_index().tolist() == [[1, 2], [0, 0], [1, 0]]
    heat = a.heat()
    assert heat[1, 2] == 0.5 and np.isnan(heat[0, 1]) and a.coverage == 0.5
    assert a.qd_score() == 3.0 and a.qd_score(offset=1.0) == 0.0
    for bad, needle in (((0, 1), "empty"), ((2, 0), "outside"), ((1,), "2 desc")):
        with pytest.raises(IndexError, match=needle):
            a.at_cell(bad)
    with pytest.raises(IndexError, match="holds 3"):
        a.at_rank(3)
    assert a.in_cell_order().index.tolist() == [0, 3, 5]


def test_the_heatmap_title_gives_the_qd_score_less_the_runs_offset():
    from matplotlib.figure import Figure

    from locustjump.present.plots import draw_archive

    for offset, score in ((0.0, "3"), (1.0, "0"), (-2.0, "9")):
        fig = Figure()
        ax = fig.add_subplot()
        draw_archive(fig, ax, _archive(), qd_offset=offset)
        assert f"coverage 50%, QD score {score}" in ax.get_title()


# --- the kick's behaviour descriptors -----------------------------------------


def test_kick_descriptors_of_a_hand_made_jump_and_of_an_unstable_episode(params):
    L = params.body_length
    t = np.linspace(0, 1, 11)
    qpos = np.zeros((2, 11, 11))
    qpos[:, :, 0] = 2.0 * L * t  # steadily ahead: 2 body lengths by the end
    qpos[:, :, 2] = 0.1 + 4 * L * t * (1 - t)  # rise of 1 L at t = 0.5
    d = kick_descriptors(qpos, L)
    assert d["apex_rise"][0] == pytest.approx(1.0)
    assert d["apex_distance"][0] == pytest.approx(1.0)
    assert d["apex_angle"][0] == pytest.approx(45.0)
    res = RolloutResult({"qpos": qpos}, np.array([False, True]), np.array([10, 3]))
    got = Kick().describe(res, params, ("apex_angle", "apex_rise"))
    np.testing.assert_allclose(got, [[45.0, 1.0], [0.0, 0.0]])  # unstable: low


def test_descriptors_of_the_rule_based_kick(params):
    """The paper's rule-based kick from the ready posture: its apex in the
    first 300 steps is 3.18 body lengths up and 0.57 ahead, at 79.8 deg."""
    rules = run_rules(steps=Kick.n_steps, model_params=params)
    res = RolloutResult(
        {"qpos": rules.qpos[None]}, np.array([False]), np.array([Kick.n_steps])
    )
    names = ("apex_rise", "apex_distance", "apex_angle")
    got = Kick().describe(res, params, names)[0]
    q = rules.qpos
    top = int(np.argmax(q[:, 2]))  # the plain reading of the docstring
    rise, ahead = q[top, 2] - q[0, 2], q[top, 0] - q[0, 0]
    L = params.body_length
    np.testing.assert_allclose(
        got, [rise / L, ahead / L, math.degrees(math.atan2(rise, ahead))]
    )
    np.testing.assert_allclose(got, [3.182, 0.5728, 79.79], rtol=2e-3)


def test_the_config_resolves_the_tasks_descriptors_and_refuses_others(tmp_path):
    cfg = TrainConfig(optimizer=MapElitesParams())
    assert cfg.optimizer.descriptors == ("apex_distance", "apex_rise")
    assert cfg.optimizer.ranges == ((-5.0, 15.0), (0.0, 5.0))
    assert cfg.optimizer.cells == (10, 10)
    rundir.write_config(tmp_path / "c.toml", cfg)
    assert rundir.load_config(tmp_path / "c.toml") == cfg
    angle = TrainConfig(optimizer=CMAMEParams(descriptors=("apex_angle",)))
    assert angle.optimizer.ranges == ((0.0, 180.0),)
    with pytest.raises(ValueError, match="unknown descriptor 'height'; kick declares"):
        TrainConfig(optimizer=MapElitesParams(descriptors=("height",)))
    with pytest.raises(ValueError, match="getup declares none"):
        TrainConfig(behaviour="getup", optimizer=MapElitesParams())


# --- a repertoire run ---------------------------------------------------------


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


def test_the_rule_based_kick_descriptors_use_the_models_scale():
    """Descriptors are in body lengths: doubling the creature's scale leaves
    a trajectory scaled with it where it was."""
    small, big = lm.LocustParams(), lm.LocustParams(scale=20.0)
    qpos = np.zeros((1, 3, 11))
    qpos[0, 1, :3] = (small.body_length, 0, 2 * small.body_length)
    a = kick_descriptors(qpos, small.body_length)
    b = kick_descriptors(qpos * big.body_length / small.body_length, big.body_length)
    for k in a:
        np.testing.assert_allclose(a[k], b[k])


_THREADS = """
import hashlib, numpy as np
from locustjump.evo import make_optimizer, CMAMEParams
p = CMAMEParams(population=50, descriptors=("a", "b"), ranges=((0, 1), (0, 1)),
                cells=(10, 10))
o = make_optimizer(p, 144, 0)
for g in range(40):
    x = o.ask()
    o.tell(-np.sum((x - 0.3) ** 2, 1), np.clip(np.abs(x[:, :2]), 0, 1))
a = o.archive()
print(hashlib.sha256(a.solution.tobytes() + o.ask().tobytes()).hexdigest())
"""


@pytest.mark.slow
def test_cma_me_gives_the_same_genomes_on_any_number_of_blas_threads():
    """CMA-ME's eigendecompositions and products run on BLAS, which may
    split them among threads: 144 genes, 40 generations, 1 and 4 threads."""
    out = []
    for n in ("1", "4"):
        env = {**os.environ, "OPENBLAS_NUM_THREADS": n, "OMP_NUM_THREADS": n,
               "MKL_NUM_THREADS": n}  # fmt: skip
        r = subprocess.run([sys.executable, "-c", _THREADS], env=env,
                           capture_output=True, text=True, check=True)  # fmt: skip
        out.append(r.stdout.strip())
    assert out[0] == out[1]


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
