"""A run directory read back (:mod:`locustjump.rundir.run`): its config, its
best genome, the frozen genomes a composed run builds on, each checked
against the run, on shipped runs (read only) and copies changed on purpose."""

import hashlib
import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import user_error
from locustjump import rundir
from locustjump.rundir import run as rr
from locustjump.rundir.config import TrainConfig

STUDY = Path(__file__).resolve().parent.parent / "results" / "study"
KICK, GETUP, LEGS = (STUDY / f"debris-{b}-s0" for b in ("kick", "getup", "return-legs"))
PIPELINE = STUDY / "debris-pipeline-s0"
REPERTOIRE = STUDY / "repertoire-kick-repertoire-s1"
SIMPLES = {"kick": KICK, "getup": GETUP, "return-legs": LEGS}
REQUIRED = ("kick", "getup", "return-legs")


def test_a_partial_config_takes_the_defaults_and_the_behaviour_given(tmp_path):
    c = tmp_path / "c.toml"
    c.write_text("seed = 4\n")
    assert rr.load_config(c) == TrainConfig(seed=4)
    assert rr.load_config(c, behaviour="getup") == TrainConfig(
        behaviour="getup", seed=4
    )
    c.write_text('behaviour = "getup"\n')
    assert rr.load_config(c, behaviour="kick").behaviour == "getup"
    c.write_text("seed = -1\n")
    assert user_error(rr.load_config, c).startswith(f"{c}: seed must be ")


def test_a_config_is_written_with_its_hash_and_reads_back(tmp_path):
    cfg = TrainConfig(behaviour="getup", seed=7, generations=3)
    rr.write_config(tmp_path / "config.toml", cfg)
    text = (tmp_path / "config.toml").read_text()
    assert text.startswith(
        f"# locustjump run configuration (config hash {cfg.hash()}).\n"
        "# Edit a copy and pass it with --config to start a new run.\n"
    )
    assert rr.load_config(tmp_path / "config.toml") == cfg


def _best(**kw):
    args = {"genome": np.arange(4.0), "fitness": 1.25, "generation": 3,
            "behaviour": "kick", "config_hash": "ab"}  # fmt: skip
    args.update(kw)
    return rr.BestGenome(**args)


def test_a_best_genome_reads_back_as_written(tmp_path):
    p = tmp_path / "best.npz"
    _best().save(p)
    for n in (4, None):
        b = rr.BestGenome.load(p, n)
        assert (b.fitness, b.generation, b.behaviour, b.config_hash) == (
            1.25, 3, "kick", "ab"
        )  # fmt: skip
        np.testing.assert_array_equal(b.genome, np.arange(4.0))
    with np.load(p) as z:
        assert sorted(z.files) == ["behaviour", "config_hash", "fitness", "format",
                                   "generation", "genome"]  # fmt: skip
        assert int(z["format"]) == rundir.FORMAT
    assert rr.BestGenome.load(str(p)).genome.size == 4


def test_a_best_genome_of_another_size_or_generation_is_named(tmp_path):
    p = tmp_path / "best.npz"
    _best().save(p)
    assert user_error(rr.BestGenome.load, p, 5) == (
        f"{p}: genome has 4 genes, the kick controller needs 5"
    )
    _best(genome=np.ones((2, 2))).save(p)
    assert user_error(rr.BestGenome.load, p) == (
        f"{p}: genome has shape (2, 2), expected (4,)"
    )
    _best(genome=np.float64(1.0)).save(p)  # not even a row of genes
    assert user_error(rr.BestGenome.load, p) == (
        f"{p}: genome has shape (), expected (-1,)"
    )
    _best(genome=np.ones((2, 2))).save(p)
    assert user_error(rr.BestGenome.load, p, 4) == (
        f"{p}: genome has shape (2, 2), expected (4,)"
    )
    _best(generation=0).save(p)
    assert (
        user_error(rr.BestGenome.load, p, 4) == f"{p}: generation must be >= 1, got 0"
    )
    _best(generation=1).save(p)
    assert rr.BestGenome.load(p, 4).generation == 1


def test_a_best_genome_file_is_bounded_by_its_size(tmp_path):
    p = tmp_path / "best.npz"
    _best(genome=np.zeros(9000)).save(p)  # 72 kB of genes, for 4 expected
    assert "bytes" in user_error(rr.BestGenome.load, p, 4)
    assert rr.BestGenome.load(p, 9000).genome.size == 9000


def test_a_frozen_runs_setting_is_named_after_its_behaviour():
    assert rr.frozen_setting("return-legs") == "frozen_return_legs"
    assert rr.frozen_setting("kick") == "frozen_kick"


def test_the_frozen_genomes_of_the_shipped_pipeline_are_its_simples():
    cfg, _, _ = rr.load_run(KICK)
    f = rr.FrozenGenomes.from_runs(REQUIRED, SIMPLES, cfg.model, 144)
    assert f.behaviours == REQUIRED and f.genomes.shape == (3, 144)
    assert f.sources == tuple(str(SIMPLES[b]) for b in REQUIRED)
    assert f.hashes == tuple(rr.load_run(SIMPLES[b])[2].config_hash for b in REQUIRED)
    for row, b in zip(f.genomes, REQUIRED, strict=True):
        np.testing.assert_array_equal(row, rr.load_run(SIMPLES[b])[2].genome)
    shipped = rr.load_config(PIPELINE / "config.toml")
    assert f.digest == shipped.frozen_digest
    data = np.ascontiguousarray(f.genomes, dtype="<f8").tobytes()
    assert f.digest == hashlib.sha256(data).hexdigest()[:16]
    assert rr.FrozenGenomes.from_runs(REQUIRED, SIMPLES, cfg.model).digest == f.digest
    finer = cfg.model.replace(substeps=12)  # composed at other substeps: allowed
    assert rr.FrozenGenomes.from_runs(REQUIRED, SIMPLES, finer).digest == f.digest


def test_the_frozen_runs_that_do_not_fit_are_named():
    model = rr.load_run(KICK)[0].model
    assert user_error(
        rr.FrozenGenomes.from_runs, REQUIRED, {"kick": KICK, "getup": None}, model
    ) == (  # fmt: skip
        "this behaviour builds on frozen_kick DIR, frozen_getup DIR, "
        "frozen_return_legs DIR (missing frozen_getup)"
    )
    swapped = {**SIMPLES, "getup": LEGS}
    assert user_error(rr.FrozenGenomes.from_runs, REQUIRED, swapped, model) == (
        f"frozen_getup {LEGS}: holds a 'return-legs' run, not 'getup'"
    )
    assert user_error(rr.FrozenGenomes.from_runs, REQUIRED, SIMPLES, model, 10) == (
        f"frozen_kick {KICK}: holds a 'kick' run, not 'kick' (144 genes, not 10)"
    )
    other = model.replace(density=301.0, friction=0.5)
    assert user_error(rr.FrozenGenomes.from_runs, REQUIRED, SIMPLES, other) == (
        f"frozen_kick {KICK}: its model parameters differ from this run's "
        "(density, friction)"
    )


def test_a_repertoire_gives_its_best_elites_best_first():
    cfg, beh, _ = rr.load_run(REPERTOIRE)
    a = rundir.read_archive(REPERTOIRE, cfg, beh.controller.num_params)
    dirs = {"kick": REPERTOIRE, "getup": GETUP}
    f = rr.FrozenGenomes.from_runs(("kick", "getup"), dirs, cfg.model,
                                   elites={"kick": 3})  # fmt: skip
    assert f.behaviours == ("kick", "kick", "kick", "getup")
    assert f.sources == (str(REPERTOIRE),) * 3 + (str(GETUP),)
    for row, i in zip(f.genomes[:3], a.ranked()[:3], strict=True):
        np.testing.assert_array_equal(row, a.solution[i])
    assert user_error(
        rr.FrozenGenomes.from_runs, ("kick",), dirs, cfg.model, elites={"kick": 24}
    ) == (  # fmt: skip
        f"frozen_kick {REPERTOIRE}: its archive holds 23 elites; the composition "
        "takes 24 (option_elites)"
    )
    assert user_error(
        rr.FrozenGenomes.from_runs, ("kick",), SIMPLES, cfg.model, elites={"kick": 2}
    ) == (  # fmt: skip
        f"frozen_kick {KICK}: a rcga run; the composition takes 2 elites of a "
        "quality-diversity run's archive (map-elites, cma-me)"
    )


def test_frozen_genomes_read_back_as_written_and_as_required(tmp_path):
    f = rr.FrozenGenomes(("a", "b"), np.arange(6.0).reshape(2, 3), ("x", "y"),
                         ("h1", "h2"))  # fmt: skip
    p = tmp_path / "frozen.npz"
    f.save(p)
    g = rr.FrozenGenomes.load(p, ("a", "b"), 3)
    assert (g.behaviours, g.sources, g.hashes) == (("a", "b"), ("x", "y"), ("h1", "h2"))
    np.testing.assert_array_equal(g.genomes, f.genomes)
    assert user_error(rr.FrozenGenomes.load, p, ("b", "a"), 3) == (
        f"{p}: not the genomes of b, a"
    )
    assert user_error(rr.FrozenGenomes.load, p, ("a", "b", "c"), 3) == (
        f"{p}: behaviours must be 3 names"
    )
    assert user_error(rr.FrozenGenomes.load, p, ("a", "b"), 4) == (
        f"{p}: genomes has shape (2, 3), expected (2, 4)"
    )
    for key, bad in (("sources", np.array([1, 2])), ("hashes", np.array(["h"]))):
        rundir.save_npz(p, format=np.array(1), behaviours=np.array(["a", "b"]),
                        genomes=f.genomes, **{"sources": np.array(["x", "y"]),
                        "hashes": np.array(["h1", "h2"]), key: bad})  # fmt: skip
        assert user_error(rr.FrozenGenomes.load, p, ("a", "b"), 3) == (
            f"{p}: {key} must be 2 names"
        )


def _copy(run, tmp_path):
    out = tmp_path / run.name
    shutil.copytree(run, out)
    return out


def test_a_composed_runs_frozen_genomes_are_the_ones_its_config_names(tmp_path):
    cfg = rr.load_config(PIPELINE / "config.toml")
    f = rr.frozen_of(cfg, PIPELINE)
    assert f is not None and f.digest == cfg.frozen_digest
    assert rr.frozen_of(rr.load_config(KICK / "config.toml"), KICK) is None
    out = _copy(PIPELINE, tmp_path)
    g = f.genomes.copy()
    g[0, 0] += 1.0
    rr.FrozenGenomes(f.behaviours, g, f.sources, f.hashes).save(out / "frozen.npz")
    digest = rr.FrozenGenomes(f.behaviours, g, f.sources, f.hashes).digest
    assert user_error(rr.frozen_of, cfg, out) == (
        f"{out / 'frozen.npz'}: its genomes (digest {digest}) are not the ones "
        f"{out / 'config.toml'} names ({cfg.frozen_digest})"
    )
    assert user_error(rr.load_run, out).endswith(f"names ({cfg.frozen_digest})")
    bare = cfg.replace(frozen_digest="")
    assert user_error(rr.frozen_of, bare, out).endswith(" names (none)")


def test_a_run_loads_with_its_behaviour_and_best(tmp_path):
    cfg, beh, best = rr.load_run(str(PIPELINE))
    assert cfg.behaviour == beh.name == "composed" and best.generation == 110
    assert best.config_hash == cfg.hash() and best.genome.size == 133
    b = rr.behaviour_of(cfg, PIPELINE)
    assert b.name == "composed" and b.terrains == cfg.scene


def test_a_directory_that_is_not_a_finished_run_is_named(tmp_path):
    assert (
        user_error(rr.load_run, tmp_path / "x")
        == f"{tmp_path / 'x'}: no such directory"
    )
    assert (
        user_error(rr.load_run, tmp_path)
        == f"{tmp_path}: holds no run (no config.toml)"
    )
    out = _copy(KICK, tmp_path)
    (out / "best.npz").unlink()
    assert user_error(rr.load_run, out) == (
        f"{out}: no best.npz yet (the run has not finished a generation)"
    )


def test_a_best_genome_of_another_run_is_named(tmp_path):
    out = _copy(KICK, tmp_path)
    cfg, _, best = rr.load_run(out)
    shutil.copy(GETUP / "best.npz", out / "best.npz")
    other = rr.BestGenome.load(GETUP / "best.npz")
    assert other.genome.size == best.genome.size  # the same network: caught by name
    assert user_error(rr.load_run, out) == (
        f"{out / 'best.npz'}: belongs to another run (getup, hash "
        f"{other.config_hash}; config.toml: kick, hash {cfg.hash()})"
    )
    _best(genome=best.genome, behaviour="kick", config_hash="x").save(out / "best.npz")
    assert "belongs to another run (kick, hash x; " in user_error(rr.load_run, out)
    for gen, ok in ((cfg.generations, True), (cfg.generations + 1, False)):
        _best(genome=best.genome, config_hash=cfg.hash(), generation=gen).save(
            out / "best.npz"
        )
        if ok:
            assert rr.load_run(out)[2].generation == gen
        else:
            assert user_error(rr.load_run, out) == (
                f"{out / 'best.npz'}: of generation {gen}, beyond the run's "
                f"{cfg.generations} (config.toml)"
            )


def test_an_archive_of_exactly_the_elites_taken_gives_them_all():
    cfg, _, _ = rr.load_run(REPERTOIRE)
    f = rr.FrozenGenomes.from_runs(("kick",), {"kick": REPERTOIRE}, cfg.model,
                                   elites={"kick": 23})  # fmt: skip
    assert f.genomes.shape == (23, 144)


def test_a_runs_behaviour_takes_its_options(tmp_path):
    run = STUDY / "composed-apex-robust6-p10-s0"
    cfg = rr.load_config(run / "config.toml")
    assert cfg.options.score_substeps == (6,)  # not the defaults
    assert rr.behaviour_of(cfg, run).options == cfg.options
    # a repertoire of 2 elites, not the default 8: its frozen genomes are 4
    rep = rr.load_config(STUDY / "repertoire-s0" / "config.toml")
    f = rr.frozen_of(rep, STUDY / "repertoire-s0")
    two = rr.FrozenGenomes(f.behaviours[6:], f.genomes[6:], f.sources[6:], f.hashes[6:])
    two.save(tmp_path / "frozen.npz")
    small = rep.replace(options=type(rep.options)(elites=2), frozen_digest=two.digest)
    assert rr.frozen_of(small, tmp_path).behaviours == ("kick", "kick", "getup",
                                                        "return-legs")  # fmt: skip


def _npz(p, **changes):
    z = {"format": np.array(1), "genome": np.zeros(4), "fitness": np.array(1.0),
         "generation": np.array(2), "behaviour": np.array("kick"),
         "config_hash": np.array("ab")}  # fmt: skip
    z.update(changes)
    np.savez(p, **{k: v for k, v in z.items() if v is not None})


@pytest.mark.parametrize(
    ("changes", "words"),
    [
        ({"format": np.array("one")}, "no format version"),
        ({"fitness": np.array(np.nan)}, "fitness must be finite, got nan"),
        ({"generation": np.array(2.0)},
         "generation must be an integer, got a float64 array of shape ()"),
        ({"behaviour": np.array(1)}, "behaviour must be text, got a int64 array "
         "of shape ()"),
        ({"config_hash": np.array(1)}, "config_hash must be text, got a int64 "
         "array of shape ()"),
        ({"genome": np.zeros(5), "behaviour": np.array(1)},  # its name first
         "behaviour must be text, got a int64 array of shape ()"),
        ({"genome": np.zeros(5), "behaviour": np.array("getup")},
         "genome has 5 genes, the getup controller needs 4"),
    ],
)  # fmt: skip
def test_each_field_of_a_best_genome_is_checked_naming_the_file(
    tmp_path, changes, words
):
    p = tmp_path / "best.npz"
    _npz(p, **changes)
    assert user_error(rr.BestGenome.load, p, 4) == f"{p}: {words}"


def test_a_finished_runs_best_genome_has_its_controllers_genes(tmp_path):
    out = _copy(KICK, tmp_path)
    cfg, _, best = rr.load_run(out)
    _best(genome=best.genome[:10], config_hash=cfg.hash()).save(out / "best.npz")
    assert user_error(rr.load_run, out) == (
        f"{out / 'best.npz'}: genome has 10 genes, the kick controller needs 144"
    )


def _padded_best(p, extra):
    """A best genome of 144 genes whose arrays declare exactly the bound of
    its file (64 KiB beside 8 bytes a gene), plus ``extra`` characters."""
    used = 8 * 144 + 8 * 3 + 4 * 2  # genes, format, fitness, generation, hash
    name = "k" * (((1 << 16) + 8 * 144 - used) // 4 + extra)
    _best(genome=np.zeros(144), behaviour=name).save(p)


def test_a_best_genome_at_its_files_bound_is_read_and_a_byte_more_is_not(tmp_path):
    p = tmp_path / "best.npz"
    _padded_best(p, 0)
    assert rr.BestGenome.load(p, 144).genome.size == 144
    _padded_best(p, 1)
    bound = (1 << 16) + 8 * 144
    assert user_error(rr.BestGenome.load, p, 144) == (
        f"{p}: its arrays declare {bound + 4:,} bytes, more than such a file "
        f"holds ({bound:,}; nothing inflated)"
    )


def test_frozen_genomes_at_their_files_bound_are_read_and_a_byte_more_is_not(
    tmp_path,
):
    p = tmp_path / "frozen.npz"
    g = np.zeros((2, 10))
    used = 8 + 2 * 4 + g.nbytes + 2 * 2 * 4  # format, names, genomes, hashes
    width = ((1 << 16) + g.nbytes - used) // 8  # two sources of this many
    for extra, ok in ((0, True), (1, False)):
        src = ("s" * (width + extra), "t")
        rr.FrozenGenomes(("a", "b"), g, src, ("h1", "h2")).save(p)
        if ok:
            assert rr.FrozenGenomes.load(p, ("a", "b"), 10).sources == src
        else:
            bound = (1 << 16) + g.nbytes
            assert user_error(rr.FrozenGenomes.load, p, ("a", "b"), 10) == (
                f"{p}: its arrays declare {bound + 8:,} bytes, more than such a "
                f"file holds ({bound:,}; nothing inflated)"
            )


def test_frozen_genomes_without_a_format_are_named(tmp_path):
    p = tmp_path / "frozen.npz"
    np.savez(p, format=np.array(1.5j), behaviours=np.array(["a"]),
             genomes=np.zeros((1, 2)), sources=np.array(["s"]),
             hashes=np.array(["h"]))  # fmt: skip
    assert user_error(rr.FrozenGenomes.load, p, ("a",), 2) == f"{p}: no format version"
