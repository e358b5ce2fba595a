"""Ranges declared once (:mod:`locustjump.ranges`): what a ``Range`` accepts,
and that the parser, its help and the config reader all read the declaration
(the same bounds in the same words wherever a setting is given)."""

import argparse
import math

import numpy as np
import pytest

from helpers import exit_status
from locustjump.cli.parser import build_parser
from locustjump.evo import CMAParams, RandomSearchParams, RCGAParams
from locustjump.evo.base import POPULATION
from locustjump.ranges import (
    INT64_MAX,
    Range,
    SettingTypeError,
    SettingValueError,
    range_of,
)
from locustjump.rundir.config import TrainConfig


def test_a_range_checks_kind_and_bounds_and_returns_the_number_it_holds():
    r = Range(2, 10, integer=True)
    assert r.check("n", np.int64(3)) == 3 and type(r.check("n", np.int64(3))) is int
    for bad in (True, 3.0, "3", None, 3 + 0j):
        with pytest.raises(
            SettingTypeError, match=r"^n must be an integer in \[2, 10\]"
        ):
            r.check("n", bad)
    for bad in (1, 11, 2**64, -(2**64)):
        with pytest.raises(SettingValueError):
            r.check("n", bad)
    assert r.check("n", 2) == 2 and r.check("n", 10) == 10  # closed bounds
    x = Range(0.0, 1.0, lo_open=True)
    assert x.check("x", 1) == 1.0 and type(x.check("x", 1)) is float
    assert x.check("x", 5e-324) == 5e-324
    for bad in (0.0, -0.0, 1.0000000000000002, math.nan, math.inf, 10**400):
        with pytest.raises(SettingValueError, match=r"^x must be in \(0, 1\]"):
            x.check("x", bad)
    with pytest.raises(SettingTypeError, match=r"^x must be a number in \(0, 1\]"):
        x.check("x", False)
    free = Range()  # a finite number, whatever its size
    assert free.check("y", -1e308) == -1e308
    with pytest.raises(SettingValueError, match="^y must be a finite number"):
        free.check("y", -math.inf)
    v = Range(0.0, lo_open=True, size=2)
    assert v.check("v", [1, 2.5]) == (1.0, 2.5)
    for bad in ((1.0,), (1.0, 2.0, 3.0), "ab", 1.0):
        with pytest.raises(SettingTypeError, match="^v must be 2 finite numbers"):
            v.check("v", bad)
    with pytest.raises(
        SettingValueError, match=r"^v must be 2 finite numbers each > 0"
    ):
        v.check("v", (1.0, 0.0))


def test_a_range_parses_an_options_text():
    r = Range(0, INT64_MAX, integer=True)
    assert r.parse("--seed", str(INT64_MAX)) == INT64_MAX
    assert str(r) == "an integer in [0, 2**63-1]"
    with pytest.raises(
        SettingValueError, match=r"^--seed must be .*, got 9223372036854775808$"
    ):
        r.parse("--seed", str(2**63))
    with pytest.raises(SettingTypeError, match="^--seed must be an integer"):
        r.parse("--seed", "1e3")
    f = Range(0.0, 120.0, lo_open=True, unit="frames/s")
    assert str(f) == "in (0, 120] frames/s"
    for text in ("nan", "inf", "-inf", "0", "1e400", "120.00000000000001"):
        with pytest.raises(SettingValueError):
            f.parse("--fps", text)
    assert f.parse("--fps", "5e-324") == 5e-324


def _options():
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                for a in sub._actions:
                    if a.option_strings:
                        yield name, a


def test_every_numeric_option_reads_a_declared_range_and_its_help_says_it():
    text_types = {"out_path", "_seeds", "_terrain_seeds"}  # paths, seed lists
    ranged = 0
    for command, a in _options():
        assert a.type not in (int, float), (command, a.option_strings)
        if a.type is None or getattr(a.type, "__name__", "") in text_types:
            continue
        valid = a.type.valid  # every other type checks a declared range
        ranged += 1
        assert valid.interval() in " ".join(a.help.split()), (command, a.help)
    assert ranged >= 25


def test_options_read_the_ranges_their_settings_declare():
    from locustjump.present.render import FPS
    from locustjump.sim.engine.job import N_STEPS
    from locustjump.sim.params import LocustParams
    from locustjump.sim.scene import TERRAIN_SEED, TERRAINS
    from locustjump.tasks.composed import SwitchOptions
    from locustjump.tasks.getup import STEP_DEG

    declared = {
        ("train", "--population"): POPULATION,
        ("train", "--generations"): range_of(TrainConfig, "generations"),
        ("train", "--seed"): range_of(TrainConfig, "seed"),
        ("reproduce", "--seed"): range_of(TrainConfig, "seed"),
        ("train", "--switch-every"): range_of(SwitchOptions, "switch_every"),
        ("train", "--terrains"): TERRAINS,
        ("evaluate", "--terrain-seed"): TERRAIN_SEED,
        ("model", "--scale"): range_of(LocustParams, "scale"),
        ("rules", "--strut-stiffness"): range_of(LocustParams, "strut_stiffness"),
        ("rules", "--steps"): N_STEPS,
        ("render", "--fps"): FPS,
        ("sweep-getup", "--step-deg"): STEP_DEG,
    }
    given = {(c, a.option_strings[-1]): a.type.valid for c, a in _options()
             if getattr(a.type, "valid", None)}  # fmt: skip
    for key, valid in declared.items():
        assert given[key] is valid, key


def test_every_optimizer_declares_one_population_range():
    for cls in (RCGAParams, CMAParams, RandomSearchParams):
        assert range_of(cls, "population") is POPULATION


@pytest.mark.parametrize("value", ["-5", "1", "0", "1000001"])
def test_population_is_refused_in_the_same_words_whatever_the_value(
    value, tmp_path, capsys
):
    for optimizer in ("rcga", "cma", "random"):
        argv = ["train", "kick", "--optimizer", optimizer, "--population", value,
                "--out", str(tmp_path / "run")]  # fmt: skip
        assert exit_status(argv) == 2
        err = capsys.readouterr().err
        assert err == (
            "locustjump: error: argument --population: --population must be an "
            f"integer in [2, 1000000], got {value}\n"
        ), err
    assert not (tmp_path / "run").exists()


def test_a_config_file_is_refused_in_the_words_of_the_same_declaration(
    tmp_path, capsys
):
    (tmp_path / "c.toml").write_text("[optimizer]\npopulation = 1\n")
    argv = ["train", "kick", "--config", str(tmp_path / "c.toml"),
            "--out", str(tmp_path / "run")]  # fmt: skip
    assert exit_status(argv) == 2
    err = capsys.readouterr().err
    assert "population must be an integer in [2, 1000000], got 1" in err
    assert err.count("\n") == 1 and not (tmp_path / "run").exists()


def test_the_largest_terrain_seed_is_a_terrain(tmp_path, capsys):
    big = str(INT64_MAX)
    out = tmp_path / "m.xml"
    argv = ["model", "--scene", "debris", "--terrain-seed", big, "--out", str(out)]
    assert exit_status(argv) == 0 and out.read_text().startswith("<mujoco")
    capsys.readouterr()
    # two terrains from it: the second's seed would be 2**63; --terrains is named
    argv = ["train", "kick", "--scene", "debris", "--terrain-seed", big,
            "--terrains", "2", "--out", str(tmp_path / "run")]  # fmt: skip
    assert exit_status(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("locustjump: error: --terrains must be at most 1 from seed")
    assert err.count("\n") == 1 and not (tmp_path / "run").exists()
    argv = ["model", "--scene", "debris", "--terrain-seed", str(2**63),
            "--out", str(out)]  # fmt: skip
    assert exit_status(argv) == 2
    assert (
        "--terrain-seed must be an integer in [0, 2**63-1]" in capsys.readouterr().err
    )


def test_reproduce_refuses_seed_with_seeds(tmp_path, capsys):
    for seed in ("0", "3"):
        argv = ["reproduce", "--seed", seed, "--seeds", "0-1", "--out",
                str(tmp_path / "rep")]  # fmt: skip
        assert exit_status(argv) == 2
        err = capsys.readouterr().err
        assert "--seeds: not allowed with argument --seed" in err, err
        assert err.count("\n") == 1
    assert not (tmp_path / "rep").exists()
