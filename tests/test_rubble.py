"""The ground's height on debris, which Eq. 4 on a terrain and the height
term of every debris study subtract (sim/rubble.py, Debris.heights), against
a plain reference: the tallest box over each point, every box tried."""

import math

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim import rubble
from locustjump.sim.scene import Debris

BL = lm.LocustParams().body_length


@pytest.fixture(autouse=True)
def _fresh_fields():
    """Each test makes its fields' boxes and grids anew: the caches live as
    long as the process, which mutation testing runs every mutant in."""
    rubble.boxes.cache_clear()
    rubble.height_grid.cache_clear()


def test_terrain_0s_boxes_as_every_shipped_debris_run_saw_them():
    """Seed 0 at the defaults: 117 boxes drawn, 108 outside the clearing;
    the first two and the last (x, y ahead and across, yaw, sides, height;
    body lengths and radians), to the last digit."""
    field = Debris(seed=0)
    got = rubble.boxes(field)
    assert field.count == 117 and got.shape == (108, 6)
    np.testing.assert_array_equal(got[[0, 1, -1]], [
        [15.83492724500072, -2.6035050196555516, 0.14568425227897247,
         0.40640553176577593, 0.6541808438456285, 0.3284489281502073],
        [5.554027985388369, 2.0479036776742996, 0.9091117311218697,
         0.7129724148546714, 0.8708572846613079, 0.2559869881787734],
        [24.014918182316173, 1.7379943947592222, 1.4510158142587737,
         0.38234910268353933, 0.815146519928583, 0.055089570976356785]])  # fmt: skip
    assert not got.flags.writeable and rubble.boxes(field) is got  # cached
    assert len(rubble.boxes(Debris(seed=0, clearing=0.0))) == 117


@pytest.mark.parametrize("seed, kept", [(1, 161), (7, 168)])
def test_every_box_within_its_fields_ranges_and_outside_the_clearing(seed, kept):
    """200 boxes drawn; those whose half diagonal reaches into the clearing
    dropped (161 and 168 kept: a box's reach from its own two sides)."""
    f = Debris(seed=seed, behind=1.0, length=5.0, width=3.0, spacing=0.3,
               size_min=0.2, size_max=0.6, height_min=0.1, height_max=0.3,
               clearing=0.8)  # fmt: skip
    b = rubble.boxes(f)
    assert f.count == 200 and len(b) == kept
    assert (-1.0 <= b[:, 0]).all() and (b[:, 0] <= 5.0).all()
    assert (np.abs(b[:, 1]) <= 1.5).all()
    assert (0.0 <= b[:, 2]).all() and (b[:, 2] <= math.pi / 2).all()
    assert ((0.2 <= b[:, 3:5]) & (b[:, 3:5] <= 0.6)).all()
    assert ((0.1 <= b[:, 5]) & (b[:, 5] <= 0.3)).all()
    reach = np.hypot(b[:, 3], b[:, 4]) / 2
    assert (np.hypot(b[:, 0], b[:, 1]) >= 0.8 + reach).all()


def _tallest_over(boxes: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The top of the tallest box whose footprint holds each point (0 where
    none does), trying every box over every point."""
    top = np.zeros(np.broadcast(x, y).shape)
    for bx, by, yaw, sx, sy, h in boxes:
        dx, dy = x - bx, y - by
        u = dx * math.cos(yaw) + dy * math.sin(yaw)
        v = -dx * math.sin(yaw) + dy * math.cos(yaw)
        inside = (np.abs(u) <= sx / 2) & (np.abs(v) <= sy / 2)
        top = np.where(inside, np.maximum(top, h), top)
    return top


@pytest.mark.parametrize(
    "field", [Debris(seed=4), Debris(seed=1001, size_max=1.5, behind=0.0, length=8.0)]
)
def test_the_grid_holds_the_tallest_box_over_each_cell_centre(field):
    x0, y0, cell, grid = rubble.height_grid(field, BL)
    cx = x0 + (np.arange(grid.shape[0]) + 0.5) * cell
    cy = y0 + (np.arange(grid.shape[1]) + 0.5) * cell
    want = _tallest_over(field.boxes(BL), cx[:, None], cy[None, :])
    np.testing.assert_array_equal(grid, want)
    assert (grid > 0).mean() > 0.1  # a field, not an empty grid
    # the grid reaches past the field by a box's half diagonal on every side
    reach = field.size_max * BL / math.sqrt(2)
    assert x0 == -field.behind * BL - reach and y0 == -field.width / 2 * BL - reach
    assert cx[-1] + cell / 2 >= field.length * BL + reach
    assert cy[-1] + cell / 2 >= field.width / 2 * BL + reach
    assert cell == rubble.HEIGHT_CELL_BL * BL
    # and no further: the last cells start inside that reach
    assert cx[-1] - cell / 2 < field.length * BL + reach
    assert cy[-1] - cell / 2 < field.width / 2 * BL + reach
    assert not grid.flags.writeable


class _Corners:
    """A field of two boxes of the largest size turned 45°, so that each
    reaches the grid's edge by its full half diagonal: one at the field's
    back left corner, one at its front right."""

    seed, behind, length, width, size_max = 0, 1.0, 2.0, 1.0, 0.5

    def boxes(self, body_length: float) -> np.ndarray:
        s = self.size_max * body_length
        return np.array([
            [-self.behind * body_length, -self.width / 2 * body_length,
             math.pi / 4, s, s, 0.2],
            [self.length * body_length, self.width / 2 * body_length,
             math.pi / 4, s, s, 0.3]])  # fmt: skip


def test_boxes_at_the_fields_corners_reach_the_grids_first_and_last_cells():
    field = _Corners()
    x0, y0, cell, grid = rubble._height_grid(field, BL)
    cx = x0 + (np.arange(grid.shape[0]) + 0.5) * cell
    cy = y0 + (np.arange(grid.shape[1]) + 0.5) * cell
    want = _tallest_over(field.boxes(BL), cx[:, None], cy[None, :])
    np.testing.assert_array_equal(grid, want)
    assert (grid[0] == 0.2).any() and (grid[:, 0] == 0.2).any()
    assert (grid[-3:] == 0.3).any() and (grid[:, -3:] == 0.3).any()  # near


def test_heights_read_the_cell_a_point_falls_in_and_zero_outside():
    field = Debris(seed=4)
    x0, y0, cell, grid = rubble.height_grid(field, BL)
    i, j = np.nonzero(grid)
    pick = np.random.default_rng(0).choice(len(i), 200, replace=False)
    i, j = i[pick], j[pick]
    # anywhere inside a cell reads that cell (at an edge, rounding decides)
    for fx, fy in ((0.5, 0.5), (0.01, 0.01), (0.99, 0.01), (0.2, 0.98)):
        x, y = x0 + (i + fx) * cell, y0 + (j + fy) * cell
        np.testing.assert_array_equal(field.heights(x, y, BL), grid[i, j])
    # shapes broadcast; points off the grid on any side are on the floor
    assert field.heights(np.zeros((2, 3)), 0.0, BL).shape == (2, 3)
    nx, ny = grid.shape
    off_x = np.array([x0 - cell * 0.01, x0 + nx * cell + 1e-9, x0 + 1.5 * cell])
    off_y = np.array([y0 + 1.5 * cell, y0 + 1.5 * cell, y0 + ny * cell + 1e-9])
    np.testing.assert_array_equal(field.heights(off_x, off_y, BL), 0.0)
    assert field.heights(np.array([x0 + 0.5 * cell]), np.array([y0 - 1e-9]), BL) == 0


def test_every_cell_is_read_the_first_and_the_last(monkeypatch):
    # (a field's edge cells hold no box top in practice, so a made grid)
    grid = np.arange(1.0, 13.0).reshape(3, 4)
    monkeypatch.setattr(rubble, "height_grid", lambda d, bl: (-1.0, 2.0, 0.5, grid))
    i, j = np.meshgrid(np.arange(3), np.arange(4), indexing="ij")
    x, y = -1.0 + (i + 0.5) * 0.5, 2.0 + (j + 0.5) * 0.5
    np.testing.assert_array_equal(Debris(seed=4).heights(x, y, BL), grid)
    np.testing.assert_array_equal(
        Debris(seed=4).heights([-1.1, 0.6], [2.1, 2.1], BL), 0
    )


def test_single_precision_points_read_as_their_double_values():
    # float32 points on the cell edges: their cells are those of the same
    # values in float64 (worked out in single precision, some fall a cell off)
    field = Debris(seed=4)
    x0, y0, cell, grid = rubble.height_grid(field, BL)
    i, j = np.nonzero(grid)
    x = (x0 + i * cell).astype(np.float32)
    y = (y0 + j * cell).astype(np.float32)
    np.testing.assert_array_equal(
        field.heights(x, y, BL), field.heights(x.astype(float), y.astype(float), BL)
    )
