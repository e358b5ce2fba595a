"""``sim/bvh.py`` on hand-made trees: the surface area heuristic's split and
its tie rules, and a static body's tree rebuilt in place — node by node, box
by box — leaving every other body's tree as the compiler built it.
(``tests/test_debris.py`` checks the rebuilt world of a debris field finds
the compiler's contacts, in order, at every step.)"""

import mujoco
import numpy as np
import pytest

from locustjump.sim.bvh import _split, _surface, rebuild_bvh


def _boxes(x, y=None, z=None):
    """Unit cubes centred at ``x`` (and ``y``, ``z``; default 0): lo, hi."""
    n = len(next(v for v in (x, y, z) if v is not None))
    c = np.stack([np.zeros(n) if v is None else np.asarray(v, float)
                  for v in (x, y, z)], axis=1)  # fmt: skip
    return c - 0.5, c + 0.5


def test_a_boxs_surface_is_half_its_area():
    lo, hi = np.array([1.0, -1.0, 2.0]), np.array([3.0, 2.0, 7.0])  # 2 x 3 x 5
    assert _surface(lo, hi) == 2 * 3 + 3 * 5 + 5 * 2
    assert _surface(np.zeros((2, 3)), np.ones((2, 3))).tolist() == [3.0, 3.0]


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_the_far_box_is_split_off_along_any_axis(axis):
    """Cubes at 0, 1 and 10: leaving 10 alone costs 5 x 2 + 3, leaving 0
    alone 3 + 21 x 2. The geom ids are not in the boxes' order (on an axis
    where the centres are equal, they order the boxes: 0, 10, 1 costs 45)."""
    at = [None, None, None]
    at[axis] = [10.0, 0.0, 1.0]
    lo, hi = _boxes(*at)
    assert _split(lo, hi, np.array([1, 0, 2])).tolist() == [False, True, True]


def test_ties_go_to_the_leftmost_split_and_the_lowest_axis():
    lo, hi = _boxes([0.0, 1.0, 2.0])  # either split costs 13: the first
    assert _split(lo, hi, np.arange(3)).tolist() == [True, False, False]
    # corners of a square: halves by x or by y cost the same; x is taken
    lo, hi = _boxes([0.0, 10.0, 0.0, 10.0], [0.0, 0.0, 10.0, 10.0])
    assert _split(lo, hi, np.arange(4)).tolist() == [True, False, True, False]


def test_equal_centres_are_ordered_by_geom_id():
    """Four cubes on one spot along x, apart along y: along x the ids decide
    the order, and the best split by x is worse than by y, which is taken."""
    lo, hi = _boxes([0.0] * 4, [0.0, 3.0, 30.0, 33.0])
    assert _split(lo, hi, np.array([3, 1, 0, 2])).tolist() == [True, True, False, False]
    lo, hi = _boxes([0.0] * 3, [0.0] * 3)  # all on one spot: ids, leftmost
    assert _split(lo, hi, np.array([2, 0, 1])).tolist() == [False, True, False]


@pytest.mark.parametrize(
    "centres, halves",
    [([0.0, 0.0, 1.0], [1.5, 1.0, 1.5]), ([3.0, 3.0, 3.0], [1.0, 1.5, 0.5])],
)
def test_boxes_of_other_lengths_along_x(centres, halves):
    """Boxes 1 x 1 across, of half-lengths ``halves`` along x: the two boxes
    first in x (by centre, then id) go together (found by a search for splits
    that a box taken from the wrong end would change)."""
    c = np.array(centres)
    h = np.ones((3, 3)) * 0.5
    h[:, 0] = halves
    lo, hi = np.c_[c, np.zeros((3, 2))] - h, np.c_[c, np.zeros((3, 2))] + h
    assert _split(lo, hi, np.arange(3)).tolist() == [True, True, False]


def _cubes(xs, y=0.0):
    return "".join(f"<geom type='box' size='.5 .5 .5' pos='{x} {y} 0'/>" for x in xs)


#: the world: cubes at 0, 1, 10 (geoms 0-2; the compiler leaves 0 alone,
#: the heuristic 10); static body A: 0, 9, 10 (geoms 3-5); static body B: 0,
#: 1, 2, 3, 20 (geoms 6-10; the compiler splits 0-1 from 2, 3, 20, the
#: heuristic 20 from the rest); body C moves. A and B's inertial frames are
#: their own (the trees' boxes are in it)
_FRAME = "<inertial pos='0 0 0' mass='1' diaginertia='1 1 1'/>"
XML = f"""<mujoco><worldbody>{_cubes([0, 1, 10])}
<body pos='0 5 0'>{_FRAME}{_cubes([0, 9, 10])}</body>
<body pos='0 10 0'>{_FRAME}{_cubes([0, 1, 2, 3, 20])}</body>
<body><joint type='free'/><geom size='.1'/><geom size='.1' pos='1 0 0'/>
<geom size='.1' pos='2 0 0'/></body></worldbody></mujoco>"""


def _tree(m, body):
    rows = slice(m.body_bvhadr[body], m.body_bvhadr[body] + m.body_bvhnum[body])
    return [m.bvh_child[rows].tolist(), m.bvh_nodeid[rows].tolist(),
            m.bvh_depth[rows].tolist(), m.bvh_aabb[rows].copy()]  # fmt: skip


def _unions_rounded_out(child, nodeid, aabb):
    """Each internal node's box: its children's union, centred, its half-size
    8 ulps of its largest coordinate out."""
    for node in range(len(nodeid)):
        if nodeid[node] >= 0:
            assert child[node] == [-1, -1]
            continue
        c = aabb[child[node]]
        lo = np.min(c[:, :3] - c[:, 3:], axis=0)
        hi = np.max(c[:, :3] + c[:, 3:], axis=0)
        centre = (lo + hi) / 2
        tol = 8 * np.finfo(float).eps * np.maximum(np.abs(lo), np.abs(hi))
        half = np.maximum(hi - centre, centre - lo) + tol
        np.testing.assert_array_equal(aabb[node], np.concatenate([centre, half]))


def test_a_static_bodys_tree_is_rebuilt_node_by_node():
    m = mujoco.MjModel.from_xml_string(XML)
    built = [_tree(m, b) for b in range(4)]
    assert built[0][:3] == [[[1, 2], [-1, -1], [3, 4], [-1, -1], [-1, -1]],
                            [-1, 0, -1, 1, 2], [0, 1, 1, 2, 2]]  # fmt: skip
    leaf = {g: built[0][3][built[0][1].index(g)] for g in (0, 1, 2)}
    rebuild_bvh(m)  # the world
    child, nodeid, depth, aabb = _tree(m, 0)
    assert child == [[1, 4], [2, 3], [-1, -1], [-1, -1], [-1, -1]]
    assert nodeid == [-1, -1, 0, 1, 2] and depth == [0, 1, 2, 2, 1]
    for node, g in ((2, 0), (3, 1), (4, 2)):
        np.testing.assert_array_equal(aabb[node], leaf[g])  # the compiler's
    _unions_rounded_out(child, nodeid, aabb)
    for b in (1, 2, 3):  # the other bodies' trees as compiled
        after = _tree(m, b)
        assert after[:3] == built[b][:3]
        np.testing.assert_array_equal(after[3], built[b][3])
    rebuild_bvh(m, 1)  # body A: the heuristic's tree is the compiler's
    assert _tree(m, 1)[:3] == built[1][:3] == [
        [[1, 2], [-1, -1], [3, 4], [-1, -1], [-1, -1]], [-1, 3, -1, 4, 5],
        [0, 1, 1, 2, 2]]  # fmt: skip
    rebuild_bvh(m, 2)  # body B: 20 alone, then 0-1 and 2-3
    child, nodeid, depth, aabb = _tree(m, 2)
    assert child == [[1, 8], [2, 5], [3, 4], [-1, -1], [-1, -1], [6, 7],
                     [-1, -1], [-1, -1], [-1, -1]]  # fmt: skip
    assert nodeid == [-1, -1, -1, 6, 7, -1, 8, 9, 10]
    assert depth == [0, 1, 2, 3, 3, 2, 3, 3, 1]
    _unions_rounded_out(child, nodeid, aabb)
    assert _tree(m, 0)[:3] == [[[1, 4], [2, 3], [-1, -1], [-1, -1], [-1, -1]],
                               [-1, -1, 0, 1, 2], [0, 1, 2, 2, 1]]  # fmt: skip


def test_a_moving_body_and_a_tree_not_of_its_leaves_are_refused():
    m = mujoco.MjModel.from_xml_string(XML)
    with pytest.raises(ValueError, match=r"^body 3 moves: only a static body's "
                       r"tree is rebuilt$"):  # fmt: skip
        rebuild_bvh(m, 3)
    m.bvh_nodeid[m.body_bvhadr[0]] = 0  # the root made a leaf: 4 leaves, 5 nodes
    with pytest.raises(ValueError, match=r"^body 0's tree is not a binary tree "
                       r"of its leaves$"):  # fmt: skip
        rebuild_bvh(m)


def test_two_leaves_are_left_as_they_are():
    m = mujoco.MjModel.from_xml_string(f"<mujoco><worldbody>{_cubes([5, 0])}"
                                       "</worldbody></mujoco>")  # fmt: skip
    before = _tree(m, 0)
    m.bvh_aabb[1] += 1.0  # a box rebuilding would put back
    rebuild_bvh(m)
    after = _tree(m, 0)
    assert after[:3] == before[:3]
    np.testing.assert_array_equal(after[3][1], before[3][1] + 1.0)
