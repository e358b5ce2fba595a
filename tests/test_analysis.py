"""The behaviour metrics every results table counts (sim/analysis.py): jumps,
the height above the ground, the ground under a path, lying overturned for
good; on made trajectories whose answers are known."""

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.analysis import (
    BOUNCE_PROMINENCE_BL,
    JUMP_THRESHOLD_BL,
    STUCK_S,
    Jump,
    clearance,
    find_jumps,
    ground_profile,
    stuck_overturned,
)
from locustjump.sim.scene import Debris, Flat

P = lm.LocustParams()
STAND = lm.standing_height(P)
THR = JUMP_THRESHOLD_BL * P.body_length  # 5 cm
PROM = BOUNCE_PROMINENCE_BL * P.body_length  # 10 cm


def _traj(z, x=None, y=None):
    q = np.zeros((len(z), 7))
    q[:, 0] = np.arange(len(z)) * 0.01 if x is None else x
    q[:, 1] = 0.0 if y is None else y
    q[:, 2] = z
    return q


def test_the_thresholds():
    assert (JUMP_THRESHOLD_BL, BOUNCE_PROMINENCE_BL, STUCK_S) == (0.1, 0.2, 1.0)


def test_standing_still_or_at_the_threshold_is_no_jump():
    assert find_jumps(_traj(np.full(50, STAND)), P) == []
    assert find_jumps(_traj(np.full(50, STAND + THR)), P) == []  # not above it


def test_one_jump_its_stretch_and_apex():
    z = np.full(40, STAND)
    z[10:20] = STAND + THR + np.array([1, 2, 3, 5, 8, 13, 8, 5, 3, 1]) * 0.01
    q = _traj(z)
    (j,) = find_jumps(q, P)
    assert j == Jump(start=10, apex_step=15, end=20, apex_height=z[15],
                     apex_x=q[15, 0], rise=z[15] - STAND)  # fmt: skip
    assert j.rise == pytest.approx(THR + 0.13)


def test_a_jump_at_either_end_of_the_episode_is_counted():
    z = np.full(12, STAND + 0.4)
    z[4:8] = STAND
    jumps = find_jumps(_traj(z), P)
    assert [(j.start, j.end) for j in jumps] == [(0, 4), (8, 12)]
    assert [j.apex_step for j in jumps] == [0, 8]  # the first of equal highs


def _two_arcs(dip):
    """Two arcs of 0.5 m above the threshold, z coming down to ``dip`` above
    it between them (never below it; below 0.45, the dip's neighbours)."""
    arc = np.array([0.1, 0.3, 0.45, 0.5, 0.45])
    z = np.concatenate([[STAND], STAND + THR + arc, [STAND + THR + dip],
                        STAND + THR + arc[::-1], [STAND]])  # fmt: skip
    return _traj(z)


def test_a_bounce_without_coming_down_splits_the_jump():
    q = _two_arcs(dip=0.05)  # 0.45 below the apexes on both sides: a landing
    jumps = find_jumps(q, P)
    assert [(j.start, j.apex_step, j.end) for j in jumps] == [(1, 4, 6), (6, 8, 12)]
    assert jumps[1].apex_height == q[8, 2]


def test_a_shallow_dip_does_not_split_the_jump():
    q = _two_arcs(dip=0.5 - PROM + 0.001)  # just under the prominence
    assert [(j.start, j.end) for j in find_jumps(q, P)] == [(1, 12)]
    q = _two_arcs(dip=0.5 - PROM - 0.001)  # just over it: split
    assert len(find_jumps(q, P)) == 2


def test_a_dip_of_exactly_the_prominence_is_no_landing():
    # a creature of a tenth of the size (body length 5 cm), where two heights
    # can differ by exactly 0.2 body lengths in floats
    small = lm.LocustParams(scale=1.0)
    stand, thr = lm.standing_height(small), JUMP_THRESHOLD_BL * small.body_length
    prom = BOUNCE_PROMINENCE_BL * small.body_length
    low = 0.014264213154933035
    high = low + prom
    assert high - low == prom and low > stand + thr
    rise = stand + 1.5 * thr
    for z in (np.array([0.0, rise, high, low, 2 * high, rise, 0.0]),
              np.array([0.0, rise, 2 * high, low, high, rise, 0.0])):  # fmt: skip
        # exactly the prominence on one side (more on the other): no landing
        assert len(find_jumps(_traj(z), small)) == 1  # more than, not at least
        z[3] = np.nextafter(low, 0.0)  # a hair lower: a landing
        assert len(find_jumps(_traj(z), small)) == 2


def test_a_dip_must_be_prominent_on_both_sides():
    z = STAND + THR + np.array([0.1, 0.5, 0.2, 0.25, 0.28, 0.2])
    # 0.3 below the apex before it, 0.08 to the high after it: no split
    assert len(find_jumps(_traj(np.concatenate([[STAND], z, [STAND]])), P)) == 1
    z = STAND + THR + np.array([0.1, 0.25, 0.2, 0.5, 0.3, 0.2])
    assert len(find_jumps(_traj(np.concatenate([[STAND], z, [STAND]])), P)) == 1


def test_a_flat_bottomed_bounce_splits_once():
    arc = np.array([0.1, 0.5, 0.1])
    z = STAND + THR + np.concatenate([arc, [0.05, 0.05], arc[::-1]])
    jumps = find_jumps(_traj(np.concatenate([[STAND], z, [STAND]])), P)
    assert [(j.start, j.end) for j in jumps] == [(1, 4), (4, 9)]


def test_three_jumps_in_one_stretch_split_at_each_landing():
    arc = np.array([0.1, 0.5, 0.1])
    z = STAND + THR + np.concatenate([arc, [0.02], arc, [0.03], arc])
    jumps = find_jumps(_traj(np.concatenate([[STAND], z, [STAND]])), P)
    assert [(j.start, j.end) for j in jumps] == [(1, 4), (4, 8), (8, 12)]


def test_on_debris_a_jump_is_above_the_ground_under_it():
    field = Debris(seed=0)
    x, y, *_, h = field.boxes(P.body_length)[0]
    q = _traj(np.full(20, STAND + h), x=np.full(20, x), y=np.full(20, y))
    assert find_jumps(q, P, field) == []  # standing on the box
    assert len(find_jumps(q, P)) == 1  # its top, on the flat floor, is a jump
    np.testing.assert_allclose(clearance(q, P, field), STAND, atol=1e-12)
    np.testing.assert_array_equal(clearance(q, P, Flat()), q[:, 2])
    # the default scene is the flat floor
    np.testing.assert_array_equal(clearance(q), q[:, 2])


def test_clearance_keeps_the_leading_shape():
    q = np.zeros((2, 3, 7))
    q[..., 2] = 0.3
    assert clearance(q, P, Debris(seed=0)).shape == (2, 3)


def test_the_ground_under_a_path():
    field = Debris(seed=0)
    x, y, *_, h = field.boxes(P.body_length)[0]
    q = _traj(np.full(3, 0.2), x=np.array([x + 1.0, x, x - 1.0]), y=np.full(3, y))
    gx, gh = ground_profile(q, P, field, points=101)
    assert len(gx) == len(gh) == 101
    half = P.body_length / 2
    assert gx[0] == x - 1.0 - half and gx[-1] == pytest.approx(x + 1.0 + half)
    np.testing.assert_allclose(np.diff(gx), (2.0 + 2 * half) / 100)
    np.testing.assert_array_equal(gh, field.heights(gx, np.full(101, y), P.body_length))
    assert gh[50] == h  # the path passes over the box's centre
    # the path's y is followed between its points
    q2 = _traj(
        np.full(2, 0.2), x=np.array([x - 1.0, x + 1.0]), y=np.array([y - 1.0, y + 1.0])
    )
    gx2, gh2 = ground_profile(q2, P, field, points=5)
    np.testing.assert_array_equal(
        gh2, field.heights(gx2, np.interp(gx2, [x - 1.0, x + 1.0], [y - 1.0, y + 1.0]),
                           P.body_length)
    )  # fmt: skip
    assert len(ground_profile(q2, P, field)[0]) == 2000  # the default
    assert ground_profile(q, P, Flat()) is None and ground_profile(q) is None


def test_stuck_overturned_is_a_whole_second_upside_down():
    n = round(STUCK_S / lm.CONTROL_DT)
    assert n == 120
    uz = np.ones(400)
    uz[100 : 100 + n] = -0.5
    assert stuck_overturned(uz) == 100
    uz[100 + n - 1] = 0.0  # one step short of a second (U_z = 0 is not down)
    assert stuck_overturned(uz) is None
    uz = np.ones(400)
    uz[-n:] = -1.0  # at the very end
    assert stuck_overturned(uz) == 400 - n
    assert stuck_overturned(-np.ones(n - 1)) is None  # shorter than a second
    assert stuck_overturned(-np.ones(n)) == 0
    # another control step: a second is another number of steps
    assert stuck_overturned(np.r_[np.ones(5), -np.ones(10)], dt=0.1) == 5
    assert stuck_overturned(np.r_[np.ones(5), -np.ones(9)], dt=0.1) is None
    # a control step over a second long: one step down is stuck
    assert stuck_overturned(np.array([1.0, -1.0, 1.0]), dt=5.0) == 1


def test_the_ground_under_a_path_that_stood_still_is_under_its_last_position():
    field = Debris(seed=0)
    x, y, *_, h = field.boxes(P.body_length)[0]
    # back to the box's x, 200 steps there sideways off it, then onto it
    xs = np.r_[x + np.linspace(0.2, 0.001, 50), np.full(200, x)]
    ys = np.r_[np.full(50, y), np.linspace(y, y - 3.0, 199), [y]]
    q = _traj(np.full(len(xs), 0.2), x=xs, y=ys)
    gx, gh = ground_profile(q, P, field, points=2001)
    # either side of where it stood, the ground under its first and its last
    # position there (in time), both on the box: not any other of its 200
    near = (np.abs(gx - x) < 0.02) & (gx != x)
    assert near.sum() >= 4 and (gh[near] == h).all()
