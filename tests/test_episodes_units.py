"""``present.episodes``: an episode's numbers (the study tables' height and
distance terms, distance, jumps, wall contact, penetration, highest point)
from made-up records, and which scenes a run is scored on; no physics."""

from types import SimpleNamespace

import numpy as np
import pytest

from locustjump.present.episodes import _scenes, episode_score
from locustjump.sim import model as lm
from locustjump.sim.scene import Debris, Flat

P = lm.LocustParams()
S = lm.standing_height(P)  # the body's standing height: no jump


class _Res(dict):
    """What a rollout records, as ``episode_score`` reads it."""

    def __init__(self, steps, unstable, **arrays):
        super().__init__(arrays)
        self.steps = np.array(steps)
        self.unstable = np.array(unstable)


def _here(scene, terms):
    """A behaviour in ``scene`` whose fitness terms are ``terms``; it keeps
    what it was asked with (``asked``)."""
    here = SimpleNamespace(scene=scene, asked=[])

    def fitness_terms(res, p):
        here.asked.append((res, p))
        return terms

    here.fitness_terms = fitness_terms
    return here


def _records(z0, z1, x0, x1):
    """Two episodes of 6 recorded steps, (x, y, z) per step."""
    q = np.zeros((2, 6, 3))
    q[:, :, 1] = 0.3  # y: off the field's centre line
    q[0, :, 0], q[1, :, 0] = x0, x1
    q[0, :, 2], q[1, :, 2] = z0, z1
    return q


def _res(unstable=(False, False)):
    # episode 0 ran to step 5 (6 rows), episode 1 to step 3: its rows 4 and 5
    # repeat an unstable simulation's last state and must not count
    q = _records(
        z0=[S, S, S + 1.5, S, S, S],  # one jump
        z1=[S, S + 1, S, S + 1, S, S + 5],  # two jumps up to step 3
        x0=[1, 2, 3, 4, 5, 6],  # 5 m
        x1=[2, 4, 6, 8, 100, 100],  # 6 m up to step 3
    )
    pen = np.array([[0, 0.01, 0.02, 0, 0, 0.03], [0, 0.05, 0, 0.001, 0.9, 0.9]])
    # the wall record of a step is after its action: step 0 (the start) is out
    wall = np.array([[1, 0, 1, 0, 0, 1], [1, 1, 0, 0, 1, 1]], dtype=bool)
    return _Res([5, 3], unstable, qpos=q, penetration=pen, wall_contact=wall)


def test_an_episodes_numbers_count_each_episode_to_its_last_step():
    terms = {"height": np.array([12.5]), "distance": np.array([3.25])}
    here, res = _here(Flat(), terms), _res()
    got = episode_score(here, res, P, 7)
    assert len(here.asked) == 1
    assert here.asked[0][0] is res and here.asked[0][1] is P
    assert got.terrain is None and got.fitness == 7.0 and type(got.fitness) is float
    assert got.height_term == 12.5 and got.distance_term == 3.25
    assert type(got.height_term) is float and type(got.distance_term) is float
    assert got.distance_m == 5.5  # the mean of 5 and 6
    assert got.jumps == 3
    assert got.wall_contact == 3 / 8  # steps 1-5 and 1-3: 2 + 1 of 8
    assert got.penetration_m == 0.05  # the deepest of either, to its last step
    assert got.highest_m == pytest.approx(S + 1.5)
    assert got.unstable is False
    assert episode_score(_here(Flat(), terms), _res((False, True)), P, 7).unstable
    assert got.to_dict()["jumps"] == 3


def test_a_behaviour_without_terms_has_none():
    got = episode_score(_here(Flat(), {}), _res(), P, 1.0)
    assert got.height_term is None and got.distance_term is None


def test_episodes_that_never_stepped_touched_no_wall():
    res = _res()
    res.steps = np.array([0, 0])
    got = episode_score(_here(Flat(), {}), res, P, 0.0)
    assert got.wall_contact == 0.0 and got.jumps == 0 and got.distance_m == 0.0
    assert got.penetration_m == 0.0 and got.highest_m == S


def test_on_a_terrain_heights_are_above_the_ground_under_the_body():
    scene = Debris(seed=3)
    res = _res()
    q = res["qpos"]
    q[:, :, 0] = np.linspace(1.0, 6.0, 6)  # over the rubble
    q[0, 2, 0] = 3.87  # episode 0's highest point: above a box 0.19 m high
    got = episode_score(_here(scene, {}), res, P, 0.0)
    assert got.terrain == 3
    ground = scene.heights(q[..., 0], q[..., 1], P.body_length)
    above = q[..., 2] - ground
    assert got.highest_m == max(above[0].max(), above[1, :4].max())
    assert ground[0, 2] > 0.18  # the highest point is over a box
    assert got.highest_m == pytest.approx(S + 1.5 - ground[0, 2])


def _beh(scene, scenes):
    return SimpleNamespace(terrains=SimpleNamespace(scene=scene, scenes=scenes))


def test_which_scenes_a_run_is_scored_on():
    own = [Debris(seed=1000), Debris(seed=1001)]
    beh = _beh(Debris(seed=1000), own)
    assert _scenes(beh, None, None) == own  # its training terrains
    assert _scenes(beh, None, Flat()) == [Flat()]  # another scene, once
    assert _scenes(beh, [7, np.int64(8)], None) == [Debris(seed=7), Debris(seed=8)]
    held = _scenes(beh, [5], Debris(seed=0, wall_height=0.0))
    assert held == [Debris(seed=5, wall_height=0.0)]  # that scene's kind
    assert type(held[0].seed) is int
    with pytest.raises(ValueError) as e:
        _scenes(_beh(Flat(), [Flat()]), [1], None)
    assert str(e.value) == (
        "terrain_seeds: the flat scene has one terrain (give a scene with "
        "terrains, e.g. Debris())"
    )
