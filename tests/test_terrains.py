"""Scenes by name and the terrains a genome is scored on
(:mod:`locustjump.sim.scene`, :mod:`locustjump.sim.world`): which terrains,
how their fitness is combined, and the words of what is refused."""

from dataclasses import dataclass
from typing import ClassVar

import mujoco
import numpy as np
import pytest

from helpers import exactly
from locustjump.ranges import INT64_MAX, SettingTypeError, SettingValueError
from locustjump.sim import names
from locustjump.sim import scene as sc
from locustjump.sim.model import to_mjcf
from locustjump.sim.params import LocustParams
from locustjump.sim.scene import Debris, Flat, Terrains


def test_the_flat_floor_is_one_terrain_of_height_zero():
    f = Flat()
    assert f.is_flat and not f.seeded and f.with_seed(7) is f
    h = f.heights(np.zeros((2, 1)), np.zeros(3), 0.5)
    assert h.shape == (2, 3) and not h.any()
    m = f.mjcf(0.5)
    assert m.geoms == (names.FLOOR,) and not m.broad_phase and m.walls == ()
    assert m.worldbody == (
        f'<geom name="{names.FLOOR}" type="plane" contype="0" conaffinity="0" '
        'size="0 0 0.025" material="grid"/>'
    )
    assert '<material name="grid" texture="grid"' in m.assets


def test_a_seeded_scene_is_one_terrain_per_seed():
    d = Debris(seed=3)
    assert d.seeded and not d.is_flat
    assert d.with_seed(5) == Debris(seed=5) and d.seed == 3


def test_terrains_are_consecutive_seeds_from_the_scenes():
    t = Terrains(Debris(seed=10), 3, "min")
    assert t.scenes == (Debris(seed=10), Debris(seed=11), Debris(seed=12))
    assert Terrains().scenes == (Flat(),) and Terrains().aggregate == "mean"
    last = Terrains(Debris(seed=INT64_MAX - 1), 2)
    assert last.scenes[-1].seed == INT64_MAX
    assert Terrains(Debris(), np.int64(2)).count == 2
    assert type(Terrains(Debris(), np.int64(2)).count) is int


def test_fitness_on_several_terrains_is_their_mean_or_worst():
    f = np.array([[1.0, 5.0], [3.0, -1.0], [2.0, 2.0]])
    assert Terrains(Debris(), 3).combine(f).tolist() == [2.0, 2.0]
    assert Terrains(Debris(), 3, "min").combine(f).tolist() == [1.0, -1.0]
    one = np.array([[4.0, -2.0]])
    for t in (Terrains(), Terrains(Flat(), 1, "min")):  # one terrain: its own
        assert t.combine(one).tolist() == [4.0, -2.0]
        assert np.shares_memory(t.combine(one), one)


def test_terrains_refused_are_named():
    with pytest.raises(SettingTypeError, match=exactly(
        "scene must be a Scene (flat, debris, ...), got 'flat'"
    )):  # fmt: skip
        Terrains("flat")
    with pytest.raises(SettingValueError, match=exactly(
        "aggregate must be one of mean, min, got 'max'"
    )):  # fmt: skip
        Terrains(Debris(), 2, "max")
    with pytest.raises(SettingValueError, match=exactly(
        "terrains must be 1 (the flat scene has one terrain), got 2"
    )):  # fmt: skip
        Terrains(Flat(), 2)
    with pytest.raises(SettingValueError, match=exactly(
        "terrains must be an integer in [1, 64], got 65"
    )):  # fmt: skip
        Terrains(Debris(), 65)
    assert Terrains(Debris(), 64).count == 64
    with pytest.raises(SettingValueError, match=exactly(
        "terrains must be at most 1 from seed 9223372036854775807 (terrain seeds "
        "are at most 2**63-1), got 2"
    )):  # fmt: skip
        Terrains(Debris(seed=INT64_MAX), 2)
    with pytest.raises(SettingValueError, match="^terrains must be at most 3 from"):
        Terrains(Debris(seed=INT64_MAX - 2), 4)


def test_scenes_by_name():
    assert sc.DEFAULT_SCENE == "flat"
    assert {"flat", "debris"} <= set(sc.scene_names())
    assert sc.scene_class("flat") is Flat and sc.scene_class("debris") is Debris
    with pytest.raises(ValueError) as e:
        sc.scene_class("moon")
    assert str(e.value).startswith("unknown scene 'moon'; choose from flat, debris")


def test_a_scene_registers_by_its_name(monkeypatch):
    monkeypatch.setattr(sc, "_REGISTRY", dict(sc._REGISTRY))

    @dataclass(frozen=True)
    class Moon(Flat):
        name: ClassVar[str] = "moon"

    assert sc.register_scene(Moon) is Moon and sc.scene_class("moon") is Moon
    assert sc.scene_names()[-1] == "moon"

    class Nameless:
        name = 3

    with pytest.raises(TypeError, match=exactly("Nameless must set a str 'name'")):
        sc.register_scene(Nameless)
    assert "3" not in sc._REGISTRY and 3 not in sc._REGISTRY


def test_the_plugins_scenes_are_looked_for_when_a_name_is_not_known(monkeypatch):
    calls = []
    monkeypatch.setattr(sc.plugins, "load", lambda *a: calls.append(a))
    sc.scene_class("flat")
    assert calls == []  # a known name: no plugin is imported
    sc.scene_names()
    assert calls == [(sc.plugins.SCENES, sc.register_scene)]
    with pytest.raises(ValueError):
        sc.scene_class("moon")
    assert calls[1:] == [(sc.plugins.SCENES, sc.register_scene)]


def test_the_floor_is_a_checkered_plane_that_collides_through_its_pairs():
    p = LocustParams()
    m = mujoco.MjModel.from_xml_string(to_mjcf(p, scene=Flat(), keyframe=False))
    floor = m.geom(names.FLOOR)
    assert floor.type[0] == mujoco.mjtGeom.mjGEOM_PLANE
    assert (floor.contype[0], floor.conaffinity[0]) == (0, 0)
    assert floor.size[2] == pytest.approx(0.05 * p.body_length)
    grid = m.material("grid")
    assert floor.matid[0] == grid.id
    assert grid.texuniform[0] and grid.reflectance[0] == 0
    assert grid.texrepeat.tolist() == [1, 1]
    tex = m.texture("grid")
    assert grid.texid[mujoco.mjtTextureRole.mjTEXROLE_RGB] == tex.id
    assert (tex.type[0], tex.width[0], tex.height[0]) == (0, 512, 512)  # 2-D
    pixels = tex.data.reshape(-1, 3)
    colours, counts = np.unique(pixels, axis=0, return_counts=True)
    assert colours.tolist() == [[76, 76, 76], [158, 163, 153], [209, 209, 198]]
    assert counts[1] == counts[2] and counts[0] == 4 * 511  # edges: one pixel
