"""Per-episode diagnostics (present.episodes, issue #44): the behaviour's own
fitness split into its terms, wall contact and the deepest penetration."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from locustjump import rundir
from locustjump.present.episodes import deepest_contact, episode_score, score_run
from locustjump.present.evaluate import evaluate_terrains
from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine.job import CONTACT_RECORDS
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.sim.scene import Debris
from locustjump.tasks import get_behaviour
from locustjump.tasks.rules import DEFAULT_CHANGE_TIME, RuleController
from locustjump.tasks.starts import ready_state

P = lm.LocustParams()
BL = P.body_length
DEBRIS_RUN = rundir.SHIPPED / "debris" / "long-seed0" / "monolithic"
FLAT_RUN = rundir.SHIPPED / "quick-seed0" / "monolithic"
RECORD = ("qpos", "obs", *CONTACT_RECORDS)


@pytest.fixture(scope="module")
def debris_run():
    if not (DEBRIS_RUN / rundir.BEST).is_file():
        pytest.skip(f"{DEBRIS_RUN} not present")
    return DEBRIS_RUN


def test_the_fitness_is_the_behaviours_and_its_terms_add_up(debris_run):
    """On held-out terrains: exactly what Behaviour.evaluate and `evaluate
    --terrain-seeds` give, height + distance to the last bit; on the run's own
    terrains, their mean is the recorded training fitness."""
    scores = score_run(debris_run, terrain_seeds=[100, 101])
    assert [s.terrain for s in scores] == [100, 101]
    cfg, beh, best = rundir.load_run(debris_run)
    for s in scores:
        # the run's own field (its walls have no margin, today's Debris() has)
        fit, _ = beh.on(beh.terrains.scene.with_seed(s.terrain)).evaluate(
            best.genome[None], cfg.model, engine=cfg.engine
        )
        assert s.fitness == fit[0]
        assert s.height_term + s.distance_term == s.fitness
        assert s.distance_term == pytest.approx(200 * s.distance_m, rel=1e-12)
        assert s.height_term > 0 and s.jumps > 0 and not s.unstable
        assert 0 <= s.wall_contact <= 1 and 0 < s.penetration_m < 0.1 * BL
    assert [s.fitness for s in scores] == evaluate_terrains(
        debris_run, [100, 101]
    ).fitness
    own = score_run(debris_run)
    assert [s.terrain for s in own] == [0, 1]
    assert np.mean([s.fitness for s in own]) == best.fitness


def test_a_flat_floor_run_has_one_score_and_no_walls():
    if not (FLAT_RUN / rundir.BEST).is_file():
        pytest.skip(f"{FLAT_RUN} not present")
    (s,) = score_run(FLAT_RUN)
    cfg, beh, best = rundir.load_run(FLAT_RUN)
    assert s.terrain is None and s.wall_contact == 0.0
    assert (
        s.fitness == beh.evaluate(best.genome[None], cfg.model, engine=cfg.engine)[0][0]
    )
    assert s.distance_term == 0.0 and s.height_term == s.fitness  # Eq. 4 alone
    with pytest.raises(ValueError, match="terrain_seeds: the flat scene"):
        score_run(FLAT_RUN, terrain_seeds=[1])
    (d,) = score_run(FLAT_RUN, terrain_seeds=[100], scene=Debris())  # zero-shot
    assert d.terrain == 100 and d.distance_term is not None


def test_other_behaviours_have_no_terms(shipped):
    (s,) = score_run(shipped / "kick")
    assert s.height_term is None and s.distance_term is None


def _score(scene, starts, ctl, params, steps=600):
    """The EpisodeScore of a controller's episode in the monolithic
    behaviour's scene ``scene`` from ``starts``."""
    here = get_behaviour("monolithic", None).on(scene)
    res = rollout(ctl, params, starts, steps, model_params=P, scene=scene,
                  record=RECORD)  # fmt: skip
    return episode_score(here, res, P, float(here.fitness(res, P)[0])), res


def test_wall_contact_is_the_share_of_steps_touching_a_wall():
    """Thrown at the wall, the creature touches it; the rules jumping in the
    walled field from its start, or in an open field, never do."""
    scene = Debris(seed=2)
    rc = RuleController.for_model(P)
    rules = rc.params_for(np.array([DEFAULT_CHANGE_TIME]))
    s = ready_state(P, scene)
    thrown = StartStates(s.qpos.copy(), s.qvel.copy(), s.ctrl.copy())
    thrown.qvel[0, :3] = (0.0, 6.0, 2.0)
    hit, res = _score(scene, thrown, rc, rules, steps=300)
    assert hit.wall_contact > 0
    assert hit.wall_contact == res["wall_contact"][0, 1:].mean()
    for field in (scene, Debris(seed=2, wall_height=0)):
        calm, _ = _score(field, ready_state(P, field), rc, rules)
        assert calm.wall_contact == 0.0 and calm.jumps > 0


def test_penetration_of_a_creature_at_rest_is_its_contacts_depth():
    """Standing still on the flat floor (a network of zeros: no target ever
    changes): the recorded penetration is small and positive, at the start
    MuJoCo's deepest contact there, and it stays about that."""
    start = StartStates.ready(lm.load_model(P))
    res = rollout(MLP(), np.zeros((1, MLP().num_params)), start, 120,
                  model_params=P, record=RECORD)  # fmt: skip
    pen = res["penetration"][0]
    m = lm.load_model(P)
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:], d.ctrl[:] = start.qpos[0], start.qvel[0], start.ctrl[0]
    mujoco.mj_forward(m, d)
    assert d.ncon > 0
    assert pen[0] == -d.contact.dist[: d.ncon].min()
    assert (pen > 0).all() and pen.max() < 0.002 * BL
    np.testing.assert_allclose(pen, pen[0], rtol=0.2)
    assert (res["wall_contact"] == 0).all()


def test_the_deepest_contact_is_found_again_by_its_replay(debris_run):
    (s,) = score_run(debris_run, terrain_seeds=[100])
    c = deepest_contact(debris_run, terrain=100)
    assert c.terrain == 100 and c.depth_m == pytest.approx(s.penetration_m, abs=1e-12)
    assert c.geoms[0] and c.geoms[1] and c.normal_force > 0
    assert c.speed >= abs(c.approach_speed)
    assert 0 < c.step <= 3000 and 0 <= c.substep < 3


def test_the_contact_audit_script_reports_score_run(debris_run, tmp_path, capsys):
    """scripts/contact_audit.py: its row is score_run's numbers, its deepest
    contact deepest_contact's."""
    import importlib.util
    import json

    path = rundir.SHIPPED.parent / "scripts" / "contact_audit.py"
    spec = importlib.util.spec_from_file_location("contact_audit", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    out = tmp_path / "a.json"
    argv = [str(debris_run), "--terrain-seeds", "100", "--json", str(out)]
    assert script.main(argv) == 0
    (row,) = json.loads(out.read_text())
    (s,) = score_run(debris_run, terrain_seeds=[100])
    assert row["terrains"] == [json.loads(json.dumps(s.to_dict()))]
    assert row["deepest"]["depth_m"] == s.penetration_m
    assert row["terrains_over_gate"] == int(s.penetration_m > 0.05 * BL)
    assert "| " + str(debris_run) in capsys.readouterr().out


def test_a_run_scored_at_its_worst_resolution_is_judged_at_a_given_one_alone():
    """A composed run evolved on the worst of 3 and 6 substeps: as trained its
    score is that worst (its recorded fitness); at 3 substeps it is the fitness
    there alone, whose terms add up to it."""
    run = rundir.SHIPPED / "study" / "composed-apex-robust6-p10-s0"
    cfg = rundir.load_config(run / rundir.CONFIG)
    assert cfg.options.score_substeps == (6,) and cfg.model.substeps == 3
    (trained,) = score_run(run)
    (at3,) = score_run(run, substeps=3)
    (at6,) = score_run(run, substeps=6)
    recorded = rundir.BestGenome.load(run / rundir.BEST).fitness
    assert trained.fitness == recorded == min(at3.fitness, at6.fitness)
    assert at3.fitness != at6.fitness
    for s in (at3, at6):
        assert s.height_term + s.distance_term == s.fitness
