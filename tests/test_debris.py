"""The debris scene: seeded terrains and their walls, the ground under the
body, the physics gates on rubble, the debris fitness and its figures
(training and testing on terrains: test_debris_runs.py)."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from locustjump import rundir
from locustjump.rundir.config import TrainConfig
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.analysis import (
    clearance,
    find_jumps,
    ground_profile,
    stuck_overturned,
)
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.sim.scene import MAX_BOXES, Debris, Flat, Terrains
from locustjump.tasks import get_behaviour
from locustjump.tasks.composed import PROGRESS_WEIGHT, successive_fitness
from locustjump.tasks.reference import rules_outcome, run_rules
from locustjump.tasks.rules import RuleController
from locustjump.tasks.starts import ready_state

P = lm.LocustParams()
BL = P.body_length


def test_a_terrain_is_its_seed():
    a, b = Debris(seed=1).boxes(BL), Debris(seed=1).boxes(BL)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, Debris(seed=2).boxes(BL))
    assert Debris(seed=1).with_seed(5) == Debris(seed=5)
    assert Flat().with_seed(5) == Flat()


def test_heights_are_the_box_tops_and_the_clearing_is_free():
    d = Debris(seed=4)
    boxes = d.boxes(BL)
    assert len(boxes) > 50
    top = d.heights(boxes[:, 0], boxes[:, 1], BL)
    # at a box's centre the ground is at least that box's top (boxes overlap)
    assert (top >= boxes[:, 5] - 1e-12).all()
    r = np.linspace(0, d.clearing * BL * 0.99, 30)
    assert (d.heights(r, 0 * r, BL) == 0).all() and (d.heights(0 * r, r, BL) == 0).all()
    far = d.heights(np.array([-50.0, 200.0]), np.array([0.0, 0.0]), BL)
    assert (far == 0).all()
    assert Flat().heights(np.ones(3), np.ones(3), BL).tolist() == [0, 0, 0]


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"spacing": 0.0}, "spacing"),
        ({"height_max": 0.01}, "height_max"),
        ({"friction": 0.0}, "friction"),
        ({"seed": -1}, "seed"),
        ({"spacing": 0.02}, f"at most {MAX_BOXES:,}"),
        ({"length": 1000, "width": 1000, "spacing": 100}, "too large"),
        ({"wall_height": -1}, "wall_height"),
    ],
)
def test_bad_debris_parameters_are_named(change, message):
    with pytest.raises(ValueError, match=message):
        Debris(**change)


def test_the_boxes_collide_with_the_creature_only():
    m = lm.load_model(P, Debris())
    boxes = [i for i in range(m.ngeom) if m.geom(i).name.startswith("debris")]
    creature = m.geom_bodyid != 0
    assert len(boxes) == len(Debris().boxes(BL))
    assert (m.geom_contype[boxes] == 0).all() and (m.geom_conaffinity[boxes] == 1).all()
    assert (m.geom_contype[creature] == 1).all()
    assert (m.geom_conaffinity[creature] == 0).all()  # never with each other
    flat = lm.load_model(P)
    assert (flat.geom_contype == 0).all()  # the floor's model is as before
    assert m.npair == flat.npair


def _world_tree(m: mujoco.MjModel) -> tuple[np.ndarray, ...]:
    rows = slice(m.body_bvhadr[0], m.body_bvhadr[0] + m.body_bvhnum[0])
    return m.bvh_child[rows], m.bvh_nodeid[rows], m.bvh_aabb[rows]


def _as_compiled(scene: Debris) -> mujoco.MjModel:
    """The debris model as MuJoCo compiles its MJCF, and without sleeping: the
    world body's tree is the compiler's, its static geoms' poses are computed
    at every step (the engine's model before issue #45)."""
    xml = lm.to_mjcf(P, scene=scene).replace('<flag sleep="enable"/>', "")
    m = mujoco.MjModel.from_xml_string(xml)
    assert not m.opt.enableflags & mujoco.mjtEnableBit.mjENBL_SLEEP
    return m


def test_the_world_tree_holds_the_compilers_leaves():
    """The engine's debris model walks a rebuilt bounding volume hierarchy
    (sim/bvh.py, docs/performance.md): the compiler's leaves with their very
    boxes, every node holding its children's, and no floor plane among them,
    so that no node is larger than the walled field; the flat floor has none."""
    scene = Debris(seed=3)
    built = _as_compiled(scene)
    m = lm.load_model(P, scene)
    assert m.geom_contype[m.geom(names.FLOOR).id] == 0  # its pairs only
    child, node, box = _world_tree(m)
    _, node0, box0 = _world_tree(built)
    leaves = node >= 0
    assert sorted(node[leaves]) == sorted(node0[node0 >= 0])
    assert m.geom(names.FLOOR).id not in node[leaves]
    assert len(node[leaves]) == len(scene.boxes(BL)) + 4
    for i in np.flatnonzero(leaves):
        np.testing.assert_array_equal(box[i], box0[node0 == node[i]][0])
    for i in np.flatnonzero(~leaves):
        for c in child[i]:
            assert c > i  # pre-order, as the compiler writes it
            assert (box[i, 3:] - np.abs(box[c, :3] - box[i, :3]) >= box[c, 3:]).all()
    field = np.array([scene.behind + scene.length + 2, scene.width + 2]) * BL / 2
    assert (box[0, 3:5] <= field * (1 + 1e-12)).all()
    assert lm.load_model(P).body_bvhnum[0] == 0


def test_the_rebuilt_tree_finds_the_compilers_contacts():
    """Thrown at the walls and dropped on the rubble with random servo
    targets, the creature meets the same contacts, in the same order, at every
    physics step with the rebuilt tree and the world asleep as with the
    compiler's tree and every geom's pose computed, and moves the same, bit
    for bit. The world's static geoms sleep; the creature never does."""
    scene = Debris(seed=3)
    models = [_as_compiled(scene), lm.load_model(P, scene)]
    start = ready_state(P, scene)
    box = scene.boxes(BL)[np.argmin(np.hypot(*scene.boxes(BL)[:, :2].T))]
    rng = np.random.default_rng(0)
    lo, hi = models[1].actuator_ctrlrange.T
    kind = [models[0].geom(g).name.rstrip("0123456789") for g in range(models[0].ngeom)]
    met = set()
    for pos, vel in (((0, 0, 0), (0, 6, 2)), ((0, 0, 0), (-6, 0, 2)),
                     ((box[0], box[1], box[5] + 0.2 * BL), (0, 0, 0))):  # fmt: skip
        ds = [mujoco.MjData(m) for m in models]
        for d in ds:
            d.qpos[:], d.ctrl[:] = start.qpos[0], start.ctrl[0]
            d.qpos[:3] += pos
            d.qvel[:3] = vel
        for _ in range(300):
            ctrl = np.clip(ds[0].ctrl + rng.uniform(-0.2, 0.2, 4), lo, hi)
            for _ in range(P.substeps):
                for m, d in zip(models, ds, strict=True):
                    d.ctrl[:] = ctrl
                    mujoco.mj_step(m, d)
                a, b = (d.contact for d in ds)
                for field in ("geom", "dist", "pos", "frame", "dim", "solref"):
                    np.testing.assert_array_equal(getattr(a, field), getattr(b, field))
                np.testing.assert_array_equal(ds[0].qpos, ds[1].qpos)
                met |= {kind[g] for g in a.geom.flat}
    assert {names.FLOOR, names.DEBRIS, names.WALL} <= met
    sleep = mujoco.mjtEnableBit.mjENBL_SLEEP
    assert models[1].opt.enableflags & sleep
    never = mujoco.mjtSleepPolicy.mjSLEEP_NEVER
    assert (models[1].tree_sleep_policy == never).all()
    assert not lm.load_model(P).opt.enableflags & sleep  # the flat floor: as before


def test_walls_close_the_field_and_are_not_ground():
    m = lm.load_model(P, Debris())
    walls = [i for i in range(m.ngeom) if m.geom(i).name.startswith(names.WALL)]
    assert len(walls) == 4
    assert (m.geom_contype[walls] == 0).all() and (m.geom_conaffinity[walls] == 1).all()
    assert np.allclose(m.geom_size[walls, 2], Debris().wall_height * BL / 2)
    # frictionless, and that is theirs: no leg can climb them
    assert (m.geom_condim[walls] == 1).all()
    assert m.geom_priority[walls].min() > m.geom_priority[m.geom_bodyid != 0].max()
    # their inner faces are the field's edges: left, right, back, front
    w = Debris().walls(BL)
    inner = [w[0, 1] - w[0, 3] / 2, w[1, 1] + w[1, 3] / 2,
             w[2, 0] + w[2, 2] / 2, w[3, 0] - w[3, 2] / 2]  # fmt: skip
    d = Debris()
    assert np.allclose(
        inner, np.array([d.width / 2, -d.width / 2, -d.behind, d.length]) * BL
    )
    open_field = Debris(wall_height=0)
    assert open_field.walls(BL).shape == (0, 4)
    assert names.WALL not in open_field.mjcf(BL).worldbody
    x, y = np.meshgrid(np.linspace(-2, 14, 200), np.linspace(-2, 2, 80))
    np.testing.assert_array_equal(d.heights(x, y, BL), open_field.heights(x, y, BL))


@pytest.mark.parametrize("substeps", [3, 12])
def test_the_walls_stop_a_creature_thrown_at_them(substeps):
    """Thrown sideways at 6 m/s, or backwards, the creature bounces off the
    walls: its body centre stays inside the field, nothing blows up or sinks
    in deeper than the gates allow; the walls push along their normal only.
    The walls of every shipped run (no margin; with one: test_walls.py)."""
    p = P.replace(substeps=substeps)
    scene = Debris(seed=2, wall_margin=0)
    for vx, vy in ((0.0, 6.0), (0.0, -6.0), (-6.0, 0.0)):
        s = ready_state(p, scene)
        with pytest.raises(ValueError, match="read-only"):  # cached and shared
            s.qvel[0, 0] = 1.0
        start = StartStates(s.qpos.copy(), s.qvel.copy(), s.ctrl.copy())
        start.qvel[0, :3] = (vx, vy, 2.0)
        ctrl = np.repeat(start.ctrl, 400, axis=0)
        pen, d = _replay_penetration(p, scene, ctrl, start)
        lo, hi = -scene.behind * BL, scene.width / 2 * BL
        assert lo < d.qpos[0] and abs(d.qpos[1]) < hi, (vx, vy, d.qpos[:3])
        gap = hi - abs(d.qpos[1]) if vy else d.qpos[0] - lo
        assert gap < BL  # it got there: it lies against the wall
        assert np.isfinite(d.qpos).all() and d.warning.number.sum() == 0
        assert pen < 0.05 * BL
    m = lm.load_model(p, scene)
    d = mujoco.MjData(m)
    d.qpos[:], d.ctrl[:] = start.qpos[0], start.ctrl[0]
    d.qvel[:3] = (0.0, 6.0, 2.0)
    dims = []
    for _ in range(400 * substeps):
        mujoco.mj_step(m, d)
        pairs = [(c.dim, m.geom(c.geom1).name + m.geom(c.geom2).name)
                 for c in d.contact[: d.ncon]]  # fmt: skip
        dims += [int(dim) for dim, pair in pairs if names.WALL in pair]
    assert dims and set(dims) == {1}


def test_debris_configs_written_before_the_walls_read_as_an_open_field():
    """A shipped run's [scene] (every parameter but wall_height) has no walls
    and keeps its hash; a partial table gets today's walls."""
    path = rundir.SHIPPED / "debris-open" / "long-seed0" / "monolithic"
    cfg = rundir.load_config(path / rundir.CONFIG)
    assert cfg.scene.scene.wall_height == 0
    assert cfg.hash() == "d45a286a71b68113"  # as before the walls existed
    partial = TrainConfig.from_dict({"scene": {"kind": "debris", "seed": 3}}, "x")
    assert partial.scene.scene.wall_height == Debris().wall_height > 0
    walled = cfg.replace(scene=Terrains(Debris(), 2))
    assert walled.hash() != cfg.replace(scene=Terrains(Debris(wall_height=0), 2)).hash()


def test_start_states_are_upright_and_at_rest_on_the_terrain():
    for seed in range(3):
        s = ready_state(P, Debris(seed=seed))
        m = lm.load_model(P, Debris(seed=seed))
        d = mujoco.MjData(m)
        d.qpos[:], d.qvel[:] = s.qpos[0], s.qvel[0]
        mujoco.mj_forward(m, d)
        assert d.xmat[1].reshape(3, 3)[2, 2] > 0.95  # upright
        assert np.abs(d.qvel).max() < 1e-2
    np.testing.assert_array_equal(
        ready_state(P).qpos, StartStates.ready(lm.load_model(P)).qpos
    )


def test_the_composed_start_touches_only_the_floor_on_every_terrain():
    """Fig. 11's start (on its side, settled on the floor) lies in the clearing
    of every training and held-out terrain the study uses, touching no box."""
    beh = get_behaviour("monolithic", None)
    for seed in (*range(5), *range(100, 120)):
        m = lm.load_model(P, Debris(seed=seed))
        d = mujoco.MjData(m)
        start = beh.on(Debris(seed=seed)).start_states(P)
        d.qpos[:], d.qvel[:] = start.qpos[0], start.qvel[0]
        mujoco.mj_forward(m, d)
        floor = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_GEOM, names.FLOOR)
        touched = {int(g) for c in d.contact[: d.ncon] for g in (c.geom1, c.geom2)}
        assert d.ncon and floor in touched, seed
        boxes = [g for g in touched if m.geom(g).name.startswith(names.DEBRIS)]
        assert boxes == [], seed


def _replay_penetration(p: lm.LocustParams, scene: Debris, ctrl: np.ndarray, start):
    """Replay recorded servo targets open loop; the deepest contact (m), the
    final state and MuJoCo's warnings."""
    m = lm.load_model(p, scene)
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:], d.ctrl[:] = start.qpos[0], start.qvel[0], start.ctrl[0]
    pen = 0.0
    for c in ctrl[1:]:
        d.ctrl[:] = c
        for _ in range(p.substeps):
            mujoco.mj_step(m, d)
            if d.ncon:
                pen = max(pen, float(-d.contact.dist[: d.ncon].min()))
    return pen, d


@pytest.mark.parametrize("substeps", [3, pytest.param(12, marks=pytest.mark.slow)])
def test_gates_hold_on_debris(substeps):
    """Rule-based and random controllers on rubble, at the model's 3 substeps and
    at 12: no blow-up, finite states, contacts shallower than 5 % of a body
    length (the flat floor's gate 5)."""
    p = P.replace(substeps=substeps)
    rc = RuleController.for_model(p)
    worst = 0.0
    for seed in range(3):
        scene = Debris(seed=seed)
        start = ready_state(p, scene)
        res = rollout(
            rc, rc.params_for(np.array([0.2, 0.5, 0.9])), start, 1200,
            model_params=p, record=("qpos", "ctrl"), scene=scene,
        )  # fmt: skip
        assert not res.unstable.any() and np.isfinite(res["qpos"]).all()
        pen, d = _replay_penetration(p, scene, res["ctrl"][1], start)
        np.testing.assert_allclose(d.qpos, res["qpos"][1, -1], atol=1e-9)
        assert d.warning.number.sum() == 0
        worst = max(worst, pen)
    assert worst < 0.05 * BL


def test_rules_on_debris_overturn_for_good_and_report_it():
    """The paper's motivation: on rubble the rules overturn and cannot get up."""
    stuck = []
    for seed in range(4):
        r = run_rules(steps=3000, model_params=P, scene=Debris(seed=seed))
        out = rules_outcome(r, P)
        assert out["jumps_before_stuck"] <= out["jumps"]
        stuck.append(out["stuck_overturned_s"] is not None)
    assert sum(stuck) >= 2
    flat = rules_outcome(run_rules(steps=3000, model_params=P), P)
    assert flat["jumps"] == 11 and flat["jumps_before_stuck"] == 11


def test_stuck_overturned_ignores_somersaults():
    uz = np.ones(400)
    uz[50:90] = -1.0  # a somersault in flight: 1/3 s
    assert stuck_overturned(uz) is None
    uz[200:] = -0.5
    assert stuck_overturned(uz) == 200


def test_height_is_measured_above_the_ground_under_the_body():
    """Standing on a box earns no more than standing on the floor."""
    scene = Debris(seed=0)
    x, y, _, _, _, h = scene.boxes(BL)[0]
    stand = 0.07
    qpos = np.zeros((2, 5, 7))
    qpos[0, :, :3] = [x, y, h + stand]  # on the box
    qpos[1, :, :3] = [0.0, 0.0, stand]  # in the clearing
    c = clearance(qpos, P, scene)
    np.testing.assert_allclose(c, stand, atol=1e-12)
    np.testing.assert_array_equal(clearance(qpos, P, Flat()), qpos[..., 2])
    flat_jumps = find_jumps(qpos[0], P)  # on the flat floor the box top is a jump
    assert find_jumps(qpos[0], P, scene) == [] and len(flat_jumps) == 1


def test_the_debris_fitness_rewards_going_across_it():
    """On a terrain E adds 200 control steps per metre of forward progress
    (hopping in place by the start scored as well as crossing the rubble);
    on the flat floor it is Eq. 4 alone."""
    scene = Debris(seed=0)
    qpos = np.zeros((2, 31, 7))
    qpos[:, :, 2] = 0.3
    qpos[0, :, 0] = np.linspace(0.0, 2.0, 31)  # 2 m forward
    qpos[1, :, 0] = np.linspace(0.0, -0.5, 31)  # 0.5 m back
    above = clearance(qpos, P, scene)[:, 1:].sum(axis=1)
    progress = PROGRESS_WEIGHT * np.array([2.0, -0.5])
    np.testing.assert_allclose(successive_fitness(qpos, P, scene), above + progress)
    assert PROGRESS_WEIGHT == 200.0
    eq4 = qpos[:, 1:, 2].sum(axis=1)
    np.testing.assert_array_equal(successive_fitness(qpos, P, Flat()), eq4)


def test_the_figures_draw_the_ground_under_the_path():
    """The trajectory figure's profile is the terrain's height along the
    path, from behind its start to beyond its end; none on the flat floor."""
    scene = Debris(seed=0)
    boxes = scene.boxes(BL)
    x0, y0 = boxes[0, :2]
    qpos = np.zeros((50, 7))  # a path across box 0, along its y
    qpos[:, 0] = np.linspace(x0 - 1.0, x0 + 1.0, 50)
    qpos[:, 1] = y0
    x, h = ground_profile(qpos, P, scene)
    assert x[0] == pytest.approx(x0 - 1.0 - BL / 2) and x[-1] == pytest.approx(
        x0 + 1.0 + BL / 2
    )
    np.testing.assert_array_equal(h, scene.heights(x, np.full_like(x, y0), BL))
    assert h.max() >= boxes[0, 5] - 1e-9  # the box is under the path
    assert ground_profile(qpos, P, Flat()) is None
