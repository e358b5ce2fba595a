"""The creature apart from its world: a scene's geoms meet every creature geom
in contact pairs, and a new scene changes nothing of the creature."""

from dataclasses import dataclass
from typing import ClassVar

import mujoco
import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.creature import CONTACT_GEOMS
from locustjump.sim.scene import (
    DEFAULT_SCENE,
    Flat,
    Scene,
    SceneMJCF,
    register_scene,
    scene_class,
    scene_names,
)


@dataclass(frozen=True)
class Step(Scene):
    """The flat floor and one box-shaped step ahead of the creature."""

    name: ClassVar[str] = "step"
    height: float = 0.1  # (body lengths)

    def mjcf(self, body_length: float) -> SceneMJCF:
        floor = Flat().mjcf(body_length)
        h = self.height * body_length / 2
        box = f'<geom name="step" type="box" pos="{2 * body_length} 0 {h}" '
        box += f'size="{body_length / 2} {body_length} {h}"/>'
        return SceneMJCF(
            assets=floor.assets,
            worldbody=floor.worldbody + box,
            geoms=(*floor.geoms, "step"),
        )


def _sorted(m: mujoco.MjModel, pairs: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """``pairs`` in MuJoCo's order: stably sorted by (body, body)."""
    return sorted(pairs, key=lambda gc: [m.geom_bodyid[m.geom(g).id] for g in gc])


def _pairs(m: mujoco.MjModel) -> list[tuple[str, str]]:
    return [
        (m.geom(int(a)).name, m.geom(int(b)).name)
        for a, b in zip(m.pair_geom1, m.pair_geom2, strict=True)
    ]


@pytest.mark.parametrize("stiffness", [0.0, 1e-5])
def test_every_creature_geom_meets_the_floor_in_order(stiffness):
    p = lm.LocustParams(strut_stiffness=stiffness)
    m = lm.load_model(p)
    creature = {m.geom(g).name for g in range(m.ngeom) if m.geom_bodyid[g] != 0}
    assert set(CONTACT_GEOMS) == creature and len(CONTACT_GEOMS) == len(creature)
    assert _pairs(m) == _sorted(m, [(names.FLOOR, c) for c in CONTACT_GEOMS])
    if stiffness == 0:  # one creature body holds the struts: the written order
        assert _pairs(m) == [(names.FLOOR, c) for c in CONTACT_GEOMS]
    assert (m.geom_contype == 0).all() and (m.geom_conaffinity == 0).all()


def test_a_scene_with_more_geoms_pairs_each_with_the_creature():
    p = lm.LocustParams()
    flat = lm.load_model(p)
    m = mujoco.MjModel.from_xml_string(lm.to_mjcf(p, scene=Step(), keyframe=False))
    written = lm.contact_pairs(("floor", "step"))
    assert written == [(g, c) for g in ("floor", "step") for c in CONTACT_GEOMS]
    assert _pairs(m) == _sorted(m, written)
    # the pairs carry the creature's contact model, as with the floor
    np.testing.assert_array_equal(m.pair_friction[-1], flat.pair_friction[0])
    np.testing.assert_array_equal(m.pair_solref[-1], flat.pair_solref[0])
    # the creature is the same creature
    np.testing.assert_array_equal(m.body_mass, flat.body_mass)
    np.testing.assert_array_equal(m.body_inertia, flat.body_inertia)
    assert m.nu == flat.nu and m.nsensor == flat.nsensor and m.nq == flat.nq


def test_the_creature_lands_on_a_scene_geom():
    """The step's pairs are live: dropped on the step, the creature rests on it."""
    p = lm.LocustParams()
    m = lm.load_model(p, Step())
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(lm.READY_KEY).id)
    bl = p.body_length
    d.qpos[:3] += (2 * bl, 0.0, 0.1 * bl)  # above the step, its height up
    mujoco.mj_step(m, d, nstep=round(1.0 / m.opt.timestep))
    assert abs(d.qpos[2] - (lm.standing_height(p) + 0.1 * bl)) < 0.05 * bl
    step = m.geom("step").id
    assert any(step in (c.geom1, c.geom2) for c in d.contact[: d.ncon])


def test_load_model_caches_per_scene():
    p = lm.LocustParams()
    assert lm.load_model(p, Step()).npair == 2 * lm.load_model(p).npair
    assert lm.load_model(p, Step(height=0.2)).geom("step").size[2] == pytest.approx(
        0.1 * p.body_length
    )


def test_scene_registry():
    assert DEFAULT_SCENE == "flat" and "flat" in scene_names()
    assert scene_class("flat") is Flat
    with pytest.raises(ValueError, match="unknown scene 'moon'; choose from flat"):
        scene_class("moon")

    class Nameless(Flat):
        name = None

    with pytest.raises(TypeError, match="Nameless must set"):
        register_scene(Nameless)
    with pytest.raises(TypeError):
        Scene()  # abstract: a scene writes its MJCF


def test_terrains_from_seed_1_are_terrains():
    """A seeded scene whose seed is 1 has terrains like any other (it was
    taken for a seedless one: `Debris(seed=1).with_seed(1)` is itself, so
    `train --scene debris --terrain-seed 1 --terrains 4` was refused); a
    seedless scene that is not flat has none to hold out."""
    from locustjump.present.episodes import _scenes
    from locustjump.sim.scene import Debris, Terrains
    from locustjump.tasks import get_behaviour

    t = Terrains(Debris(seed=1), count=4)
    assert [s.seed for s in t.scenes] == [1, 2, 3, 4]
    assert Debris(seed=1).seeded and not Flat().seeded and not Step().seeded
    beh = get_behaviour("kick", terrains=Terrains(Debris(seed=1)))
    assert [s.seed for s in _scenes(beh, [1, 7], None)] == [1, 7]
    with pytest.raises(ValueError, match=r"^terrains must be 1 \(the step scene has"):
        Terrains(Step(), count=2)
