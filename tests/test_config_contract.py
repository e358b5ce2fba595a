"""A run's configuration (rundir/config.py) stated exactly: the range of each
top-level setting with its boundary, the defaults of a [scene] table, and the
one-line error for each wrong table (tests/test_config_coerce.py: how each TOML
value is coerced to its setting's type).

Written against the mutants the suite let through (issue #48,
scripts/mutation.py): seed -1 accepted, the 2**63 bounds, `true` taken for an
integer or a float, the default terrain count.
"""

import re

import pytest

from helpers import exactly
from locustjump.errors import UserError
from locustjump.evo import RCGAParams, optimizer_kinds
from locustjump.evo.cma import CMAParams
from locustjump.evo.map_elites import MapElitesParams
from locustjump.evo.qd import DEFAULT_CELLS
from locustjump.rundir import config as C
from locustjump.sim.engine.job import ENGINES
from locustjump.sim.scene import MAX_TERRAINS, Debris, Flat, Terrains
from locustjump.tasks import behaviour_names
from locustjump.tasks.base import CommonOptions
from locustjump.tasks.composed import SwitchOptions

SRC = "cfg.toml"
KINDS = ", ".join(optimizer_kinds())  # the built-in optimizers


# --- TrainConfig's own checks --------------------------------------------------


def test_the_boundaries_are_accepted():
    C.TrainConfig(seed=0, generations=1)
    C.TrainConfig(seed=2**63 - 1, generations=2**63 - 1)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"seed": -1}, "seed must be an integer in [0, 2**63-1], got -1"),
        ({"generations": 0}, "generations must be an integer in [1, 2**63-1], got 0"),
        (
            {"seed": 2**63},
            ("seed must be an integer in [0, 2**63-1], got 9223372036854775808"),
        ),
        (
            {"generations": 2**63},
            "generations must be an integer in [1, 2**63-1], got 9223372036854775808",
        ),
        ({"engine": "gpu"}, f"engine must be one of {', '.join(ENGINES)}, got 'gpu'"),
        (
            {"behaviour": "fly"},
            f"behaviour must be one of {', '.join(behaviour_names())}, got 'fly'",
        ),
        (
            {"behaviour": "composed", "options": CommonOptions()},
            (
                "options must be SwitchOptions (the composed behaviour's), got "
                "CommonOptions(score_substeps=())"
            ),
        ),
        (
            {"optimizer": object()},
            (
                "optimizer must be an optimizer's settings (RCGAParams, "
                "CMAParams, RandomSearchParams, MapElitesParams, CMAMEParams), "
                "got <object object at "
            ),
        ),
    ],
)
def test_a_setting_out_of_range_is_named(kwargs, message):
    # an object's repr ends in its address: that message is matched to "at "
    pattern = "^" + re.escape(message) if message.endswith(" at ") else exactly(message)
    with pytest.raises((ValueError, TypeError), match=pattern):
        C.TrainConfig(**kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"frozen_digest": 3}, "frozen_digest must be text, got 3"),
        ({"model": 3}, "model must be LocustParams, got 3"),
        (
            {"scene": "debris"},
            "scene must be Terrains (e.g. Terrains(Debris())), got 'debris'",
        ),
        (
            {
                "optimizer": type(
                    "Fake", (), {"kind": "rcga", "__repr__": lambda s: "fake"}
                )()
            },
            (
                "optimizer must be an optimizer's settings (RCGAParams, "
                "CMAParams, RandomSearchParams, MapElitesParams, CMAMEParams), "
                "got fake"
            ),
        ),
    ],
)
def test_a_setting_of_the_wrong_type_is_named(kwargs, message):
    with pytest.raises(TypeError, match=exactly(message)):
        C.TrainConfig(**kwargs)


def test_a_qd_optimizer_takes_the_behaviour_s_descriptors():
    cfg = C.TrainConfig(optimizer=MapElitesParams(population=4))
    opt = cfg.optimizer
    assert opt.descriptors == ("apex_distance", "apex_rise")  # the kick's default
    assert opt.ranges == ((-5.0, 15.0), (0.0, 5.0))  # as the kick declares them
    assert opt.cells == (DEFAULT_CELLS, DEFAULT_CELLS)
    chosen = MapElitesParams(population=4, descriptors=("apex_angle",), cells=(7,))
    assert C.TrainConfig(optimizer=chosen).optimizer.ranges == ((0.0, 180.0),)
    with pytest.raises(
        ValueError,
        match=exactly(
            "unknown descriptor 'tilt'; kick declares apex_rise, apex_distance, "
            "apex_angle"
        ),
    ):
        C.TrainConfig(optimizer=MapElitesParams(population=4, descriptors=("tilt",)))
    with pytest.raises(
        ValueError,
        match=exactly(
            "the map-elites optimizer needs behaviour descriptors and getup "
            "declares none"
        ),
    ):
        C.TrainConfig(behaviour="getup", optimizer=MapElitesParams(population=4))


def test_options_default_to_the_behaviour_s_and_population_is_the_optimizer_s():
    cfg = C.TrainConfig(behaviour="composed", optimizer=CMAParams(population=7))
    assert cfg.options == SwitchOptions() and cfg.population == 7
    assert C.TrainConfig().options == CommonOptions()
    assert cfg.replace(seed=3).seed == 3 and cfg.replace(seed=3).population == 7


def test_to_dict_is_config_toml_and_names_only_what_is_set():
    d = C.TrainConfig(
        seed=5, generations=9, optimizer=RCGAParams(population=6)
    ).to_dict()
    assert list(d) == [
        "format",
        "behaviour",
        "seed",
        "generations",
        "engine",
        "optimizer",
        "model",
        "options",
        "scene",
    ]
    assert (d["behaviour"], d["seed"], d["generations"]) == ("kick", 5, 9)
    assert d["optimizer"]["kind"] == "rcga" and d["optimizer"]["population"] == 6
    assert d["options"] == {"score_substeps": []}  # tuples as TOML arrays
    assert d["scene"] == {"kind": "flat", "terrains": 1, "aggregate": "mean"}
    d = C.TrainConfig(frozen_digest="ab").to_dict()
    assert d["frozen_digest"] == "ab"


def test_the_hash_ignores_generations_only():
    cfg = C.TrainConfig()
    assert len(cfg.hash()) == 16
    assert cfg.replace(generations=5).hash() == cfg.hash()
    for other in (
        cfg.replace(seed=1),
        cfg.replace(frozen_digest="x"),
        cfg.replace(scene=Terrains(Debris(), 2)),
        cfg.replace(options=CommonOptions((3,))),
    ):
        assert other.hash() != cfg.hash()


# --- from_dict: a config.toml's table ---------------------------------------------


def test_from_dict_reads_every_table():
    cfg = C.TrainConfig.from_dict(
        {
            "behaviour": "composed",
            "seed": 4,
            "generations": 3,
            "engine": "numpy",
            "optimizer": {"kind": "cma", "population": 8},
            "model": {"scale": 2.0},
            "options": {"switch_every": 5},
            "scene": {"kind": "debris", "seed": 7, "terrains": 2, "aggregate": "min"},
        },
        SRC,
    )
    assert (cfg.behaviour, cfg.seed, cfg.generations, cfg.engine) == (
        "composed",
        4,
        3,
        "numpy",
    )
    assert cfg.optimizer == CMAParams(population=8) and cfg.model.scale == 2.0
    assert cfg.options == SwitchOptions(switch_every=5)
    assert cfg.scene == Terrains(Debris(seed=7), 2, "min")
    assert C.TrainConfig.from_dict(cfg.to_dict(), SRC) == cfg
    assert C.TrainConfig.from_dict({}, SRC) == C.TrainConfig()


@pytest.mark.parametrize(
    "table, message",
    [
        ({"colour": 1}, "unknown key 'colour'"),
        ({"seed": -1}, "seed must be an integer in [0, 2**63-1], got -1"),
        ({"seed": True}, "seed must be int, got bool True"),
        ({"seed": 1.0}, "seed must be int, got float 1.0"),
        ({"engine": 3}, "engine must be str, got int 3"),
        (
            {"behaviour": "fly", "options": {}},
            f"unknown behaviour 'fly'; choose from {', '.join(behaviour_names())}",
        ),
        ({"options": {"switch_every": 2}}, "unknown key 'options.switch_every'"),
        ({"optimizer": 3}, "optimizer must be a table"),
        (
            {"optimizer": {"kind": "sa"}},
            f"optimizer.kind: unknown optimizer 'sa'; choose from {KINDS}",
        ),
        (
            {"optimizer": {"population": 1, "elite": 0}},
            "[optimizer] population must be an integer in [2, 1000000], got 1",
        ),
        ({"model": []}, "model must be a table"),
        ({"model": {"legs": 6}}, "unknown key 'model.legs'"),
        ({"scene": {"kind": 3}}, "scene.kind must be a string, got 3"),
        ({"scene": "debris"}, "scene must be a table"),
        (
            {"scene": {"kind": "moon"}},
            "scene.kind: unknown scene 'moon'; choose from flat, debris",
        ),
        ({"scene": {"terrains": True}}, "scene.terrains must be int, got bool True"),
        (
            {"scene": {"kind": "debris", "terrains": 0}},
            f"[scene] terrains must be an integer in [1, {MAX_TERRAINS}], got 0",
        ),
        ({"scene": {"aggregate": 1}}, "scene.aggregate must be str, got int 1"),
        ({"scene": {"kind": "debris", "height": 1}}, "unknown key 'scene.height'"),
    ],
)
def test_each_wrong_table_is_one_line_naming_the_file_and_key(table, message):
    with pytest.raises(UserError, match=exactly(f"{SRC}: {message}")):
        C.TrainConfig.from_dict(table, SRC)


def test_an_rcga_table_of_format_1_is_named_as_the_file_names_it():
    with pytest.raises(UserError, match=exactly(f"{SRC}: rcga must be a table")):
        C.TrainConfig.from_dict({"format": 1, "rcga": 3}, SRC)
    assert C.optimizer_from_table({}, SRC) == RCGAParams()


def test_a_scene_table_defaults_to_one_terrain_and_the_mean():
    t = C.terrains_from_table({"kind": "debris", "seed": 3}, SRC)
    assert (t.count, t.aggregate, t.scene) == (1, "mean", Debris(seed=3))
    assert C.terrains_from_table({}, SRC) == Terrains(Flat())
    assert C.scene_table(t) == {
        "kind": "debris",
        **{
            k: list(v) if isinstance(v, tuple) else v
            for k, v in vars(Debris(seed=3)).items()
        },
        "terrains": 1,
        "aggregate": "mean",
    }


# --- [plugins]: where a run's classes came from -----------------------------------


def plugin_params(module):
    """An optimizer's settings class defined in ``module`` (a plugin's)."""
    import dataclasses

    cls = dataclasses.make_dataclass(
        "HillParams", [("population", int, 4)], frozen=True
    )
    cls.kind, cls.__module__ = "hill", module
    return cls


def test_plugins_are_recorded_but_not_hashed(monkeypatch):
    import locustjump.evo as evo

    monkeypatch.setattr(evo, "_REGISTRY", dict(evo._REGISTRY))
    runs = []
    for module in ("hillpkg", "otherpkg"):
        params = plugin_params(module)
        evo._REGISTRY["hill"] = type("Hill", (), {"Params": params})
        cfg = C.TrainConfig(optimizer=params())
        runs.append((cfg.to_dict()["plugins"], cfg.hash()))
    assert runs[0][0] == {"hillpkg": ""} and runs[1][0] == {"otherpkg": ""}
    assert runs[0][1] == runs[1][1]  # the same experiment from either module
    assert "plugins" not in C.TrainConfig().to_dict()


def test_a_config_s_plugins_table_is_read_and_checked():
    assert C.TrainConfig.from_dict({"plugins": {"x.y": "xdist"}}, SRC) == (
        C.TrainConfig()
    )
    for bad in (3, {"m": 1}):
        with pytest.raises(
            UserError, match=exactly(f"{SRC}: plugins must be a table of strings")
        ):
            C.TrainConfig.from_dict({"plugins": bad}, SRC)
    message = (
        f"{SRC}: made with the plugin nosuch.mod (distribution nosuchdist), which "
        "is not loaded here: install nosuchdist, or give plugin nosuch.mod"
    )
    with pytest.raises(UserError, match=exactly(message)):
        C.TrainConfig.from_dict(
            {"plugins": {"nosuch.mod": "nosuchdist"}, "optimizer": {"kind": "hill"}},
            SRC,
        )
