"""Walls that hold (docs/physics.md): the debris field's ``wall_margin``.

MuJoCo has no continuous collision detection, so a limb at 15-22 m/s moves
4-6 cm in one 2.78 ms substep and is found that deep inside a wall; the
walls' contact margin makes them push from ``wall_margin`` before their face
on. What the margin must keep: the field's geometry, every shipped run's
config hash and physics (they read margin 0). What it must give: no wall face
entered deeper than the 5 % body-length gate, by a thrown creature or by the
trained controllers that entered them up to 8.4 % without it
(results/debris/contact-audit.md)."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

from locustjump import rundir
from locustjump.present.episodes import deepest_contact
from locustjump.rundir.config import TrainConfig, scene_table
from locustjump.rundir.migrations import scene_before
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks.starts import ready_state

P = lm.LocustParams()
BL = P.body_length
#: the penetration gate of tests/test_debris.py (body lengths)
GATE_BL = 0.05


def test_new_fields_have_a_wall_margin_and_open_ones_none():
    assert Debris().wall_margin == 0.1
    # no walls, no margin: an open field is one scene however it is spelt
    assert Debris(wall_height=0).wall_margin == 0
    assert Debris(wall_height=0) == Debris(wall_height=0, wall_margin=0)


@pytest.mark.parametrize(
    ("bad", "kind"),
    [(-0.01, ValueError), (0.5, ValueError), (2.0, ValueError),
     (float("nan"), ValueError), (float("inf"), ValueError), ("x", TypeError)],
)  # fmt: skip
def test_a_bad_wall_margin_is_named(bad, kind):
    with pytest.raises(kind, match=r"^wall_margin must be (a number )?in \[0, 0.5\)"):
        Debris(wall_margin=bad)


def test_the_margin_is_on_the_walls_only_and_moves_nothing():
    """The wall geoms get the margin (gap 0: they push from it on), nothing
    else does; the walls, the boxes and the ground under the body are where
    they were, and a margin-0 field writes the MJCF it always did."""
    with_margin, without = Debris(), Debris(wall_margin=0)
    m = lm.load_model(P, with_margin)
    walls = np.array([m.geom(i).name.startswith(names.WALL) for i in range(m.ngeom)])
    assert walls.sum() == 4
    np.testing.assert_allclose(m.geom_margin[walls], with_margin.wall_margin * BL)
    assert (m.geom_gap == 0).all() and (m.geom_margin[~walls] == 0).all()
    assert (lm.load_model(P, without).geom_margin == 0).all()
    np.testing.assert_array_equal(with_margin.walls(BL), without.walls(BL))
    np.testing.assert_array_equal(with_margin.boxes(BL), without.boxes(BL))
    x, y = np.meshgrid(np.linspace(-2, 14, 200), np.linspace(-2, 2, 80))
    np.testing.assert_array_equal(
        with_margin.heights(x, y, BL), without.heights(x, y, BL)
    )
    assert "margin" not in without.mjcf(BL).worldbody
    assert without.mjcf(BL).worldbody == with_margin.mjcf(BL).worldbody.replace(
        f' margin="{with_margin.wall_margin * BL:.9g}" gap="0"', ""
    )


def _thrown(p: lm.LocustParams, scene: Debris, velocity, steps: int = 400):
    """The creature thrown from its start with body velocity ``velocity``
    (m/s), servos held: the smallest signed distance (m) of any wall contact
    to the wall's face (negative: into it; +inf: none) and the final data."""
    m = lm.load_model(p, scene)
    d = mujoco.MjData(m)
    s = ready_state(p, scene)
    d.qpos[:], d.qvel[:], d.ctrl[:] = s.qpos[0], s.qvel[0], s.ctrl[0]
    d.qvel[:3] = velocity
    wall = np.array([m.geom(i).name.startswith(names.WALL) for i in range(m.ngeom)])
    closest = np.inf
    for _ in range(steps * p.substeps):
        mujoco.mj_step(m, d)
        n = d.ncon
        on = wall[d.contact.geom1[:n]] | wall[d.contact.geom2[:n]]
        if on.any():  # MuJoCo's dist is to the face, whatever the margin
            closest = min(closest, float(d.contact.dist[:n][on].min()))
    return closest, d


@pytest.mark.parametrize("substeps", [3, 12])
@pytest.mark.parametrize("speed", [6.0, 15.0])
def test_walls_with_a_margin_hold_a_creature_thrown_at_them(substeps, speed):
    """Thrown sideways or backwards at 6 or 15 m/s, the creature reaches the
    wall (a contact inside its margin) but no wall face is entered deeper than
    the gate; its body centre stays inside the field, nothing blows up."""
    p = P.replace(substeps=substeps)
    scene = Debris(seed=2)
    margin = scene.wall_margin * BL
    lo, hi = -scene.behind * BL, scene.width / 2 * BL
    for direction in ((0, 1), (0, -1), (-1, 0)):
        velocity = (speed * direction[0], speed * direction[1], 2.0)
        closest, d = _thrown(p, scene, velocity)
        assert closest < margin, (direction, closest)  # it met the wall
        assert -closest < GATE_BL * BL, (direction, closest)
        assert lo < d.qpos[0] and abs(d.qpos[1]) < hi, (direction, d.qpos[:3])
        assert np.isfinite(d.qpos).all() and d.warning.number.sum() == 0


def test_shipped_walled_runs_read_no_margin_and_keep_their_hash():
    """A walled field's [scene] written before the margin (every parameter
    but wall_margin) reads as margin 0, an open field's (neither wall_height
    nor wall_margin) as no walls; both keep their config hash (the margin is
    hashed only when not 0). A partial table gets today's margin."""
    walled = rundir.SHIPPED / "debris" / "long-seed0" / "monolithic"
    cfg = rundir.load_config(walled / rundir.CONFIG)
    assert cfg.scene.scene.wall_height == Debris().wall_height
    assert cfg.scene.scene.wall_margin == 0
    assert cfg.hash() == "8f47cad31c960d00"  # as before the margin existed
    assert "wall_margin" not in (walled / rundir.CONFIG).read_text()
    open_field = rundir.SHIPPED / "debris-open" / "long-seed0" / "monolithic"
    cfg_open = rundir.load_config(open_field / rundir.CONFIG)
    assert cfg_open.scene.scene == Debris(wall_height=0)
    assert cfg_open.hash() == "d45a286a71b68113"
    # with the margin, the same run is another experiment
    margin = cfg.replace(scene=Terrains(Debris(), cfg.scene.count))
    assert margin.scene.scene.wall_margin == 0.1 and margin.hash() != cfg.hash()
    partial = TrainConfig.from_dict({"scene": {"kind": "debris", "seed": 3}}, "x")
    assert partial.scene.scene.wall_margin == Debris().wall_margin


def test_only_tables_written_before_the_margin_read_as_without_one():
    """The later fields are filled in only as locustjump left them out: the
    last ones added (wall_margin; wall_height and wall_margin). A table that
    names the margin but not the height was written by a person: defaults."""
    full = scene_table(Terrains(Debris(wall_height=5.0, wall_margin=0.2)))
    fields = [f.name for f in dataclasses.fields(Debris)]
    table = {k: v for k, v in full.items() if k in fields}

    def read(*drop):
        t = {k: v for k, v in table.items() if k not in drop}
        return scene_before("debris", t, fields)

    assert read() == table
    assert read("wall_margin")["wall_margin"] == 0.0
    assert read("wall_margin")["wall_height"] == 5.0
    both = read("wall_height", "wall_margin")
    assert both["wall_height"] == both["wall_margin"] == 0.0
    assert "wall_height" not in read("wall_height")  # today's default
    assert "wall_margin" not in read("seed", "wall_margin")


#: (shipped run, held-out terrain): the two deepest entries into a wall of
#: results/debris/contact-audit.md (8.4 % and 7.2 % of a body length)
TRAINED = [
    ("long-seed3/monolithic", 101, 0.0419),
    ("long-seed4/composed", 111, 0.0359),
]


@pytest.mark.parametrize(("run", "terrain", "without"), TRAINED)
def test_walls_with_a_margin_hold_trained_controllers(run, terrain, without):
    """A shipped trained controller's best genome, re-simulated in its own
    scene on the terrain where it went deepest into a wall: without a margin
    (as it trained) past the gate, with today's margin (its trajectory
    changes) no wall face entered deeper than the gate."""
    path = rundir.SHIPPED / "debris" / run
    scene = rundir.load_config(path / rundir.CONFIG).scene.scene
    assert scene.wall_margin == 0
    before = deepest_contact(path, terrain=terrain, among=names.WALL)
    assert before.depth_m == pytest.approx(without, abs=5e-5)
    assert before.depth_m > GATE_BL * BL
    held = dataclasses.replace(scene, wall_margin=Debris().wall_margin)
    after = deepest_contact(path, terrain=terrain, scene=held, among=names.WALL)
    assert after is not None  # it still reaches a wall (inside the margin)
    assert after.depth_m < GATE_BL * BL, after
