"""The optimizer base class: each optimizer, plugging one in, the reason an
optimizer stops, its diagnostics in metrics.csv, and bad input."""

import dataclasses
import json
import re
from typing import Any, ClassVar

import numpy as np
import pytest

from locustjump import rundir
from locustjump.cli import main
from locustjump.evo import _REGISTRY as OPTIMIZERS
from locustjump.evo import (
    CMAES,
    RCGA,
    CMAParams,
    Optimizer,
    RandomSearch,
    RandomSearchParams,
    RCGAParams,
    make_optimizer,
    optimizer_kinds,
    params_class,
    register,
    rng_from_state,
    rng_state,
)
from locustjump.rundir.config import TrainConfig
from locustjump.runs.reproduction import Budget, Reproduction
from locustjump.runs.trainer import train

KINDS = {"rcga": RCGAParams, "cma": CMAParams, "random": RandomSearchParams}


def _sphere(x: np.ndarray) -> np.ndarray:
    return -np.sum((x - 0.3) ** 2, axis=1)  # maximised at 0.3


def _run(opt: Optimizer, generations: int) -> list[np.ndarray]:
    asked = []
    for _ in range(generations):
        x = opt.ask()
        asked.append(x)
        opt.tell(_sphere(x))
    return asked


@pytest.mark.parametrize("kind", list(KINDS))
def test_every_optimizer_follows_the_protocol(kind):
    params = KINDS[kind](population=8)
    opt = make_optimizer(params, 5, seed=3)
    asked = _run(opt, 30)
    assert isinstance(opt, Optimizer) and kind in optimizer_kinds()
    assert all(x.shape[1] == 5 for x in asked)
    assert opt.generation == 30 and opt.stop() == {}
    # best is the best told so far, and the optimizer improved on its start
    told = np.concatenate([_sphere(x) for x in asked])
    assert opt.best_fitness == told.max() == _sphere(opt.best[None])[0]
    assert opt.best_fitness > _sphere(asked[0]).max()


@pytest.mark.parametrize("kind", list(KINDS))
def test_same_seed_same_genomes_and_state_round_trip(kind):
    params = KINDS[kind](population=8)
    a, b = make_optimizer(params, 5, 7), make_optimizer(params, 5, 7)
    for xa, xb in zip(_run(a, 10), _run(b, 10), strict=True):
        np.testing.assert_array_equal(xa, xb)
    # restored from its arrays (as in checkpoint.npz), it goes on identically
    c = make_optimizer(params, 5, 7)
    c.load_state({k: np.asarray(v) for k, v in a.state().items()})
    for xa, xc in zip(_run(a, 5), _run(c, 5), strict=True):
        np.testing.assert_array_equal(xa, xc)
    assert c.best_fitness == a.best_fitness
    other = make_optimizer(params, 5, 8)
    assert not np.array_equal(other.ask(), make_optimizer(params, 5, 7).ask())


def test_cma_minimises_minus_fitness_and_leaves_global_numpy_alone():
    np.random.seed(0)
    before = np.random.get_state()[1].copy()
    opt = CMAES(10, CMAParams(population=10, sigma0=0.5), seed=1)
    _run(opt, 60)
    assert opt.best_fitness > -0.01  # converged towards the maximum
    np.testing.assert_array_equal(np.random.get_state()[1], before)


def test_rcga_and_random_search_are_the_registered_classes():
    assert isinstance(make_optimizer(RCGAParams(), 3, 0), RCGA)
    assert isinstance(make_optimizer(RandomSearchParams(), 3, 0), RandomSearch)


def test_cma_run_trains_resumes_and_records_its_optimizer(tmp_path):
    cfg = TrainConfig(generations=3, optimizer=CMAParams(population=6), seed=2)
    out = tmp_path / "cma"
    train(cfg, out, progress=False, stop_after=1)
    train(cfg, out, progress=False, resume=True)
    whole = tmp_path / "whole"
    train(cfg, whole, progress=False)
    for name in (rundir.BEST, rundir.CHECKPOINT):
        with np.load(out / name) as za, np.load(whole / name) as zb:
            for k in set(za.files) - {"metrics_row"}:
                np.testing.assert_array_equal(za[k], zb[k])
    text = (out / rundir.CONFIG).read_text()
    assert '[optimizer]\nkind = "cma"' in text
    assert rundir.load_config(out / rundir.CONFIG) == cfg
    assert cfg.hash() != cfg.replace(optimizer=RCGAParams(population=6)).hash()


# --- a user's own optimizer (the README example) ------------------------------


@dataclasses.dataclass(frozen=True)
class HillClimbParams:
    kind: ClassVar[str] = "hillclimb"
    population: int = 8
    step: float = 0.1

    def replace(self, **changes: Any) -> "HillClimbParams":
        return dataclasses.replace(self, **changes)


class HillClimb(Optimizer):
    """Gaussian samples around the best genome so far."""

    Params = HillClimbParams

    def _ask(self):
        n = (self.params.population, self.num_params)
        return self.best + self.rng.normal(0, self.params.step, n)

    def _tell(self, genomes, fitness):
        pass  # the base keeps the best so far

    def _state(self):
        return {"best": self.best, "best_fitness": np.array(self.best_fitness),
                "rng": rng_state(self.rng)}  # fmt: skip

    def _set_state(self, s):
        self._set_best(s["best"], float(s["best_fitness"]))
        self.rng = rng_from_state(s["rng"])


def test_a_plugged_optimizer_trains_and_resumes(tmp_path, monkeypatch):
    monkeypatch.setitem(OPTIMIZERS, "hillclimb", HillClimb)
    register(HillClimb)
    cfg = TrainConfig(generations=3, optimizer=HillClimbParams(), seed=1)
    train(cfg, tmp_path / "a", progress=False, stop_after=2)
    r = train(cfg, tmp_path / "a", progress=False, resume=True)
    assert r.generation == 3
    argv = ["train", "kick", "--optimizer", "hillclimb", "--generations", "3",
            "--seed", "1", "--quiet", "--out", str(tmp_path / "b")]  # fmt: skip
    assert main(argv) == 0
    a = rundir.BestGenome.load(tmp_path / "a" / rundir.BEST)
    b = rundir.BestGenome.load(tmp_path / "b" / rundir.BEST)
    np.testing.assert_array_equal(a.genome, b.genome)


# --- bad input ---------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["train", "kick", "--optimizer", "adam"], "--optimizer"),
        (["train", "kick", "--backend", "mpi"], "--backend"),
        (["reproduce", "--optimizer", "adam"], "--optimizer"),
        (["evaluate", "x", "--backend", "gpu"], "--backend"),
    ],
)
def test_unknown_optimizer_or_backend(tmp_path, capsys, argv, needle):
    out = tmp_path / "out"
    with pytest.raises(SystemExit) as e:
        main([*argv, "--out", str(out)] if argv[0] != "evaluate" else argv)
    err = capsys.readouterr().err
    assert e.value.code == 2 and needle in err and len(err.splitlines()) == 1
    assert not out.exists()


def test_resume_with_another_optimizer_is_refused(tmp_path, capsys):
    out = tmp_path / "run"
    argv = ["train", "kick", "--population", "4", "--generations", "1", "--quiet",
            "--out", str(out)]  # fmt: skip
    assert main(argv) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    capsys.readouterr()
    code = main(["train", "kick", "--resume", "--optimizer", "cma", "--generations",
                 "2", "--quiet", "--out", str(out)])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "trained with the 'rcga' optimizer, not 'cma'" in err
    assert len(err.splitlines()) == 1
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before


def test_reproduce_keeps_its_optimizer(tmp_path, capsys):
    """A reproduction started with one optimizer (markers written before
    optimizers were pluggable name none: the RCGA) is not continued with
    another."""
    d = tmp_path / "repro"
    d.mkdir()
    (d / rundir.MARKER).write_text(  # as results/long-seed0's, of 0.1.0
        'budget = "quick"\nseed = 0\npopulation = 50\ncommand = "locustjump '
        'reproduce"\nlocustjump = "0.1.0"\n[generations]\nkick = 30\n'
    )
    before = (d / rundir.MARKER).read_bytes()
    assert main(["reproduce", "--optimizer", "cma", "--quiet", "--out", str(d)]) == 2
    err = capsys.readouterr().err
    assert "optimizer 'rcga', not 'cma'" in err and len(err.splitlines()) == 1
    assert sorted(p.name for p in d.iterdir()) == [rundir.MARKER]
    assert (d / rundir.MARKER).read_bytes() == before


# --- the base class's bookkeeping ---------------------------------------------


@pytest.mark.parametrize("kind", list(KINDS))
def test_ask_is_told_once(kind):
    opt = make_optimizer(KINDS[kind](population=4), 3, seed=1)
    with pytest.raises(RuntimeError, match="without a pending ask"):
        opt.tell(np.zeros(4))
    x = opt.ask()
    np.testing.assert_array_equal(opt.ask(), x)  # asked again: the same genomes
    with pytest.raises(RuntimeError, match="between generations"):
        opt.state()
    opt.tell(_sphere(x))
    with pytest.raises(RuntimeError, match="told once"):
        opt.tell(_sphere(x))
    assert opt.generation == 1


def test_an_optimizer_is_a_subclass_of_the_base():
    class Duck:  # the members, but not the base's bookkeeping
        Params = HillClimbParams

        def ask(self): ...
        def tell(self, f): ...

    with pytest.raises(TypeError, match="Duck is not a subclass"):
        register(Duck)

    class Half(Optimizer):
        Params = HillClimbParams

        def _ask(self): ...

    with pytest.raises(TypeError, match="Half does not define _set_state"):
        register(Half)

    class Wrong(HillClimb):
        def _ask(self):
            return np.zeros((2, 3))

    with pytest.raises(ValueError, match=r"_ask\(\) gave shape \(2, 3\)"):
        Wrong(5, HillClimbParams(), 0).ask()


@pytest.mark.parametrize("kind", list(KINDS))
def test_one_seed_argument(kind):
    cls, params = OPTIMIZERS[kind], KINDS[kind](population=4)
    a, b = cls(3, params, seed=4), make_optimizer(params, 3, 4)
    np.testing.assert_array_equal(a.ask(), b.ask())
    assert a.seed == 4
    with pytest.raises(TypeError, match="seed must be an int"):
        cls(3, params, seed=0.5)


def test_rcga_takes_a_seed_not_a_generator():
    # the rng= argument (a generator or a seed) is gone: a generator where the
    # seed goes is refused by name
    with pytest.raises(TypeError, match="seed must be an integer in .*, got Generator"):
        RCGA(3, RCGAParams(population=4), np.random.default_rng(7))


def test_cma_stop_reasons_are_plain_and_leave_the_budget_to_the_trainer():
    opt = CMAES(4, CMAParams(population=6), seed=0)
    reasons = {"conditioncov": np.float64(1e14), "tolfun": 1e-11, "maxiter": 3}
    opt.es.stop = lambda: reasons
    assert opt.stop() == {"conditioncov": 1e14}
    assert type(opt.stop()["conditioncov"]) is float


def test_cma_diagnostics():
    opt = CMAES(4, CMAParams(population=6, sigma0=0.3), seed=0)
    d = opt.diagnostics()
    assert d["sigma"] == 0.3 and d["condition"] == pytest.approx(1.0, rel=1e-3)
    _run(opt, 20)
    d = opt.diagnostics()
    assert d["sigma"] == opt.es.sigma != 0.3 and d["condition"] >= 1.0
    assert RCGA(3).diagnostics() == {} == RandomSearch(3).diagnostics()


# --- the trainer: stop.json, diagnostics columns ------------------------------


@dataclasses.dataclass(frozen=True)
class TiredParams:
    kind: ClassVar[str] = "tired"
    population: int = 4
    init_scale: float = 1.0

    def replace(self, **changes: Any) -> "TiredParams":
        return dataclasses.replace(self, **changes)


class Tired(RandomSearch):
    """Random search that gives up after two generations."""

    Params = TiredParams

    def _stop(self):
        return {"tired": np.int64(self.generation)} if self.generation >= 2 else {}


TINY = Budget("tiny", 4, {"kick": 5, "getup": 1, "return-legs": 1, "composed": 1})


def test_an_early_stop_is_saved_and_shown(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(OPTIMIZERS, "tired", Tired)
    cfg = TrainConfig(generations=5, optimizer=TiredParams(), seed=1)
    out = tmp_path / "kick"
    r = train(cfg, out, progress=False)
    assert r.generation == 2 and r.stopped == {"tired": 2}
    saved = json.loads((out / rundir.STOP).read_text())
    assert saved == {"generation": 2, "reasons": {"tired": 2}}
    assert len(rundir.read_metrics(out / rundir.METRICS)) == 2
    # resumed, it stops again at once, and so says the command line
    argv = ["train", "kick", "--resume", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    said = capsys.readouterr().out
    assert "stopped early (tired 2, in stop.json)" in said
    assert len(rundir.read_metrics(out / rundir.METRICS)) == 2
    # a reproduction's stage that stopped early is done once evaluated
    rundir.eval_metrics_path(out).parent.mkdir()
    rundir.write_json(rundir.eval_metrics_path(out), {})
    rep = Reproduction(tmp_path, TINY, (0,))
    assert rep.stage_done("kick")
    (out / rundir.STOP).unlink()
    assert not rep.stage_done("kick")
    # a run that goes on to its budget has no stop.json
    done = train(cfg.replace(optimizer=RandomSearchParams(4)), tmp_path / "b",
                 progress=False)  # fmt: skip
    assert done.stopped == {} and not (tmp_path / "b" / rundir.STOP).exists()


def test_diagnostics_columns_and_older_metrics_files(tmp_path):
    cfg = TrainConfig(generations=3, optimizer=CMAParams(population=6), seed=2)
    whole = tmp_path / "whole"
    train(cfg, whole, progress=False)
    header = (whole / rundir.METRICS).read_text().splitlines()[0].split(",")
    assert header == [*rundir.METRICS_COLUMNS, "sigma", "condition"]
    m = rundir.read_metrics(whole / rundir.METRICS)
    assert m["sigma"][0] != 0.5 and np.all(m["condition"] >= 1.0)
    # the RCGA's metrics.csv keeps its columns (those of the shipped runs)
    rcga = tmp_path / "rcga"
    train(cfg.replace(optimizer=RCGAParams(population=6)), rcga, progress=False)
    first = (rcga / rundir.METRICS).read_text().splitlines()[0]
    assert first == ",".join(rundir.METRICS_COLUMNS)
    # a CMA-ES run written before diagnostics (no such columns) resumes in
    # its own format, with the same numbers
    out = tmp_path / "old"
    train(cfg, out, progress=False, stop_after=2)
    m = out / rundir.METRICS
    m.write_text("".join(",".join(ln.split(",")[:8]) + "\n"
                         for ln in m.read_text().splitlines()))  # fmt: skip
    train(cfg, out, progress=False, resume=True)
    rows = m.read_text().splitlines()
    assert rows[0] == ",".join(rundir.METRICS_COLUMNS)
    assert len(rows) == 4 and all(len(r.split(",")) == 8 for r in rows)
    old, new = rundir.read_metrics(m), rundir.read_metrics(whole / rundir.METRICS)
    for k in ("generation", "best", "mean", "std", "evaluations"):
        np.testing.assert_array_equal(old[k], new[k])


@pytest.mark.parametrize("kind", [None, 3, [], {"rcga": 1}])
def test_an_optimizer_kind_that_is_no_name_is_unknown(kind):
    # an unhashable kind once reached the registry's lookup: a TypeError
    with pytest.raises(ValueError, match=re.escape(f"unknown optimizer {kind!r}")):
        params_class(kind)
    with pytest.raises(ValueError, match="unknown optimizer"):
        TrainConfig(optimizer=type("Settings", (), {"kind": kind})())
