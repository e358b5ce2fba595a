"""Behaviour descriptors (tasks/descriptors.py): what a declaration accepts,
and how episodes' values become one row per controller."""

import numpy as np
import pytest

from locustjump.tasks.descriptors import Descriptor, describe

RISE = Descriptor("rise", 0.0, 5.0, "L", "height")
AHEAD = Descriptor("ahead", -5.0, 15.0, "L", "distance")


@pytest.mark.parametrize(
    ("low", "high", "needle"),
    [
        (np.nan, 1.0, "descriptor d: range must be finite"),
        (0.0, np.inf, "descriptor d: range must be finite"),
        (-np.inf, 1.0, "descriptor d: range must be finite"),
        (1.0, 1.0, "descriptor d: low must be below high"),
        (2.0, 1.0, "descriptor d: low must be below high"),
    ],
)
def test_a_declaration_needs_a_finite_increasing_range(low, high, needle):
    with pytest.raises(ValueError) as err:
        Descriptor("d", low, high, "L", "doc")
    assert str(err.value) == needle


def test_a_finite_increasing_range_is_declared():
    d = Descriptor("d", -1.0, 1e-9, "deg", "doc")
    assert (d.low, d.high) == (-1.0, 1e-9)


def test_an_unknown_name_is_refused_naming_it_and_what_is_declared():
    ep = {"rise": np.zeros(2), "ahead": np.zeros(2)}
    with pytest.raises(ValueError) as err:
        describe(ep, (RISE, AHEAD), ("rise", "height", "apex"), np.zeros(2, bool), 1)
    declared = "the task declares rise, ahead"
    assert str(err.value) == f"unknown descriptor 'height'; {declared}"
    with pytest.raises(ValueError) as err:
        describe(ep, (), ("rise",), np.zeros(2, bool), 1)
    assert str(err.value) == "unknown descriptor 'rise'; the task declares none"


def test_a_controller_is_the_mean_over_its_starts_then_terrains():
    # 2 terrains x 2 controllers x 3 start states, terrain-major
    rise = np.arange(12.0)
    ahead = -rise
    out = describe({"rise": rise, "ahead": ahead}, (RISE, AHEAD), ("ahead", "rise"),
                   np.zeros(12, bool), per_controller=3, terrains=2)  # fmt: skip
    # controller 0: starts 0-2 on terrain 0 (mean 1), 6-8 on terrain 1 (mean 7)
    np.testing.assert_array_equal(out, [[-4.0, 4.0], [-7.0, 7.0]])


def test_one_terrain_is_the_default_and_an_unstable_episode_counts_at_low():
    rise = np.array([1.0, 2.0, 3.0, 4.0])
    unstable = np.array([False, True, False, False])
    out = describe({"rise": rise, "ahead": rise}, (RISE, AHEAD), ("rise", "ahead"),
                   unstable, per_controller=2)  # fmt: skip
    # the unstable episode counts at each descriptor's low: 0 and -5
    np.testing.assert_array_equal(out, [[0.5, -2.0], [3.5, 3.5]])
