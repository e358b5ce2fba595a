"""What a reproduction is (``runs/reproduction.py``), without training: its
budgets, its stages, the checks it makes before anything is written, the
command that makes and continues it, its markers and when a stage is done."""

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import pytest

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.evo.cma import CMAParams
from locustjump.runs import reproduction as rp
from locustjump.sim import scene
from locustjump.sim.scene import Debris, Flat, Terrains
from locustjump.version import __version__

PAPER = ("kick", "getup", "return-legs", "composed")


def test_a_baseline_gets_the_paper_stages_generations_together():
    b = rp.Budget("b", 10, {"kick": 1, "getup": 2, "return-legs": 3, "composed": 4})
    assert b.generations == {
        "kick": 1, "getup": 2, "return-legs": 3, "composed": 4, "monolithic": 10,
    }  # fmt: skip
    assert b.of("getup") == 2 and b.of("monolithic") == 10
    own = rp.Budget("o", 10, {**dict.fromkeys(PAPER, 5), "monolithic": 7, "x": 9})
    assert own.of("monolithic") == 7 and "x" not in own.generations


def test_the_budgets():
    """What docs/results.md and the README quote for each budget."""
    gens = {n: [b.of(s) for s in rp.TRAINED] for n, b in rp.BUDGETS.items()}
    assert gens == {
        "quick": [30, 10, 20, 30, 90],
        "demo": [100, 20, 60, 30, 210],
        "long": [100, 20, 60, 120, 300],
        "paper": [1000, 1000, 1000, 1000, 4000],
    }
    assert {b.population for b in rp.BUDGETS.values()} == {50}
    assert all(b.name == n for n, b in rp.BUDGETS.items())


def test_budget_of():
    b = rp.Budget("mine", 4, dict.fromkeys(PAPER, 1))
    assert rp.budget_of(b) is b and rp.budget_of("long") is rp.BUDGETS["long"]
    with pytest.raises(UserError) as e:
        rp.budget_of("huge")
    assert str(e.value) == "unknown budget 'huge'; choose from quick, demo, long, paper"


def test_the_stages_in_order_and_what_each_builds_on():
    assert rp.stages_of() == ("rules", *PAPER, "monolithic")
    assert rp.stages_of(monolithic=False) == ("rules", *PAPER)
    assert rp.STAGES == rp.stages_of() and rp.TRAINED == (*PAPER, "monolithic")
    assert rp.requires("rules") == () and rp.requires("kick") == ()
    assert rp.requires("composed") == ("kick", "getup", "return-legs")


def _open(out, seeds=(0,), **kw):
    return rp.Reproduction.open(out, kw.pop("budget", "quick"), seeds, **kw)


@pytest.mark.parametrize(
    ("seeds", "many", "said"),
    [
        ((), True, "need distinct non-negative seeds, got ()"),
        ((1, 1), True, "need distinct non-negative seeds, got (1, 1)"),
        ((2, -1), True, "need distinct non-negative seeds, got (2, -1)"),
        ((0, 1), False, "a single-seed reproduction has one seed"),
    ],
)
def test_the_seeds_are_checked(tmp_path, seeds, many, said):
    with pytest.raises(UserError) as e:
        _open(tmp_path / "r", seeds, many=many)
    assert str(e.value).endswith(said) and str(e.value).startswith(("seeds: ", "a "))
    assert not (tmp_path / "r").exists()


def test_an_unknown_engine_or_optimizer_is_refused(tmp_path):
    with pytest.raises(UserError) as e:
        _open(tmp_path, engine="warp")
    assert str(e.value) == "unknown engine 'warp'; choose from numpy, numba"
    with pytest.raises(ValueError, match="^unknown optimizer 'nelder'; choose from"):
        _open(tmp_path, optimizer="nelder")


def test_open_takes_the_defaults_or_what_the_marker_recorded(tmp_path):
    rep = _open(tmp_path / "new", seeds=[3])
    assert (rep.engine, rep.terrains, rep.seeds, rep.many) == (
        rp.DEFAULT_ENGINE, Terrains(), (3,), False,
    )  # fmt: skip
    debris = Terrains(Debris(seed=2), 3)
    other = _open(tmp_path / "old", engine="numpy", terrains=debris)
    other.start()
    again = _open(tmp_path / "old")
    assert (again.engine, again.terrains) == ("numpy", debris)
    assert _open(tmp_path / "new", optimizer="cma").optimizer == "cma"
    _open(tmp_path / "many", [1, 2], many=True, engine="numpy", terrains=debris).start()
    again = _open(tmp_path / "many", [1, 2], many=True)
    assert (again.engine, again.terrains) == ("numpy", debris)


def test_a_scene_table_a_marker_cannot_hold_names_the_marker(tmp_path):
    _open(tmp_path / "r").start()
    path = tmp_path / "r" / rundir.MARKER
    marker = tomllib.loads(path.read_text())
    marker["scene"]["kind"] = "lava"
    rundir.write_toml(path, marker)
    with pytest.raises(UserError, match=f"^{path}: .*lava"):
        _open(tmp_path / "r")


def test_a_seed_reproduction_is_its_directory_or_a_seed_directory(tmp_path):
    one = _open(tmp_path / "one", seeds=[4])
    assert one.seed_dir(4) == tmp_path / "one"
    many = _open(tmp_path / "many", seeds=[1, 5], many=True, budget="long")
    assert many.seed_dir(5) == tmp_path / "many" / "seed-5"
    five = many.for_seed(5)
    assert (five.out, five.seeds, five.many, five.budget) == (
        tmp_path / "many" / "seed-5", (5,), False, rp.BUDGETS["long"],
    )  # fmt: skip


@pytest.mark.parametrize(
    ("kw", "flags"),
    [
        ({}, "--budget quick --seed 2 --out D"),
        ({"optimizer": "cma"}, "--budget quick --seed 2 --optimizer cma --out D"),
        ({"engine": "numpy"}, "--budget quick --seed 2 --engine numpy --out D"),
        (
            {"terrains": Terrains(Debris())},
            "--budget quick --seed 2 --scene debris --out D",
        ),
        (
            {"terrains": Terrains(Debris(seed=7), 4)},
            "--budget quick --seed 2 --scene debris --terrain-seed 7 --terrains 4 "
            "--out D",
        ),
        (
            {"terrains": Terrains(Debris(width=5.0))},
            "--budget quick --seed 2 --scene D/reproduce.toml --out D",
        ),
        (
            {
                "optimizer": "cma",
                "engine": "numpy",
                "terrains": Terrains(Debris(seed=7), 2),
            },
            "--budget quick --seed 2 --optimizer cma --engine numpy --scene debris "
            "--terrain-seed 7 --terrains 2 --out D",
        ),
        (
            {"engine": "numpy", "terrains": Terrains(Debris(width=5.0))},
            "--budget quick --seed 2 --engine numpy --scene D/reproduce.toml --out D",
        ),
        (
            {"terrains": Terrains(Debris(), 2, "min")},
            "--budget quick --seed 2 --scene D/reproduce.toml --out D",
        ),
    ],
)
def test_the_command_that_makes_it(tmp_path, kw, flags):
    rep = _open(tmp_path / "D", seeds=[2], **kw)
    want = "locustjump reproduce " + flags.replace("D", str(tmp_path / "D"))
    assert rep.command() == want
    assert rep.command(monolithic=False) == want.replace(
        " --out", " --no-monolithic --out"
    )


@dataclass(frozen=True)
class Slope(Flat):
    """A scene of a plugin's: no seed, not the flat floor."""

    name: ClassVar[str] = "slope-test"

    @property
    def is_flat(self) -> bool:
        return False


def test_the_command_with_a_scene_without_seeds(tmp_path, monkeypatch):
    monkeypatch.setitem(scene._REGISTRY, Slope.name, Slope)
    rep = _open(tmp_path / "D", seeds=[2], terrains=Terrains(Slope()))
    assert rep.command() == (
        f"locustjump reproduce --budget quick --seed 2 --scene slope-test --out "
        f"{tmp_path / 'D'}"
    )


def test_the_command_over_seeds(tmp_path):
    rep = _open(tmp_path / "M", seeds=[3, 1], many=True, budget="demo")
    out = tmp_path / "M"
    assert (
        rep.command() == f"locustjump reproduce --budget demo --seeds 3,1 --out {out}"
    )
    assert rep.command("ray") == (
        f"locustjump reproduce --budget demo --seeds 3,1 --backend ray --out {out}"
    )
    own = _open(out, seeds=[3, 1], many=True, terrains=Terrains(Debris(width=5.0)))
    assert f"--scene {out / 'seeds.toml'}" in own.command()


def test_the_marker(tmp_path):
    rep = _open(tmp_path / "r", seeds=[6], budget="long", engine="numpy")
    assert rep.marker() == {
        "budget": "long", "seed": 6, "optimizer": "rcga", "engine": "numpy",
        "population": 50, "scene": {"kind": "flat", "terrains": 1, "aggregate": "mean"},
    }  # fmt: skip
    many = _open(tmp_path / "m", seeds=[6, 7], many=True)
    assert "seed" not in many.marker() and many.marker()["budget"] == "quick"


def test_start_writes_the_markers_once(tmp_path):
    rep = _open(tmp_path / "r", seeds=[1])
    rep.start("the command given")
    marker = tomllib.loads((tmp_path / "r" / rundir.MARKER).read_text())
    assert marker == {
        **rep.marker(),
        "generations": {s: rp.BUDGETS["quick"].of(s) for s in rp.TRAINED},
        "command": "the command given",
        "locustjump": __version__,
    }
    _open(tmp_path / "r", seeds=[1]).start("another")  # continued: kept as it is
    assert tomllib.loads((tmp_path / "r" / rundir.MARKER).read_text()) == marker
    _open(tmp_path / "s").start()
    written = tomllib.loads((tmp_path / "s" / rundir.MARKER).read_text())
    assert written["command"] == _open(tmp_path / "s").command()


def test_start_makes_the_directories_it_needs_and_no_other(tmp_path):
    _open(tmp_path / "a" / "b" / "r").start()
    assert sorted(p.name for p in (tmp_path / "a" / "b" / "r").iterdir()) == [
        rundir.MARKER
    ]
    _open(tmp_path / "c" / "m", seeds=[4, 2], many=True).start()
    made = {p.name for p in (tmp_path / "c" / "m").iterdir()}
    assert made == {rundir.SEEDS_MARKER, "seed-2", "seed-4"}


def test_start_over_seeds_lists_every_seed_so_far(tmp_path):
    out = tmp_path / "m"
    _open(out, seeds=[4, 2], many=True).start()
    _open(out, seeds=[9, 2], many=True).start("again")
    seeds = tomllib.loads((out / rundir.SEEDS_MARKER).read_text())
    assert seeds["seeds"] == [2, 4, 9] and seeds["command"] == "again"
    assert "seed" not in seeds and seeds["generations"]["monolithic"] == 90
    for s in (2, 4, 9):
        one = tomllib.loads((out / f"seed-{s}" / rundir.MARKER).read_text())
        assert one["seed"] == s
    assert one["command"] == _open(out / "seed-9", seeds=[9]).command()


def test_check_refuses_what_is_not_this_reproduction(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(UserError, match="exists and is not a directory"):
        _open(f)
    _open(tmp_path / "r", seeds=[1]).start()
    with pytest.raises(UserError) as e:
        _open(tmp_path / "r", seeds=[2])
    assert "holds a reproduction with seed 1, not 2 (choose another " in str(e.value)
    with pytest.raises(UserError, match="with budget 'quick', not 'long'"):
        _open(tmp_path / "r", seeds=[1], budget="long")
    with pytest.raises(UserError, match="holds a single-seed reproduction; give "):
        _open(tmp_path / "r", seeds=[1, 2], many=True)
    _open(tmp_path / "m", seeds=[1, 2], many=True).start()
    with pytest.raises(
        UserError, match="holds a reproduction over seeds with optimizer"
    ):
        _open(tmp_path / "m", seeds=[1, 2], many=True, optimizer="cma")
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "notes.txt").write_text("mine")
    with pytest.raises(UserError, match=r"directory is not empty and holds no "
                       r"reproduction \(no reproduce.toml\)"):  # fmt: skip
        _open(tmp_path / "full")
    assert (tmp_path / "full" / "notes.txt").read_text() == "mine"
    (tmp_path / "empty").mkdir()
    _open(tmp_path / "empty")  # an empty directory is welcome


def test_check_looks_into_each_seeds_directory(tmp_path):
    out = tmp_path / "m"
    _open(out, seeds=[1], many=True).start()
    (out / "seed-3").mkdir()
    (out / "seed-3" / "x").write_text("x")
    with pytest.raises(UserError, match="seed-3: directory is not empty"):
        _open(out, seeds=[1, 3], many=True)


def test_a_key_an_older_marker_lacks_is_not_checked(tmp_path):
    rep = _open(tmp_path / "r", seeds=[1])
    rep.start()
    path = tmp_path / "r" / rundir.MARKER
    marker = tomllib.loads(path.read_text())
    del marker["engine"]  # written before there were engines: numpy's
    rundir.write_toml(path, marker)
    assert _open(tmp_path / "r", seeds=[1]).engine == "numpy"
    with pytest.raises(UserError, match="with engine 'numpy', not 'numba'"):
        _open(tmp_path / "r", seeds=[1], engine="numba")
    many = _open(tmp_path / "m", seeds=[1], many=True)
    many.start()
    for path in (
        tmp_path / "m" / rundir.SEEDS_MARKER,
        tmp_path / "m" / "seed-1" / rundir.MARKER,
    ):
        marker = tomllib.loads(path.read_text())
        del marker["engine"]
        rundir.write_toml(path, marker)
    assert _open(tmp_path / "m", seeds=[1], many=True, engine="numpy").engine == "numpy"


def _run(d: Path, generations: int) -> None:
    d.mkdir(parents=True)
    rows = "".join(f"{g},0\n" for g in range(1, generations + 1))
    (d / rundir.METRICS).write_text("generation,x\n" + rows)


def test_a_stage_is_done_when_trained_and_evaluated(tmp_path, monkeypatch):
    rep = _open(tmp_path / "r", seeds=[2])
    monkeypatch.setattr(
        rp.rundir, "generations_done", lambda d: int(Path(d, "g").read_text())
    )
    kick = tmp_path / "r" / "kick"
    kick.mkdir(parents=True)
    (kick / "g").write_text("30")
    assert not rep.stage_done("kick")  # not evaluated
    rundir.eval_metrics_path(kick).parent.mkdir()
    rundir.eval_metrics_path(kick).write_text("{}")
    assert rep.stage_done("kick") and rep.stage_done("kick", seed=2)
    (kick / "g").write_text("29")  # one generation short of the budget
    assert not rep.stage_done("kick")
    (kick / rundir.STOP).write_text("{}")  # the optimizer stopped early
    assert rep.stage_done("kick")
    assert not rep.stage_done("rules")
    (tmp_path / "r" / "rules").mkdir()
    (tmp_path / "r" / "rules" / rundir.RULES_SUMMARY).write_text("{}")
    assert rep.stage_done("rules")


def test_a_stage_of_another_seed_is_looked_for_in_its_directory(tmp_path):
    rep = _open(tmp_path / "m", seeds=[2, 1], many=True)
    rules = tmp_path / "m" / "seed-2" / "rules"
    rules.mkdir(parents=True)
    (rules / rundir.RULES_SUMMARY).write_text("{}")
    assert rep.stage_done("rules", seed=2) and not rep.stage_done("rules", seed=1)
    assert rep.stage_done("rules")  # of the first seed


def test_what_each_stage_trains(tmp_path):
    debris = Terrains(Debris(seed=1), 2)
    rep = _open(tmp_path / "r", seeds=[5], budget="long", optimizer="cma",
                engine="numpy", terrains=debris)  # fmt: skip
    cfg = rep.train_config("composed")
    assert (cfg.behaviour, cfg.seed, cfg.generations) == ("composed", 5, 120)
    assert cfg.optimizer == CMAParams(population=50)
    assert (cfg.engine, cfg.scene, cfg.model) == ("numpy", debris, rp.lm.LocustParams())
    many = _open(tmp_path / "m", seeds=[1, 2], many=True)
    assert many.train_config("kick", seed=2).seed == 2
    assert many.train_config("kick").seed == 1


def test_an_older_marker_is_read_as_it_was_meant(tmp_path):
    assert rp._read_marker(tmp_path / "none.toml") == {
        "scene": {"kind": "flat", "terrains": 1, "aggregate": "mean"}
    }
    many = _open(tmp_path / "m", seeds=[1], many=True)
    many.start()
    seeds = tmp_path / "m" / rundir.SEEDS_MARKER
    table = tomllib.loads(seeds.read_text())
    del table["scene"]  # written before there were scenes
    rundir.write_toml(seeds, table)
    assert rp._read_marker(seeds)["scene"]["kind"] == "flat"
    assert rp._read_marker(seeds)["seeds"] == [1]
