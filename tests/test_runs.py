"""Run directories: files, bit-identical resume (also after a kill), evaluate,
thread-count independence, and bad input."""

import dataclasses
import re
import signal
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_same_run, wait_for_rows
from locustjump import rundir
from locustjump.cli import main
from locustjump.errors import UserError
from locustjump.evo import params_class
from locustjump.evo.rcga import RCGAParams
from locustjump.present.evaluate import evaluate_run
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.tasks import get_behaviour
from locustjump.tasks.kick import kick_fitness

SMALL = TrainConfig(generations=4, optimizer=RCGAParams(population=6), seed=5)


@pytest.fixture(scope="module")
def full_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("full") / "run"
    train(SMALL, out, progress=False, backend=ThreadBackend(2))
    return out


def test_run_directory_files(full_run):
    for name in (
        rundir.CONFIG,
        rundir.METRICS,
        rundir.CHECKPOINT,
        rundir.BEST,
        "fitness.png",
    ):
        assert (full_run / name).is_file(), name
    assert rundir.load_config(full_run / rundir.CONFIG) == SMALL
    m = rundir.read_metrics(full_run / rundir.METRICS)
    np.testing.assert_array_equal(m["generation"], [1, 2, 3, 4])
    np.testing.assert_array_equal(m["evaluations"], [6, 4, 4, 4])  # elites kept
    assert np.all(np.diff(m["best"]) >= 0)
    best = rundir.BestGenome.load(full_run / rundir.BEST, 144)
    assert best.fitness == m["best"][-1]
    assert best.behaviour == "kick" and best.config_hash == SMALL.hash()
    # no temporary files are left behind by the atomic writes
    assert not list(full_run.glob(".*.tmp"))


def test_resume_is_bit_identical(full_run, tmp_path):
    out = tmp_path / "run"
    r = train(SMALL, out, progress=False, stop_after=2)
    assert r.generation == 2
    # as if killed between the checkpoint and the metrics row of generation 2
    m = out / rundir.METRICS
    m.write_text("".join(m.read_text().splitlines(keepends=True)[:-1]))
    train(SMALL, out, progress=False, resume=True)
    assert_same_run(full_run, out)


def test_thread_count_does_not_change_the_result(full_run, tmp_path):
    out = tmp_path / "run"
    train(SMALL, out, progress=False, backend=ThreadBackend(1))
    assert_same_run(full_run, out)


@pytest.mark.parametrize("kind", ["rcga", "cma", "random"])
def test_resume_after_a_kill_is_bit_identical(tmp_path, kind):
    cfg = SMALL.replace(generations=40, optimizer=params_class(kind)(population=6))
    ref = tmp_path / "ref"
    train(cfg, ref, progress=False)
    out = tmp_path / "killed"
    cmd = [sys.executable, "-m", "locustjump.cli", "train", "kick", "--population",
           "6", "--seed", "5", "--generations", "40", "--threads", "1", "--quiet",
           "--optimizer", kind, "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd)
    wait_for_rows(out, 2, timeout=120)  # early: 38 generations of margin
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = len(rundir.read_metrics(out / rundir.METRICS))
    assert 0 < done < 40, "the run should have been killed mid-way"
    assert main(["train", "kick", "--resume", "--quiet", "--out", str(out)]) == 0
    assert_same_run(ref, out)


def test_resume_can_extend_a_finished_run(full_run, tmp_path):
    out = tmp_path / "run"
    train(SMALL.replace(generations=2), out, progress=False)
    train(SMALL, out, progress=False, resume=True)
    assert_same_run(full_run, out)
    assert rundir.load_config(out / rundir.CONFIG).generations == 4


def test_evaluate_reproduces_the_recorded_fitness(full_run, capsys):
    assert main(["evaluate", str(full_run)]) == 0
    text = capsys.readouterr().out
    assert "matches training" in text and "apex_height_m" in text
    assert (full_run / "eval" / "trajectory.csv").is_file()
    assert (full_run / "eval" / "kick_vs_rules.png").is_file()
    ev = evaluate_run(full_run)
    assert ev.matches and ev.metrics["fitness"] == ev.fitness
    # Python's own numbers, not NumPy's (np.float64 passes isinstance(float))
    types = {type(v) for v in ev.metrics.values()}
    assert types <= {float, int, bool, str, list, dict}, types
    assert {type(v) for v in ev.metrics.values() if isinstance(v, float)} == {float}
    header = (full_run / "eval" / "trajectory.csv").read_text().splitlines()[0]
    assert header.startswith("step,t,x,y,z,up_z,touch,hip_l,knee_l,hip_r,knee_r")


def test_metrics_are_plain_python_all_the_way_down():
    from locustjump.present.evaluate import plain

    m = plain({"a": np.float64(1.5), "b": [np.int64(2), (np.bool_(True),)],
               "c": {"d": np.arange(2.0)}, "e": "x"})  # fmt: skip
    assert m == {"a": 1.5, "b": [2, (True,)], "c": {"d": [0.0, 1.0]}, "e": "x"}
    assert type(m["a"]) is float and type(m["b"][0]) is int
    assert type(m["b"][1][0]) is bool and type(m["c"]["d"][0]) is float


def test_kick_fitness_is_the_rectangle():
    q = np.zeros((1, 4, 7))
    q[0, :, 0] = [0.0, 1.0, 2.0, 3.0]  # x
    q[0, :, 2] = [0.5, 1.5, 1.0, 0.0]  # z: up 1, then up 0.5, then below start
    assert kick_fitness(q)[0] == pytest.approx(max(1 * 1.0, 2 * 0.5, 3 * 0.0))
    q[0, :, 0] *= -1  # backwards: nothing counts
    assert kick_fitness(q)[0] == 0.0


def test_kick_fitness_of_the_rule_based_kick_is_positive(params):
    from locustjump.tasks.rules import RuleController

    beh = get_behaviour("kick")
    rc = RuleController.for_model(params)
    from locustjump.sim.engine.rollout import rollout

    res = rollout(rc, rc.params_for(0.125), beh.start_states(params), beh.n_steps)
    assert kick_fitness(res["qpos"])[0] > 0.1


# --- bad input -----------------------------------------------------------------


def run_cli(args, capsys):
    code = main(args)
    err = capsys.readouterr().err.strip()
    return code, err


def test_new_run_refuses_a_used_directory(full_run, capsys):
    before = (full_run / rundir.METRICS).read_bytes()
    code, err = run_cli(["train", "kick", "--out", str(full_run)], capsys)
    assert code == 2 and "holds a run" in err and "--resume" in err
    assert len(err.splitlines()) == 1
    assert (full_run / rundir.METRICS).read_bytes() == before


def copy_run(src: Path, dst: Path) -> Path:
    dst.mkdir()
    for f in src.iterdir():
        if f.is_file():
            (dst / f.name).write_bytes(f.read_bytes())
    return dst


def test_truncated_checkpoint_is_named(full_run, tmp_path, capsys):
    out = copy_run(full_run, tmp_path / "run")
    data = (out / rundir.CHECKPOINT).read_bytes()
    (out / rundir.CHECKPOINT).write_bytes(data[: len(data) // 2])
    snapshot = {f.name: f.read_bytes() for f in out.iterdir() if f.is_file()}
    code, err = run_cli(
        ["train", "kick", "--resume", "--generations", "6", "--out", str(out)], capsys
    )
    assert code == 2 and rundir.CHECKPOINT in err and len(err.splitlines()) == 1
    # nothing overwritten, except config.toml (not rewritten either: same bytes)
    assert {f.name: f.read_bytes() for f in out.iterdir() if f.is_file()} == snapshot


def test_bad_genome_files_are_named(full_run, tmp_path, capsys):
    out = copy_run(full_run, tmp_path / "run")
    best = rundir.BestGenome.load(out / rundir.BEST)
    dataclasses.replace(best, genome=best.genome[:-1]).save(out / rundir.BEST)
    code, err = run_cli(["evaluate", str(out)], capsys)
    assert code == 2 and "143 genes" in err and "144" in err
    (out / rundir.BEST).write_bytes(b"not a zip file")
    code, err = run_cli(["evaluate", str(out)], capsys)
    assert code == 2 and rundir.BEST in err
    with zipfile.ZipFile(out / rundir.BEST, "w") as z:  # an npz without our keys
        z.writestr("x.npy", b"")
    code, err = run_cli(["evaluate", str(out)], capsys)
    assert code == 2 and rundir.BEST in err


@pytest.mark.parametrize(
    "text, match",
    [
        ("seed = 1\nbogus = 2\n", "unknown key 'bogus'"),
        ("[rcga]\npopulation = 'fifty'\n", "rcga.population must be int"),
        ("[model]\nhip_pos = [1.0, 2.0]\n", "model.hip_pos"),
        ("[rcga]\nelite = 60\n", "elite"),
        ("seed = [\n", "not valid TOML"),
        ('behaviour = "getup"\n', "behaviour"),
        ('[optimizer]\nkind = "cma"\nalpha = 1\n', "optimizer.alpha"),
        ('[optimizer]\nkind = "cma"\nsigma0 = "big"\n', "optimizer.sigma0"),
        ('[optimizer]\nkind = "sgd"\n', "unknown optimizer 'sgd'"),
        ("[optimizer]\nkind = 3\n", "optimizer.kind"),
        ('[optimizer]\nkind = "cma"\nsigma0 = -1.0\n', "sigma0"),
        ('[optimizer]\nkind = "cma"\n[rcga]\npopulation = 4\n', "not both"),
    ],
)
def test_bad_config_is_named(tmp_path, capsys, text, match):
    cfg = tmp_path / "my.toml"
    cfg.write_text(text)
    out = tmp_path / "run"
    code, err = run_cli(
        ["train", "kick", "--config", str(cfg), "--out", str(out)], capsys
    )
    assert code == 2 and match in err and str(cfg) in err, err
    assert len(err.splitlines()) == 1
    assert not out.exists()


def test_config_file_sets_the_run(tmp_path):
    cfg = tmp_path / "my.toml"
    cfg.write_text('[rcga]\ncrossover = "sbx"\npopulation = 4\n')
    out = tmp_path / "run"
    assert main(["train", "kick", "--config", str(cfg), "--generations", "1",
                 "--quiet", "--out", str(out)]) == 0  # fmt: skip
    c = rundir.load_config(out / rundir.CONFIG)
    assert (
        c.optimizer.crossover == "sbx"
        and c.optimizer.population == 4
        and c.generations == 1
    )


def test_resume_checks_what_the_directory_holds(full_run, tmp_path, capsys):
    code, err = run_cli(["train", "kick", "--resume", "--out", str(tmp_path)], capsys)
    assert code == 2 and "holds no run" in err
    code, err = run_cli(
        ["train", "kick", "--resume", "--seed", "9", "--out", str(full_run)], capsys
    )
    assert code == 2 and "seed 9 differs from the run's seed 5" in err
    # another behaviour's run: stored config says kick, the command says getup
    other = copy_run(full_run, tmp_path / "other")
    text = (other / rundir.CONFIG).read_text().replace('"kick"', '"nope"')
    (other / rundir.CONFIG).write_text(text)
    code, err = run_cli(["train", "kick", "--resume", "--out", str(other)], capsys)
    assert code == 2 and "behaviour" in err and rundir.CONFIG in err


def test_checkpoint_of_another_configuration_is_refused(full_run, tmp_path):
    out = copy_run(full_run, tmp_path / "run")
    (out / rundir.CONFIG).write_text(
        (out / rundir.CONFIG).read_text().replace("seed = 5", "seed = 6")
    )
    with pytest.raises(UserError, match="another configuration"):
        train(SMALL.replace(seed=6), out, progress=False, resume=True)


def test_evaluate_of_a_directory_without_a_run(tmp_path, capsys):
    code, err = run_cli(["evaluate", str(tmp_path)], capsys)
    assert code == 2 and "holds no run" in err
    code, err = run_cli(["evaluate", str(tmp_path / "missing")], capsys)
    assert code == 2 and "no such directory" in err


def test_shipped_runs_keep_their_config_hash():
    """A creature option added later (e.g. ``strut_stiffness``) must not orphan
    the shipped run directories: each config's recorded hash still matches."""
    root = Path(__file__).resolve().parent.parent / "results"
    configs = sorted(root.glob("*/*/config.toml"))
    if not configs:
        pytest.skip(f"no shipped runs under {root}")
    for path in configs:
        text = path.read_text()
        recorded = re.search(r"config hash ([0-9a-f]{16})", text).group(1)
        cfg = TrainConfig.from_dict(tomllib.loads(text), str(path))
        assert cfg.hash() == recorded, path
        changed = dataclasses.replace(
            cfg, model=cfg.model.replace(strut_stiffness=1e-5)
        )
        assert changed.hash() != recorded


def test_a_run_made_before_pluggable_optimizers_resumes(shipped, tmp_path):
    """Shipped checkpoints hold the RCGA's state unprefixed and no optimizer
    name; they resume and keep their rows. (Checked once against the code
    before the change: results/quick-seed0/kick extended to 33 generations by
    both gives the same best genome, population, random state and metrics.)"""
    import shutil

    out = tmp_path / "kick"
    shutil.copytree(shipped / "kick", out)
    with np.load(out / rundir.CHECKPOINT) as z:
        assert "optimizer" not in z.files and "population" in z.files
    rows = (out / rundir.METRICS).read_text().splitlines()
    cfg = rundir.load_config(out / rundir.CONFIG)
    assert (
        cfg.optimizer.kind == "rcga" and "[rcga]" in (out / rundir.CONFIG).read_text()
    )
    train(cfg.replace(generations=cfg.generations + 1), out, progress=False,
          resume=True)  # fmt: skip
    after = (out / rundir.METRICS).read_text().splitlines()
    assert after[: len(rows)] == rows and len(after) == len(rows) + 1
    with np.load(out / rundir.CHECKPOINT) as z:
        assert str(z["optimizer"]) == "rcga" and "opt_population" in z.files


def test_score_substeps_takes_the_worst_resolution(tmp_path, capsys):
    """--score-substeps (beyond the paper): each genome's fitness is the minimum
    over the model's resolution and the given ones; recorded in config.toml,
    hashed, checked on resume and reproduced by evaluate."""
    argv = ["train", "kick", "--generations", "2", "--population", "4", "--quiet"]
    plain, robust = tmp_path / "plain", tmp_path / "robust"
    assert main([*argv, "--out", str(plain)]) == 0
    assert main([*argv, "--score-substeps", "6,12", "--out", str(robust)]) == 0
    cfg = rundir.load_config(robust / rundir.CONFIG)
    assert cfg.options.score_substeps == (6, 12)
    assert cfg.hash() != rundir.load_config(plain / rundir.CONFIG).hash()
    _, beh, best = rundir.load_run(robust)
    p = cfg.model
    each = [
        beh.fitness(beh.simulate(best.genome[None], q, engine=cfg.engine), q)[0]
        for q in (p, *(dataclasses.replace(p, substeps=s) for s in (6, 12)))
    ]
    assert best.fitness == min(each)
    assert evaluate_run(robust).matches
    capsys.readouterr()
    resume = ["train", "kick", "--resume", "--out", str(robust)]
    assert main([*resume, "--score-substeps", "6"]) == 2
    assert "score_substeps 6 differs from the run's options.score_substeps 6,12" in (
        capsys.readouterr().err
    )
    for bad in ("0", "6,6", "6,x"):
        try:
            code = main([*argv, "--score-substeps", bad, "--out", str(tmp_path / "b")])
        except SystemExit as e:  # argparse's own refusal
            code = e.code
        assert code == 2
        assert "--score-substeps" in capsys.readouterr().err
        assert not (tmp_path / "b").exists()
