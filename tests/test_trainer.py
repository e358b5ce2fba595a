"""Which run directory :func:`locustjump.runs.trainer.train` may write, new or
resumed, and what it refuses, in one line and before writing anything, on
the formula behaviour of ``tests/helpers.py`` (no physics)."""

import dataclasses
import threading
from pathlib import Path

import numpy as np
import pytest

from formula import Formula, formula_config
from helpers import user_error
from locustjump import rundir
from locustjump.evo import CMAParams, RCGAParams
from locustjump.runs import loop, trainer
from locustjump.runs.trainer import train
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.rollout import rollout_bytes
from locustjump.sim.model import load_model
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks.options import CommonOptions

pytestmark = pytest.mark.usefixtures("formula")


def _files(d):
    return sorted(p.name for p in d.iterdir())


def test_a_new_run_goes_into_an_empty_or_absent_directory(tmp_path):
    (tmp_path / "empty").mkdir()
    for out in (tmp_path / "empty", tmp_path / "new" / "deeper"):
        assert train(formula_config(), out, progress=False).generation == 4
        assert {"config.toml", "metrics.csv", "best.npz", "checkpoint.npz"} <= set(
            _files(out)
        )


def test_a_run_stopped_before_its_config_starts_again(tmp_path):
    out = tmp_path / "r"
    out.mkdir()
    (out / ".config.tmp.toml").write_text("half")
    (out / "frozen.npz").write_bytes(b"old")
    train(formula_config(), out, progress=False)
    assert ".config.tmp.toml" not in _files(out) and "frozen.npz" not in _files(out)


def test_a_directory_in_use_is_refused_before_anything_is_written(tmp_path):
    run, other = tmp_path / "run", tmp_path / "other"
    train(formula_config(), run, progress=False, stop_after=1)
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    before = {d: _files(d) for d in (run, other)}
    assert user_error(train, formula_config(), run, progress=False) == (
        f"out {run}: directory holds a run (use resume=True to continue a run, or "
        "choose another out)"
    )
    assert user_error(train, formula_config(), other, progress=False) == (
        f"out {other}: directory is not empty (use resume=True to continue a run, "
        "or choose another out)"
    )
    afile = tmp_path / "afile"
    afile.write_text("x")
    assert user_error(train, formula_config(), afile, progress=False) == (
        f"out {afile}: exists and is not a directory"
    )
    assert {d: _files(d) for d in (run, other)} == before


def test_a_run_resumed_must_be_the_same_run(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False, stop_after=1)
    before = (out / "metrics.csv").read_bytes()
    resume = {"progress": False, "resume": True}
    assert user_error(train, formula_config(behaviour="kick"), out, **resume) == (
        f"resume=True: {out} holds a 'formula' run, not 'kick'"
    )
    cma = formula_config(optimizer=CMAParams(population=6))
    assert user_error(train, cma, out, **resume) == (
        f"resume=True: {out} was trained with the 'rcga' optimizer, not 'cma'"
    )
    assert user_error(train, formula_config(seed=6), out, **resume) == (
        f"resume=True: seed 6 differs from the run's seed 5 ({out / 'config.toml'})"
    )
    two = formula_config(seed=6, optimizer=RCGAParams(population=8))
    assert user_error(train, two, out, **resume) == (
        f"resume=True: optimizer.population 8 differs from the run's "
        f"optimizer.population 6 ({out / 'config.toml'}) (and 1 more)"
    )
    assert user_error(train, formula_config(), tmp_path / "none", **resume) == (
        f"resume=True: {tmp_path / 'none'} holds no run (no config.toml)"
    )
    assert (out / "metrics.csv").read_bytes() == before


def test_a_resumed_run_takes_the_checkpoints_metrics_row(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False, stop_after=2)
    lines = (out / "metrics.csv").read_text().splitlines()
    (out / "metrics.csv").write_text("\n".join(lines[:2]) + "\n")  # row 2 lost
    trainer._resume(out, formula_config(), ThreadBackend(1), False)
    again = (out / "metrics.csv").read_text().splitlines()
    _, row, _ = rundir.read_checkpoint(out / "checkpoint.npz", formula_config(), 144)
    assert again == [*lines[:2], row.strip()]  # the checkpoint held it
    assert again[2].split(",")[:4] == lines[2].split(",")[:4]  # (its own wall time)


def test_a_metrics_column_of_another_optimizer_is_named(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False, stop_after=1)
    text = (out / "metrics.csv").read_text().splitlines()
    text[0] += ",sigma"
    text[1] += ",0.5"
    (out / "metrics.csv").write_text("\n".join(text) + "\n")
    assert user_error(train, formula_config(), out, progress=False, resume=True) == (
        f"{out / 'metrics.csv'}: column 'sigma' is not a diagnostic of the 'rcga' "
        "optimizer"
    )


def test_a_run_whose_first_genomes_cannot_be_made_is_named(tmp_path, monkeypatch):
    from locustjump.evo.rcga import RCGA

    def nan(self):
        return np.full((6, 144), np.nan)

    monkeypatch.setattr(RCGA, "ask", nan)
    out = tmp_path / "r"
    assert user_error(train, formula_config(), out, progress=False) == (
        "[optimizer]: the first genomes are not finite"
    )

    def overflow(self):
        raise OverflowError("too large")

    monkeypatch.setattr(RCGA, "ask", overflow)
    assert user_error(train, formula_config(), out, progress=False) == (
        "[optimizer]: cannot make the first genomes (too large)"
    )
    assert not out.exists()


def test_a_composed_run_needs_the_runs_it_builds_on(tmp_path):
    out = tmp_path / "r"
    assert user_error(
        train, formula_config(behaviour="composed"), out, progress=False
    ) == (  # fmt: skip
        "train composed needs the runs it builds on (frozen_kick DIR frozen_getup "
        "DIR frozen_return_legs DIR)"
    )
    assert not out.exists()


def test_the_budget_shown_for_a_difference(tmp_path):
    assert trainer._shown([1, 2]) == "1,2" and trainer._shown([]) == "none"
    assert trainer._shown(None) == "none" and trainer._shown(0.5) == "0.5"
    assert trainer._differences(
        {"a": 1, "t": {"x": 1, "y": 2}, "generations": 9, "format": 2},
        {"a": 2, "t": {"x": 1, "y": 3}, "b": 4, "generations": 3},
    ) == [("a", 1, 2), ("b", None, 4), ("t.y", 2, 3)]
    assert trainer._differences({"t": {"x": 1}}, {"t": 3}) == [("t", {"x": 1}, 3)]


def test_a_longer_budget_is_recorded_only_once_the_run_is_checked(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False)
    assert Formula.calls == 4
    r = train(formula_config(generations=5), out, progress=False, resume=True)
    assert (
        r.generation == 5 and rundir.load_config(out / "config.toml").generations == 5
    )


STUDY = Path(__file__).resolve().parent.parent / "results" / "study"
SIMPLE = ("kick", "getup", "return-legs")


def _frozen():
    model = rundir.load_run(STUDY / "debris-kick-s0")[0].model
    dirs = {b: STUDY / f"debris-{b}-s0" for b in SIMPLE}
    return rundir.FrozenGenomes.from_runs(SIMPLE, dirs, model, 144)


def _composed(**kw):
    return formula_config(behaviour="formula-composed", **kw)


def test_a_composed_run_keeps_the_genomes_it_builds_on(tmp_path):
    frozen, out = _frozen(), tmp_path / "r"
    r = train(_composed(), out, progress=False, frozen=frozen, stop_after=2)
    assert r.generation == 2
    cfg = rundir.load_config(out / "config.toml")
    assert cfg.frozen_digest == frozen.digest
    kept = rundir.frozen_of(cfg, out)
    np.testing.assert_array_equal(kept.genomes, frozen.genomes)
    assert kept.sources == frozen.sources
    assert rundir.load_run(out)[1].controller.num_params == 133
    # resumed with or without them, and its digest in the config or not
    assert train(_composed(), out, progress=False, resume=True, stop_after=1,
                 frozen=frozen).generation == 3  # fmt: skip
    assert train(_composed(), out, progress=False, resume=True,  # neither
                 stop_after=1).generation == 4  # fmt: skip
    named = _composed(frozen_digest=frozen.digest, generations=5)
    assert train(named, out, progress=False, resume=True).generation == 5
    whole = tmp_path / "whole"
    train(_composed(generations=5), whole, progress=False, frozen=frozen)
    assert (out / "metrics.csv").read_text().count("\n") == 6
    with np.load(out / "best.npz") as a, np.load(whole / "best.npz") as b:
        np.testing.assert_array_equal(a["genome"], b["genome"])


def test_a_composed_run_with_other_genomes_is_refused(tmp_path):
    frozen, out = _frozen(), tmp_path / "r"
    other = _composed(frozen_digest="0123456789abcdef")
    assert user_error(train, other, out, progress=False, frozen=frozen) == (
        f"the frozen genomes (digest {frozen.digest}) are not the ones the "
        "configuration names (0123456789abcdef)"
    )
    assert not out.exists()
    train(_composed(frozen_digest=frozen.digest), out, progress=False,
          frozen=frozen, stop_after=1)  # fmt: skip
    assert user_error(train, other, out, progress=False, resume=True) == (
        f"resume=True: frozen_digest 0123456789abcdef differs from the run's "
        f"frozen_digest {frozen.digest} ({out / 'config.toml'})"
    )


def test_a_simple_run_ignores_frozen_genomes_given(tmp_path):
    r = train(formula_config(), tmp_path / "r", progress=False, frozen=_frozen())
    assert r.generation == 4
    assert rundir.load_config(tmp_path / "r" / "config.toml").frozen_digest == ""


def test_a_new_run_is_the_behaviour_of_its_config(tmp_path, monkeypatch):
    asked = []
    monkeypatch.setattr(trainer, "require_memory", lambda *a, **k: asked.append((a, k)))
    monkeypatch.setattr(Formula, "start_states", lambda self, p: [0, 1, 2])
    cfg = formula_config(scene=Terrains(Debris(seed=3), 2, "min"),
                         options=CommonOptions((6,)))  # fmt: skip
    backend = ThreadBackend(1)
    run = trainer._check_new(tmp_path / "r", cfg, Formula, None, backend)
    assert run.beh.terrains == cfg.scene and run.beh.options == cfg.options
    assert run.backend is backend and run.cfg == cfg and run.out == tmp_path / "r"
    need = rollout_bytes(load_model(cfg.model, Debris(seed=3)), 6 * 3 * 2,
                         run.beh.n_steps, run.beh.record)  # fmt: skip
    assert asked == [((need, "a generation of 6 genomes"),
                      {"setting": ("population", 6)})]  # fmt: skip
    assert not (tmp_path / "r").exists()


def test_a_resumed_run_is_evaluated_on_the_backend_given(tmp_path):
    out, backend = tmp_path / "r", ThreadBackend(1)
    train(formula_config(), out, progress=False, stop_after=1)
    train(formula_config(), out, progress=False, resume=True, backend=backend)
    assert [g[1] for g in Formula.given[1:]] == [backend] * 3
    Formula.reset()
    train(formula_config(), tmp_path / "d", progress=False, stop_after=1)
    assert isinstance(Formula.given[0][1], ThreadBackend)  # the default


def test_a_finished_run_resumed_at_its_budget_does_nothing(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False)
    assert train(formula_config(), out, progress=False, resume=True).generation == 4
    assert Formula.calls == 4


def test_a_kept_best_genome_of_another_size_is_named(tmp_path):
    out = tmp_path / "r"
    train(formula_config(), out, progress=False, stop_after=1)
    best = rundir.BestGenome.load(out / "best.npz")
    short = dataclasses.replace(best, genome=best.genome[:10])
    short.save(out / "best.npz")
    assert user_error(train, formula_config(), out, progress=False, resume=True) == (
        f"{out / 'best.npz'}: genome has 10 genes, the formula controller needs 144"
    )


def _cma(**kw):
    return formula_config(optimizer=CMAParams(population=6), **kw)


def test_a_resumed_run_without_metrics_keeps_the_checkpoints_columns(tmp_path):
    out = tmp_path / "r"
    train(_cma(), out, progress=False, stop_after=1)
    (out / "metrics.csv").unlink()
    train(_cma(), out, progress=False, resume=True, stop_after=1)
    lines = (out / "metrics.csv").read_text().splitlines()
    assert lines[0].endswith(",sigma,condition") and len(lines) == 3
    assert all(line.count(",") == 9 for line in lines)
    # a checkpoint written before the optimizer had diagnostics: none
    old = tmp_path / "old"
    train(_cma(), old, progress=False, stop_after=1)
    with np.load(old / "checkpoint.npz") as z:
        arrays = {k: z[k] for k in z.files}
    row = str(arrays["metrics_row"]).strip().split(",")
    arrays["metrics_row"] = np.array(",".join(row[:8]) + "\n")
    rundir.save_npz(old / "checkpoint.npz", **arrays)
    (old / "metrics.csv").unlink()
    train(_cma(), old, progress=False, resume=True, stop_after=1)
    lines = (old / "metrics.csv").read_text().splitlines()
    assert lines[0] == ",".join(rundir.METRICS_COLUMNS) and len(lines) == 3
    assert all(line.count(",") == 7 for line in lines)


def test_a_new_run_that_fails_while_made_leaves_nothing(tmp_path, monkeypatch):
    def full(path, cfg):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(rundir, "write_config", full)
    out = tmp_path / "new" / "r"
    with pytest.raises(OSError):
        train(formula_config(), out, progress=False)
    assert not (tmp_path / "new").exists()


def test_progress_is_shown_unless_told_not_to(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(loop.tqdm, "_lock", threading.RLock(), raising=False)
    train(formula_config(), tmp_path / "r", stop_after=1)  # shown by default
    assert "formula:  25%|" in capsys.readouterr().err
    train(formula_config(), tmp_path / "r", resume=True, progress=False, stop_after=1)
    assert capsys.readouterr().err == ""
    train(formula_config(), tmp_path / "r", resume=True, progress=True)
    assert "formula: 100%|" in capsys.readouterr().err
