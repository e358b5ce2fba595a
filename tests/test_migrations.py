"""Older file formats (locustjump.rundir.migrations): read as they were meant,
hashed as they were, and a newer format refused in one line."""

import json

import numpy as np
import pytest

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.evo import CMAParams
from locustjump.rundir import migrations
from locustjump.rundir.config import TrainConfig
from locustjump.sim.params import LocustParams

#: config hashes computed by e4febb0 (before the engine was the run's and
#: before config format 2): the default config, on the compiled engine
#: (``model.engine = "numba"``) and on NumPy (no engine key)
HASH_NUMBA = "1c1e0a431ebc3af3"
HASH_NUMPY = "732d98bacb9a8b94"


def _format1(cfg: TrainConfig, **model) -> dict:
    """``cfg``'s table as format 1 spelled it."""
    d = cfg.to_dict()
    del d["format"], d["engine"]
    d["model"].update(model)
    if "frozen_digest" in d:
        d["simple"] = d.pop("frozen_digest")
    return d


def test_new_configs_record_their_format_and_engine_and_keep_the_old_hashes():
    new = TrainConfig()
    d = new.to_dict()
    assert d["format"] == migrations.CONFIG_FORMAT == 2
    assert d["engine"] == "numba" and "engine" not in d["model"]
    assert (new.hash(), new.replace(engine="numpy").hash()) == (HASH_NUMBA, HASH_NUMPY)


@pytest.mark.parametrize(
    ("model", "engine"), [({"engine": "numba"}, "numba"), ({}, "numpy")]
)
def test_format1_engine_under_model_or_absent_reads_as_the_runs(
    tmp_path, model, engine
):
    cfg = TrainConfig(behaviour="composed", frozen_digest="ab" * 8)
    rundir.write_toml(tmp_path / "config.toml", _format1(cfg, **model))
    read = rundir.load_config(tmp_path / "config.toml")
    assert read.engine == engine and read.frozen_digest == "ab" * 8
    assert read == cfg.replace(engine=engine)
    assert read.hash() == cfg.replace(engine=engine).hash()


@pytest.mark.parametrize(
    "text", ["[model]\nsubsteps = 6\n", 'behaviour = "getup"\n[model]\nscale = 10.0\n']
)
def test_a_partial_config_with_a_model_table_gets_todays_engine(tmp_path, text):
    """A hand-written --config naming part of [model] is today's spelling, not
    a run's config.toml from before the compiled engine (those name every
    field: NumPy, above)."""
    (tmp_path / "c.toml").write_text(text)
    assert rundir.load_config(tmp_path / "c.toml").engine == TrainConfig().engine


def test_format1_rcga_table_reads_as_the_rcga(tmp_path):
    d = _format1(TrainConfig(), engine="numba")
    d["rcga"] = {k: v for k, v in d.pop("optimizer").items() if k != "kind"}
    rundir.write_toml(tmp_path / "config.toml", d)
    assert rundir.load_config(tmp_path / "config.toml") == TrainConfig()
    other = TrainConfig(optimizer=CMAParams())
    assert other.hash() not in (HASH_NUMBA, HASH_NUMPY)


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["model"].update(engine="numba"), "unknown key 'model.engine'"),
        (lambda d: d.update(format=3), r"newer locustjump \(config format 3"),
        (lambda d: d.update(format="2"), "format must be an integer"),
        (lambda d: d.update(simple="x"), "unknown key 'simple'"),
    ],
)
def test_format2_refuses_older_spellings_and_newer_formats(tmp_path, edit, message):
    d = TrainConfig().to_dict()
    edit(d)
    rundir.write_toml(tmp_path / "config.toml", d)
    with pytest.raises(UserError, match=message):
        rundir.load_config(tmp_path / "config.toml")


def test_format1_with_both_spellings_is_refused(tmp_path):
    d = _format1(TrainConfig(), engine="numba")
    d["engine"] = "numpy"
    rundir.write_toml(tmp_path / "config.toml", d)
    with pytest.raises(UserError, match="not two"):
        rundir.load_config(tmp_path / "config.toml")


def test_markers_summaries_and_frozen_files_of_older_versions(tmp_path):
    assert migrations.reproduction_marker({"budget": "quick"}) == {
        "budget": "quick", "optimizer": "rcga", "engine": "numpy",
        "scene": {"kind": "flat", "terrains": 1, "aggregate": "mean"},
    }  # fmt: skip
    model = json.loads(json.dumps(rundir.config._table(LocustParams())))
    old = migrations.rules_summary({"model": {**model, "engine": "numpy"}}, "numba")
    assert old["engine"] == "numpy" and "engine" not in old["model"]
    assert migrations.rules_summary({}, "numba") == {"model": {}, "engine": "numba"}
    assert migrations.frozen_path(tmp_path) == tmp_path / rundir.FROZEN
    np.savez(tmp_path / migrations.FROZEN_BEFORE, x=np.zeros(1))
    assert migrations.frozen_path(tmp_path) == tmp_path / "simple.npz"
    np.savez(tmp_path / rundir.FROZEN, x=np.zeros(1))
    assert migrations.frozen_path(tmp_path) == tmp_path / rundir.FROZEN


def test_a_newer_npz_format_is_refused_in_one_line(tmp_path):
    best = rundir.BestGenome(np.zeros(3), 1.0, 1, "kick", "0" * 16)
    best.save(tmp_path / "best.npz")
    assert rundir.BestGenome.load(tmp_path / "best.npz", 3).fitness == 1.0
    z = dict(np.load(tmp_path / "best.npz"))
    np.savez(tmp_path / "best.npz", **{**z, "format": np.array(rundir.FORMAT + 1)})
    with pytest.raises(UserError, match="a newer locustjump wrote it"):
        rundir.BestGenome.load(tmp_path / "best.npz", 3)
