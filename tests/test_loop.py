"""The training loop and the run it writes (:mod:`locustjump.runs.loop`,
:mod:`locustjump.runs.trainer`), on a behaviour whose fitness is a formula of
the genome: no physics, so that every generation takes milliseconds and
every row, best genome and checkpoint can be stated exactly. The same loop
with the physics: ``tests/test_runs.py``."""

import json
import re
import threading

import numpy as np
import pytest

from formula import STEPS, Formula, formula_config
from helpers import user_error
from locustjump import rundir
from locustjump.evo import CMAParams, MapElitesParams
from locustjump.runs import loop, trainer
from locustjump.runs.trainer import train
from locustjump.sim.engine.backends import ThreadBackend

pytestmark = pytest.mark.usefixtures("formula")


_cfg = formula_config


def _rows(out):
    """metrics.csv without its wall-time columns (wall_s, steps_per_s)."""
    lines = (out / rundir.METRICS).read_text().splitlines()
    cut = [line.split(",") for line in lines]
    return [[c for i, c in enumerate(r) if i not in (4, 7)] for r in cut]


def test_a_run_writes_a_row_a_best_and_a_checkpoint_each_generation(tmp_path):
    out = tmp_path / "run"
    r = train(_cfg(), out, progress=False)
    assert (r.out, r.generation, r.stopped) == (out, 4, {})
    rows = _rows(out)
    assert rows[0] == ["generation", "best", "mean", "std", "evaluations",
                       "control_steps"]  # fmt: skip
    assert [row[0] for row in rows[1:]] == ["1", "2", "3", "4"]
    # the first generation evaluates all 6; then the 2 elites keep their fitness
    assert [row[4:] for row in rows[1:]] == [["6", str(6 * STEPS)]] + [
        ["4", str(4 * STEPS)]
    ] * 3
    m = rundir.read_metrics(out / rundir.METRICS)
    best = rundir.BestGenome.load(out / rundir.BEST)
    assert best.fitness == m["best"].max() == r.best.fitness
    assert best.generation == int(m["generation"][np.argmax(m["best"])])
    assert best.fitness == -((best.genome - 0.3) ** 2).sum()  # its own fitness
    assert (best.behaviour, best.config_hash) == ("formula", _cfg().hash())
    cfg = rundir.load_config(out / rundir.CONFIG)
    ck_best, ck_row, _ = rundir.read_checkpoint(out / rundir.CHECKPOINT, cfg, 144)
    assert ck_best.fitness == best.fitness and ck_row.startswith("4,")
    assert ck_row.split(",")[1:4] == [str(m["best"][-1]), str(m["mean"][-1]),
                                      str(m["std"][-1])]  # fmt: skip
    assert (out / rundir.FITNESS_PNG).is_file() and not (out / rundir.STOP).exists()
    assert not (out / rundir.ARCHIVE).exists() and r.wall_s > 0


def test_a_row_holds_the_generations_best_mean_and_spread(tmp_path, monkeypatch):
    seen = []
    original = Formula.evaluate

    def evaluate(self, genomes, p, **kw):
        fit, res = original(self, genomes, p, **kw)
        seen.append(fit)
        return fit, res

    monkeypatch.setattr(Formula, "evaluate", evaluate)
    # CMA-ES: every genome evaluated each generation, held in the order asked
    train(_cfg(optimizer=CMAParams(population=6)), tmp_path / "r", progress=False)
    m = rundir.read_metrics(tmp_path / "r" / rundir.METRICS)
    for row, fit in zip(m, seen, strict=True):
        assert (row["best"], row["mean"], row["std"]) == (
            fit.max(), fit.mean(), fit.std()
        )  # fmt: skip
    assert m.dtype.names[8:] == ("sigma", "condition")


def test_the_times_in_a_row_are_the_generations_own(tmp_path):
    out = tmp_path / "r"
    r = train(_cfg(optimizer=CMAParams(population=6)), out, progress=False)
    m = rundir.read_metrics(out / rundir.METRICS)
    assert 0 < m["wall_s"].max() < 60 and 0 < r.wall_s < 60
    assert all(_rate_fits(*r) for r in m[["control_steps", "wall_s", "steps_per_s"]])
    cfg = rundir.load_config(out / rundir.CONFIG)
    _, row, _ = rundir.read_checkpoint(out / rundir.CHECKPOINT, cfg, 144)
    cells = row.strip().split(",")
    last = (out / rundir.METRICS).read_text().splitlines()[-1].split(",")
    assert len(cells) == len(last) == 10  # with CMA-ES's two columns
    assert cells[8:] == last[8:] and cells[:4] == last[:4]
    wall, steps, rate = float(cells[4]), int(cells[6]), float(cells[7])
    assert 0 < wall < 60 and _rate_fits(steps, wall, rate)


def _rate_fits(steps, wall, rate):
    """Whether ``rate`` is ``steps / wall`` for a wall time rounded to 0.1 ms
    (as written) and a rate rounded to 0.1."""
    return steps / (wall + 5e-5) - 0.05 <= rate <= steps / max(wall - 5e-5, 1e-9) + 0.05


def test_the_run_is_evaluated_with_its_model_backend_and_engine(tmp_path):
    backend = ThreadBackend(threads=1)
    cfg = _cfg(engine="numpy")
    train(cfg, tmp_path / "r", progress=False, backend=backend, stop_after=2)
    assert Formula.given == [(cfg.model, backend, "numpy")] * 2
    Formula.given = []
    qd = _cfg(optimizer=_qd())
    train(qd, tmp_path / "q", progress=False, backend=backend, stop_after=1)
    assert Formula.given == [(qd.model, backend, qd.engine),
                             (qd.model, ("apex_distance", "apex_rise"))]  # fmt: skip


def test_the_best_genome_is_the_first_of_the_best_fitness(tmp_path):
    Formula.coarse = True  # whole tens: later genomes tie with the best
    out = tmp_path / "r"
    train(_cfg(generations=6), out, progress=False)
    m = rundir.read_metrics(out / rundir.METRICS)
    best = rundir.BestGenome.load(out / rundir.BEST)
    first = int(m["generation"][np.flatnonzero(m["best"] == m["best"].max())[0]])
    assert best.generation == first and best.fitness == m["best"].max()


def test_a_stopped_and_resumed_run_is_the_uninterrupted_one(tmp_path):
    whole, parts = tmp_path / "whole", tmp_path / "parts"
    train(_cfg(), whole, progress=False)
    r = train(_cfg(), parts, progress=False, stop_after=1)
    assert r.generation == 1 and len(_rows(parts)) == 2
    assert (
        train(_cfg(), parts, progress=False, resume=True, stop_after=2).generation == 3
    )
    train(_cfg(), parts, progress=False, resume=True)
    assert _rows(parts) == _rows(whole)
    for name in (rundir.BEST, rundir.CHECKPOINT):
        with np.load(whole / name) as a, np.load(parts / name) as b:
            assert a.files == b.files
            for k in a.files:
                if k != "metrics_row":  # its wall time differs
                    np.testing.assert_array_equal(a[k], b[k], err_msg=k)


def test_a_run_extended_goes_on_from_its_last_generation(tmp_path):
    out = tmp_path / "r"
    train(_cfg(), out, progress=False)
    r = train(_cfg().replace(generations=6), out, progress=False, resume=True)
    assert r.generation == 6 and len(_rows(out)) == 7
    assert rundir.load_config(out / rundir.CONFIG).generations == 6
    whole = tmp_path / "whole"
    train(_cfg().replace(generations=6), whole, progress=False)
    assert _rows(out) == _rows(whole)
    assert user_error(train, _cfg(), out, progress=False, resume=True) == (
        f"generations 4: the run in {out} has already done 6 (a run can be "
        "extended, not shortened)"
    )


def test_an_optimizer_that_stops_says_why_and_the_run_ends(tmp_path, monkeypatch):
    from locustjump.evo.rcga import RCGA

    monkeypatch.setattr(
        RCGA, "stop", lambda self: {"tired": 1.5} if self.generation >= 2 else {}
    )
    out = tmp_path / "r"
    r = train(_cfg(), out, progress=False)
    assert (r.generation, r.stopped) == (2, {"tired": 1.5})
    assert json.loads((out / rundir.STOP).read_text()) == {
        "generation": 2, "reasons": {"tired": 1.5}
    }  # fmt: skip
    assert len(_rows(out)) == 3
    r = train(_cfg(), out, progress=False, resume=True)  # stopped: stays stopped
    assert (r.generation, r.stopped) == (2, {"tired": 1.5}) and len(_rows(out)) == 3


def test_a_failed_generation_keeps_the_last_one_and_its_figure(tmp_path):
    out = tmp_path / "r"
    Formula.fail_at = 3
    with pytest.raises(RuntimeError, match="the simulation broke"):
        train(_cfg(), out, progress=False)
    assert len(_rows(out)) == 3  # generations 1 and 2
    assert (out / rundir.FITNESS_PNG).is_file()
    Formula.fail_at = None
    assert train(_cfg(), out, progress=False, resume=True).generation == 4


def test_a_failed_figure_after_a_failed_generation_reports_the_first(
    tmp_path, monkeypatch
):
    def broken(out):
        raise OSError("no figure")

    monkeypatch.setattr(loop, "fitness_figure", broken)
    Formula.fail_at = 2
    with pytest.raises(RuntimeError, match="the simulation broke"):
        train(_cfg(), tmp_path / "a", progress=False)
    Formula.fail_at = None
    with pytest.raises(OSError, match="no figure"):  # the run's only failure
        train(_cfg(), tmp_path / "b", progress=False)


def test_progress_is_shown_on_request(tmp_path, capsys, monkeypatch):
    # a lock of this process only: tqdm's default also holds a semaphore that
    # forked processes share (the mutation tool's), which one that dies
    # holding it would leave locked for the rest
    monkeypatch.setattr(loop.tqdm, "_lock", threading.RLock(), raising=False)
    train(_cfg(), tmp_path / "quiet", progress=False, stop_after=2)
    assert capsys.readouterr().err == ""
    train(_cfg(), tmp_path / "quiet", progress=True, resume=True)
    err = capsys.readouterr().err
    m = rundir.read_metrics(tmp_path / "quiet" / rundir.METRICS)
    assert err.startswith("\rformula:  50%|") and " 2/4 [" in err  # from where it was
    assert " 4/4 [" in err and "gen/s, " in err
    last = m[-1]
    assert f"best={last['best']:.4g}, mean={last['mean']:.4g}, steps_s=" in err
    shown = re.findall(r"steps_s=(\d[\d,]*)", err)[-1]  # as written, about
    assert abs(int(shown.replace(",", "")) / last["steps_per_s"] - 1) < 0.3
    run = trainer._resume(tmp_path / "quiet", _cfg(generations=5), ThreadBackend(1),
                          False)  # fmt: skip
    run.run()  # a Trainer shows its progress unless told not to
    assert "formula: 100%|" in capsys.readouterr().err


def test_an_optimizer_is_asked_to_stop_only_after_a_generation(tmp_path, monkeypatch):
    from locustjump.evo.rcga import RCGA

    monkeypatch.setattr(RCGA, "stop", lambda self: {"never started": 1})
    r = train(_cfg(), tmp_path / "r", progress=False)
    assert (r.generation, r.stopped) == (1, {"never started": 1})


def test_the_figure_is_titled_with_the_behaviour_and_seed(tmp_path, monkeypatch):
    drawn = []
    monkeypatch.setattr(loop, "fitness_curves", lambda *a, **k: drawn.append((a, k)))
    out = tmp_path / "r"
    train(_cfg(), out, progress=False, stop_after=1)
    (path, m), kw = drawn[-1]
    assert path == out / rundir.FITNESS_PNG and len(m) == 1
    assert kw == {"title": "formula: fitness per generation (seed 5)"}


def test_a_run_stopped_before_its_first_metrics_starts_over_alike(tmp_path):
    out, whole = tmp_path / "r", tmp_path / "whole"
    train(_cfg(), out, progress=False, stop_after=1)
    for name in (rundir.METRICS, rundir.BEST, rundir.CHECKPOINT):
        (out / name).unlink()  # as if killed between config.toml and metrics.csv
    train(_cfg(), out, progress=False, resume=True)
    train(_cfg(), whole, progress=False)
    assert _rows(out) == _rows(whole)


def test_a_checkpoint_holding_other_state_is_refused(tmp_path):
    out = tmp_path / "r"
    train(_cfg(), out, progress=False, stop_after=1)
    with np.load(out / rundir.CHECKPOINT) as z:
        arrays = {k: z[k] for k in z.files}
    rundir.save_npz(out / rundir.CHECKPOINT, **arrays, opt_sigma=np.array(0.5))
    assert user_error(train, _cfg(), out, progress=False, resume=True).startswith(
        f"{out / rundir.CHECKPOINT}: "
    )


def test_a_call_trains_at_least_one_generation(tmp_path):
    for n in (0, -1, 1.0):
        assert user_error(train, _cfg(), tmp_path / "r", stop_after=n).startswith(
            "stop_after must be an integer in [1, "
        )
    assert not (tmp_path / "r").exists()


def test_no_figure_before_a_first_row(tmp_path):
    out = tmp_path / "r"
    rundir.write_config(out.mkdir() or out / rundir.CONFIG, _cfg())
    rundir.truncate_metrics(out / rundir.METRICS, 0, "")
    assert loop.fitness_figure(out) == out / rundir.FITNESS_PNG
    assert not (out / rundir.FITNESS_PNG).exists()


def _qd():
    return MapElitesParams(population=6, descriptors=("apex_distance", "apex_rise"),
                           ranges=((0.0, 1.0), (0.0, 1.0)), cells=(4, 4))  # fmt: skip


def test_a_repertoire_run_keeps_its_archive_each_generation(tmp_path):
    out = tmp_path / "r"
    cfg = _cfg(optimizer=_qd())
    train(cfg, out, progress=False, stop_after=2)
    a = rundir.read_archive(out, cfg, 144)
    m = rundir.read_metrics(out / rundir.METRICS)
    assert m["coverage"][-1] == a.coverage and len(m) == 2
    (out / rundir.ARCHIVE).unlink()  # killed between the checkpoint and the archive
    trainer._resume(out, cfg, ThreadBackend(1), False)  # restores it
    b = rundir.read_archive(out, cfg, 144)
    np.testing.assert_array_equal(a.solution, b.solution)
    train(cfg, out, progress=False, resume=True)
    assert (out / rundir.ARCHIVE_PNG).is_file()


def test_a_malformed_optimizer_state_is_named(tmp_path, monkeypatch):
    from locustjump.evo.rcga import RCGA

    out = tmp_path / "r"
    train(_cfg(), out, progress=False, stop_after=1)

    def broken(self, state):
        raise KeyError("population")

    monkeypatch.setattr(RCGA, "load_state", broken)
    assert user_error(train, _cfg(), out, progress=False, resume=True) == (
        f"{out / rundir.CHECKPOINT}: malformed checkpoint ('population')"
    )
