"""composed-height and monolithic-height: Eq. 4 above the ground alone, the
ablation of the distance term (issue #45)."""

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.engine.rollout import rollout
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks import behaviour_names, get_behaviour
from locustjump.tasks.composed import successive_terms

P = lm.LocustParams()


@pytest.fixture(scope="module")
def genomes():
    beh = get_behaviour("monolithic")
    return np.random.default_rng(3).normal(0, 0.5, (2, beh.controller.num_params))


def test_registered():
    assert {"composed-height", "monolithic-height"} <= set(behaviour_names())


def test_on_the_flat_floor_it_is_the_monolithic_fitness(genomes):
    mine = get_behaviour("monolithic-height").evaluate(genomes, P)[0]
    theirs = get_behaviour("monolithic").evaluate(genomes, P)[0]
    np.testing.assert_array_equal(mine, theirs)


def test_on_debris_it_is_the_height_term_alone(genomes):
    t = Terrains(Debris(seed=3))
    beh, full = (
        get_behaviour("monolithic-height", terrains=t),
        get_behaviour("monolithic", terrains=t),
    )
    fit, res = beh.evaluate(genomes, P, record=("qpos",))
    height, distance = successive_terms(res["qpos"], P, beh.scene)
    np.testing.assert_array_equal(fit, height)
    assert np.any(distance != 0)  # the full fitness differs by it
    np.testing.assert_allclose(full.evaluate(genomes, P)[0], height + distance)
    terms = beh.episode_terms(res, P)
    np.testing.assert_array_equal(terms["height"] + terms["distance"], fit)


def test_its_dense_reward_adds_up_to_its_fitness(genomes):
    beh = get_behaviour("monolithic-height", terrains=Terrains(Debris(seed=3)))
    res = rollout(beh.controller, genomes[:1], beh.start_states(P), beh.n_steps,
                  scene=beh.scene, record=("qpos", "obs"))  # fmt: skip
    reward = beh.reward(P)
    reward.reset(res["qpos"][0, 0], res["obs"][0, 0])
    total = sum(reward.step(q, o) for q, o in zip(res["qpos"][0, 1:], res["obs"][0, 1:],
                                                    strict=True))  # fmt: skip
    assert total == pytest.approx(beh.episode_fitness(res, P)[0], rel=1e-12)


def test_the_height_is_counted_above_the_box_under_the_body():
    # a made trajectory: controller 0 stands over the tallest box, controller
    # 1 over the open clearing at the start, both at z = 0.5 m for 4 steps
    beh = get_behaviour("monolithic-height", terrains=Terrains(Debris(seed=3)))
    boxes = beh.scene.boxes(P.body_length)
    x, y, *_, top = boxes[np.argmax(boxes[:, 5])]
    assert beh.scene.heights(x, y, P.body_length) == top > 0
    qpos = np.zeros((2, 5, 7))
    qpos[0, :, :2] = x, y
    qpos[:, :, 2] = 0.5
    res = {"qpos": qpos}
    np.testing.assert_allclose(beh.episode_fitness(res, P), [4 * (0.5 - top), 4 * 0.5])
    terms = beh.episode_terms(res, P)
    assert terms["distance"].shape == (2,) and terms["distance"].dtype == np.float64
    np.testing.assert_array_equal(terms["distance"], np.zeros(2))
    np.testing.assert_array_equal(terms["height"], beh.episode_fitness(res, P))
    reward = beh.reward(P)
    reward.reset(qpos[0, 0], np.zeros(1))
    assert reward.step(qpos[0, 1], np.zeros(1)) == pytest.approx(0.5 - top)
