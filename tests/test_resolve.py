"""``locustjump train``'s options resolved into the configuration it runs, and
the terrains a command's ``--scene``/``--terrain-seed``/``--terrains`` name
(:mod:`locustjump.cli.resolve`): what wins over what, and each refusal's
words (the option named, as the command line prints it)."""

import argparse
from pathlib import Path

import pytest

from helpers import user_error
from locustjump import rundir
from locustjump.cli import resolve as rs
from locustjump.evo import CMAParams, RCGAParams
from locustjump.rundir.config import TrainConfig
from locustjump.sim.scene import Debris, Flat, Terrains
from locustjump.tasks.options import CommonOptions

STUDY = Path(__file__).resolve().parent.parent / "results" / "study"
KICK = STUDY / "debris-kick-s0"  # trained on debris terrains 1000-1003


def test_the_defaults_then_a_file_then_the_options_given(tmp_path):
    assert rs.resolve_config("getup", tmp_path / "r") == TrainConfig(behaviour="getup")
    conf = tmp_path / "c.toml"
    conf.write_text('seed = 3\ngenerations = 9\n[optimizer]\nkind = "cma"\n')
    cfg = rs.resolve_config("kick", tmp_path / "r", config=conf)
    assert (cfg.seed, cfg.generations, cfg.optimizer.kind) == (3, 9, "cma")
    cfg = rs.resolve_config("kick", tmp_path / "r", config=str(conf), seed=4,
                            generations=5, population=7, engine="numpy")  # fmt: skip
    assert (cfg.seed, cfg.generations, cfg.engine) == (4, 5, "numpy")
    assert cfg.optimizer == CMAParams().replace(population=7)


def test_another_optimizer_starts_from_its_defaults(tmp_path):
    conf = tmp_path / "c.toml"
    conf.write_text('[optimizer]\nkind = "rcga"\npopulation = 12\n')
    same = rs.resolve_config("kick", tmp_path, config=conf, optimizer="rcga")
    assert same.optimizer == RCGAParams(population=12)  # kept: the same kind
    other = rs.resolve_config("kick", tmp_path, config=conf, optimizer="cma")
    assert other.optimizer == CMAParams()
    assert rs.resolve_config(
        "kick", tmp_path, optimizer="cma", population=8
    ).optimizer == (CMAParams(population=8))
    assert user_error(rs.resolve_config, "kick", tmp_path, optimizer="nope").startswith(
        "--optimizer: unknown optimizer 'nope'"
    )


def test_a_behaviours_options_are_its_own(tmp_path):
    cfg = rs.resolve_config("kick", tmp_path, options={"score_substeps": (6, 12)})
    assert cfg.options == CommonOptions((6, 12))
    composed = rs.resolve_config("composed", tmp_path, options={"switch_every": 30})
    assert composed.options.switch_every == 30
    assert user_error(
        rs.resolve_config, "kick", tmp_path, options={"switch_every": 30}
    ) == (  # fmt: skip
        "--switch-every: only the composed, composed-height and composed-repertoire "
        "behaviours take it, not 'kick'"
    )
    assert user_error(
        rs.resolve_config, "kick", tmp_path, options={"score_substeps": (0,)}
    ).startswith(  # fmt: skip
        "--score-substeps must be distinct integers each in [1, 48], got [0]"
    )


@pytest.mark.parametrize(
    ("kw", "words"),
    [
        ({"seed": -1}, "--seed must be an integer in [0, 2**63-1], got -1"),
        ({"population": 1}, "--population must be an integer in [2, 1000000], got 1"),
        ({"generations": 0}, "--generations must be an integer in [1, 2**63-1], got 0"),
        ({"terrains": 2}, "--terrains must be 1 (the flat scene has one terrain), "
                          "got 2"),
    ],
)  # fmt: skip
def test_an_options_value_is_refused_naming_the_option(tmp_path, kw, words):
    assert user_error(rs.resolve_config, "kick", tmp_path, **kw) == words


def test_a_config_file_that_is_not_there_or_not_this_behaviour(tmp_path):
    missing = tmp_path / "none.toml"
    assert user_error(rs.resolve_config, "kick", tmp_path, config=missing).startswith(
        f"--config: {missing}: "
    )
    conf = tmp_path / "c.toml"
    conf.write_text('behaviour = "getup"\n')
    assert user_error(rs.resolve_config, "kick", tmp_path, config=conf) == (
        f"{conf}: behaviour 'getup' differs from the command's 'kick'"
    )
    conf.write_text("seed = 'x'\n")  # there, but wrong: named as the file
    assert user_error(rs.resolve_config, "kick", tmp_path, config=conf).startswith(
        f"{conf}: "
    )


def test_a_resumed_run_is_its_own_config_with_the_options_given(tmp_path):
    cfg = rs.resolve_config("kick", KICK, resume=True)
    assert cfg == rundir.load_config(KICK / "config.toml")
    longer = rs.resolve_config("kick", KICK, resume=True, generations=150)
    assert longer == cfg.replace(generations=150)
    assert user_error(
        rs.resolve_config, "kick", KICK, resume=True, config="c.toml"
    ) == ("--resume reads the run's own config.toml; drop --config")
    assert user_error(rs.resolve_config, "getup", KICK, resume=True) == (
        f"--resume: {KICK} holds a 'kick' run, not 'getup'"
    )
    assert user_error(rs.resolve_config, "kick", tmp_path / "x", resume=True) == (
        f"--resume: {tmp_path / 'x'} holds no run (no config.toml)"
    )
    (tmp_path / "frozen.npz").write_bytes(b"")  # a run stopped before its config
    assert user_error(rs.resolve_config, "kick", tmp_path, resume=True) == (
        f"--resume: {tmp_path} holds no run (no config.toml); it was stopped "
        "before it started: rerun without --resume"
    )


def test_terrains_named_over_a_base():
    base = Terrains(Debris(seed=10), 4, "min")
    assert rs.terrains_arg(None) is None
    assert rs.terrains_arg(None, base=base) is base
    assert rs.terrains_arg("debris") == Terrains(Debris())
    assert rs.terrains_arg("flat", base=base) == Terrains(Flat())
    assert rs.terrains_arg(None, 20, base=base) == Terrains(Debris(seed=20), 4, "min")
    assert rs.terrains_arg(None, 20, 2, base=base) == Terrains(
        Debris(seed=20), 2, "min"
    )
    assert rs.terrains_arg(None, None, 2, base=base) == Terrains(
        Debris(seed=10), 2, "min"
    )
    assert rs.terrains_arg("debris", 5, 3) == Terrains(Debris(seed=5), 3)
    assert rs.terrains_arg(None, None, 1) == Terrains()


def test_terrains_refused_name_the_option():
    assert user_error(rs.terrains_arg, None, 3) == (
        "--terrain-seed: the flat scene has no terrains to choose from "
        "(e.g. --scene debris)"
    )
    assert user_error(rs.terrains_arg, "debris", -1) == (
        "--terrain-seed must be an integer in [0, 2**63-1], got -1"
    )
    assert user_error(
        rs.terrains_arg, None, 2**63 - 1, None, Terrains(Debris(), 2)
    ).startswith(  # fmt: skip
        "--terrain-seed: terrains must be at most 1 from seed"
    )
    assert user_error(rs.terrains_arg, "debris", None, 65) == (
        "--terrains must be an integer in [1, 64], got 65"
    )
    assert user_error(rs.terrains_arg, "moon") == (
        "--scene: unknown scene 'moon'; choose from flat, debris, or give a .toml "
        "file with a [scene] table"
    )


def test_a_scene_file(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('[scene]\nkind = "debris"\nseed = 7\nterrains = 2\n')
    assert rs.terrains_arg(str(f)) == Terrains(Debris(seed=7), 2)
    f.write_text("x = 1\n")
    assert user_error(rs.terrains_arg, str(f)) == f"--scene: {f}: no [scene] table"


def test_a_runs_own_terrains(tmp_path):
    assert rs.own_terrains(KICK) == rundir.load_config(KICK / "config.toml").scene
    (tmp_path / "summary.json").write_text('{"scene": {"kind": "debris", "seed": 4}}')
    (tmp_path / "trajectory.csv").write_text("")
    assert rs.own_terrains(tmp_path) == Terrains(Debris(seed=4))
    (tmp_path / "summary.json").write_text("{}")  # made before scenes: the floor
    assert rs.own_terrains(str(tmp_path)) == Terrains()
    (tmp_path / "trajectory.csv").unlink()  # a summary alone is no run
    assert user_error(rs.own_terrains, tmp_path) == (
        f"--terrain-seed: {tmp_path} is not a run; give --scene too"
    )


def _args(scene=None, terrain_seed=None):
    return argparse.Namespace(scene=scene, terrain_seed=terrain_seed)


def test_a_commands_scene_over_the_runs_own():
    assert rs.scene_override(_args(), KICK) is None
    assert rs.scene_override(_args(terrain_seed=100), KICK) == Debris(seed=100)
    assert rs.scene_override(_args("flat", None), KICK) == Flat()
    assert rs.scene_override(_args("debris", 3)) == Debris(seed=3)
    assert user_error(rs.scene_override, _args(terrain_seed=3)).startswith(
        "--terrain-seed: the flat scene has no terrains"
    )


def test_a_scene_file_that_is_not_one_is_named(tmp_path):
    d = tmp_path / "d.toml"
    d.mkdir()
    assert user_error(rs.terrains_arg, str(d)) == (
        f"{d}: is a directory, not a regular file; expected a scene file"
    )
    f = tmp_path / "s.toml"
    f.write_text('[scene]\nkind = "moon"\n')
    assert user_error(rs.terrains_arg, str(f)) == (
        f"{f}: scene.kind: unknown scene 'moon'; choose from flat, debris"
    )


def test_a_rule_based_runs_scene_table_is_named_when_wrong(tmp_path):
    (tmp_path / "summary.json").write_text('{"scene": {"kind": "moon"}}')
    (tmp_path / "trajectory.csv").write_text("")
    assert user_error(rs.own_terrains, tmp_path).startswith(
        f"{tmp_path / 'summary.json'}: scene.kind: unknown scene 'moon'"
    )


def test_a_seed_near_the_last_takes_the_count_given_not_the_bases():
    base = Terrains(Debris(), 4)
    last = rs.terrains_arg(None, 2**63 - 1, 1, base=base)
    assert last == Terrains(Debris(seed=2**63 - 1), 1)


def test_the_scene_options_reach_the_config(tmp_path):
    cfg = rs.resolve_config("kick", tmp_path, scene="debris", terrain_seed=5,
                            terrains=3)  # fmt: skip
    assert cfg.scene == Terrains(Debris(seed=5), 3)
    conf = tmp_path / "c.toml"
    conf.write_text("seed = 2\n")  # names no behaviour: the command's
    assert rs.resolve_config("getup", tmp_path, config=conf).behaviour == "getup"


def _raises(error):
    def make(*args, **changes):
        raise error

    return make


def test_a_checked_error_names_the_option_in_place_of_its_setting():
    from locustjump.errors import setting_ref
    from locustjump.ranges import SettingValueError

    twice = SettingValueError("n_steps", f"below the {setting_ref('n_steps')} of x", 5)
    assert user_error(rs._checked, "--n-steps", _raises(twice)) == (
        "--n-steps must be below the n_steps of x, got 5"  # the first: the option's
    )
    assert user_error(rs._checked, "--steps", _raises(twice), n_steps=5) == (
        "--steps must be below the n_steps of x, got 5"  # a change it made
    )
    other = SettingValueError("seed", "an integer", -1)
    assert user_error(rs._checked, "--terrain-seed", _raises(other)) == (
        "--terrain-seed: seed must be an integer, got -1"
    )
    assert user_error(rs._checked, "--x", _raises(ValueError("bad"))) == "--x: bad"
