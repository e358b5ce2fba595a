"""The repertoire as plain arrays (evo/archive.py): what an archive accepts,
its grid, and how one elite is picked, by rank or by cell."""

import numpy as np
import pytest

from locustjump.evo.archive import Archive


def _fields(**changes):
    """A valid 2 x 3 grid holding 3 elites (cells 5, 0, 3), with changes."""
    f = {
        "names": ("x", "y"),
        "lows": np.array([0.0, -1.0]),
        "highs": np.array([1.0, 1.0]),
        "dims": (2, 3),
        "index": np.array([5, 0, 3]),
        "solution": np.arange(6.0).reshape(3, 2),
        "objective": np.array([0.5, 2.0, 0.5]),
        "measures": np.array([[0.9, 0.9], [0.1, -0.9], [0.6, -0.9]]),
        "generation": np.array([1, 1, 2]),
    }
    f.update(changes)
    return f


ONE_EACH = "names, lows, highs and dims must be one per descriptor"
BOUNDS = "every low bound must be below its high bound"


def _archive(**changes):
    return Archive(**_fields(**changes))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"names": ("x",)}, ONE_EACH),
        ({"lows": np.zeros(3)}, ONE_EACH),
        ({"highs": np.ones(1)}, ONE_EACH),
        ({"dims": (2, 3, 1)}, ONE_EACH),
        ({"names": (), "lows": np.zeros(0), "highs": np.zeros(0), "dims": (),
          "measures": np.zeros((3, 0))},
         ONE_EACH),
        ({"highs": np.array([1.0, -1.0])}, BOUNDS),
        ({"highs": np.array([-1.0, 1.0])}, BOUNDS),
        ({"dims": (2, 0)}, "dims must be >= 1, got [2, 0]"),
        ({"solution": np.zeros(3)}, "solution is not one row per elite (3)"),
        ({"solution": np.zeros((2, 2))}, "solution is not one row per elite (3)"),
        ({"objective": np.zeros((3, 1))}, "objective is not one row per elite (3)"),
        ({"objective": np.zeros(4)}, "objective is not one row per elite (3)"),
        ({"measures": np.zeros((3, 3))}, "measures is not one row per elite (3)"),
        ({"measures": np.zeros((2, 2))}, "measures is not one row per elite (3)"),
        ({"generation": np.zeros((3, 1))}, "generation is not one row per elite (3)"),
        ({"generation": np.zeros(2)}, "generation is not one row per elite (3)"),
        ({"index": np.array([[5], [0], [3]])}, "index must be one cell per elite"),
        ({"index": np.array([5, -1, 3])}, "a cell index is outside the grid's 6"),
        ({"index": np.array([5, 6, 3])}, "a cell index is outside the grid's 6"),
        ({"index": np.array([5, 0, 5])}, "two elites share a cell"),
        ({"solution": np.array([[0.0, 1], [2, np.nan], [4, 5]])},
         "solution is not finite"),
        ({"objective": np.array([0.5, np.inf, 0.5])}, "objective is not finite"),
        ({"measures": np.array([[0.9, 0.9], [0.1, -np.inf], [0.6, -0.9]])},
         "measures is not finite"),
    ],
)  # fmt: skip
def test_a_malformed_archive_is_refused_saying_what_is_wrong(changes, message):
    with pytest.raises(ValueError) as err:
        _archive(**changes)
    assert str(err.value) == message


def test_the_edges_of_the_grid_are_legal():
    a = _archive(index=np.array([5, 0, 4]), dims=(2, 3))  # the last cell, 5
    assert a.cells == 6 and len(a) == 3
    one = _archive(dims=(1, 6))  # one cell along a descriptor is a grid
    assert one.cells == 6
    line = _archive(names=("x",), lows=np.zeros(1), highs=np.ones(1), dims=(6,),
                    measures=np.array([[0.9], [0.1], [0.6]]))  # fmt: skip
    assert line.cells == 6 and line.at_cell((3,)) == 2  # one descriptor is a grid
    empty = _archive(index=np.zeros(0, int), solution=np.zeros((0, 2)),
                     objective=np.zeros(0), measures=np.zeros((0, 2)),
                     generation=np.zeros(0, int))  # fmt: skip
    assert len(empty) == 0 and empty.coverage == 0.0 and empty.qd_score() == 0.0
    # generations are counts, not checked for finiteness (an int array)
    assert _archive(generation=np.array([0, 7, 2])).generation[1] == 7


def test_the_grid_its_cells_edges_and_heat():
    a = _archive()
    assert a.cells == 6 and len(a) == 3 and a.coverage == 0.5
    assert a.grid_index().tolist() == [[1, 2], [0, 0], [1, 0]]
    np.testing.assert_array_equal(a.edges(0), [0.0, 0.5, 1.0])
    np.testing.assert_allclose(a.edges(1), [-1.0, -1 / 3, 1 / 3, 1.0], rtol=1e-15)
    heat = a.heat()
    assert heat.shape == (2, 3)
    expected = np.full((2, 3), np.nan)
    expected[1, 2], expected[0, 0], expected[1, 0] = 0.5, 2.0, 0.5
    np.testing.assert_array_equal(heat, expected)


def test_the_qd_score_is_added_in_cell_order():
    # cells 5, 0, 3: added as held, 1e16 - 1e16 + 1 = 1; in cell order,
    # -1e16 + 1 (rounds to -1e16) + 1e16 = 0
    a = _archive(objective=np.array([1e16, -1e16, 1.0]))
    assert a.qd_score() == 0.0
    b = _archive(objective=np.array([3.0, 1.0, 2.0]))
    assert b.qd_score() == 6.0 and b.qd_score(offset=1.0) == 3.0
    assert b.qd_score(offset=-0.5) == 7.5


def test_elites_are_ranked_best_first_ties_by_lower_cell():
    a = _archive(objective=np.array([0.5, 2.0, 0.5]))
    assert a.ranked().tolist() == [1, 2, 0]  # cells 0, then 3 before 5
    assert [a.at_rank(k) for k in range(3)] == [1, 2, 0]
    b = _archive(objective=np.array([3.0, 1.0, 2.0]))
    assert b.ranked().tolist() == [0, 2, 1]


@pytest.mark.parametrize("k", [-1, 3, 10])
def test_a_rank_that_does_not_exist_is_named(k):
    with pytest.raises(IndexError) as err:
        _archive().at_rank(k)
    assert str(err.value) == (
        f"elite {k} does not exist: the archive holds 3 (0 .. 2, best first)"
    )


def test_an_elite_is_found_by_its_cell():
    a = _archive()
    assert a.at_cell((1, 2)) == 0 and a.at_cell((0, 0)) == 1 and a.at_cell((1, 0)) == 2


@pytest.mark.parametrize(
    ("cell", "message"),
    [
        ((1,), "cell 1: the grid has 2 descriptors (x, y)"),
        ((1, 2, 0), "cell 1,2,0: the grid has 2 descriptors (x, y)"),
        ((2, 0), "cell 2,0 is outside the grid: x has cells 0 .. 1"),
        ((-1, 0), "cell -1,0 is outside the grid: x has cells 0 .. 1"),
        ((0, 3), "cell 0,3 is outside the grid: y has cells 0 .. 2"),
        ((0, -1), "cell 0,-1 is outside the grid: y has cells 0 .. 2"),
        ((0, 1), "cell 0,1 is empty (no elite there)"),
        ((1, 1), "cell 1,1 is empty (no elite there)"),
    ],
)
def test_a_cell_that_holds_no_elite_is_named(cell, message):
    with pytest.raises(IndexError) as err:
        _archive().at_cell(cell)
    assert str(err.value) == message


def test_in_cell_order_every_field_moves_together():
    a = _archive()
    b = a.in_cell_order()
    order = [1, 2, 0]  # cells 0, 3, 5
    assert b.names == a.names and b.dims == a.dims
    np.testing.assert_array_equal(b.lows, a.lows)
    np.testing.assert_array_equal(b.highs, a.highs)
    np.testing.assert_array_equal(b.index, [0, 3, 5])
    for name in ("solution", "objective", "measures", "generation"):
        np.testing.assert_array_equal(getattr(b, name), getattr(a, name)[order])
