"""The geometry of a debris field (:class:`~locustjump.sim.scene.Debris`)
apart from its MJCF: the seeded boxes and the grid of their tops the fitness
reads the ground's height from. Functions of a field's parameters (any
object with ``Debris``'s fields), cached per field."""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np

#: Cell of the height grid the fitness reads the ground's height from (body
#: lengths; 1 cm at the default size).
HEIGHT_CELL_BL = 0.02
#: Thickness of the walls around a debris field (body lengths).
WALL_THICKNESS_BL = 1.0


def _boxes(d: Any) -> np.ndarray:
    """The boxes of terrain ``d`` in body lengths (yaw in radians)."""
    rng = np.random.default_rng(d.seed)
    n = d.count
    out: np.ndarray = np.empty((n, 6))
    out[:, 0] = rng.uniform(-d.behind, d.length, n)
    out[:, 1] = rng.uniform(-d.width / 2, d.width / 2, n)
    out[:, 2] = rng.uniform(0.0, math.pi / 2, n)
    out[:, 3] = rng.uniform(d.size_min, d.size_max, n)
    out[:, 4] = rng.uniform(d.size_min, d.size_max, n)
    out[:, 5] = rng.uniform(d.height_min, d.height_max, n)
    # conservative: a box's half diagonal against the clearing's radius
    reach = np.hypot(out[:, 3], out[:, 4]) / 2
    out = out[np.hypot(out[:, 0], out[:, 1]) >= d.clearing + reach]
    out.flags.writeable = False
    return out


def _height_grid(d: Any, body_length: float) -> tuple[float, float, float, np.ndarray]:
    """(x0, y0, cell, grid (nx, ny)): box tops rasterised at cell centres."""
    rows = d.boxes(body_length)
    cell = HEIGHT_CELL_BL * body_length
    reach = d.size_max * body_length / math.sqrt(2)  # a box's half diagonal
    x0 = -d.behind * body_length - reach
    y0 = -d.width / 2 * body_length - reach
    nx = math.ceil(((d.behind + d.length) * body_length + 2 * reach) / cell)
    ny = math.ceil((d.width * body_length + 2 * reach) / cell)
    grid = np.zeros((nx, ny))
    for x, y, yaw, sx, sy, h in rows:
        i0, i1 = (max(0, math.floor((c - x0) / cell)) for c in (x - reach, x + reach))
        j0, j1 = (max(0, math.floor((c - y0) / cell)) for c in (y - reach, y + reach))
        cx = x0 + (np.arange(i0, min(nx, i1 + 2)) + 0.5) * cell
        cy = y0 + (np.arange(j0, min(ny, j1 + 2)) + 0.5) * cell
        dx, dy = cx[:, None] - x, cy[None, :] - y
        u = dx * math.cos(yaw) + dy * math.sin(yaw)
        v = -dx * math.sin(yaw) + dy * math.cos(yaw)
        inside = (np.abs(u) <= sx / 2) & (np.abs(v) <= sy / 2)
        view = grid[i0 : i0 + len(cx), j0 : j0 + len(cy)]
        np.maximum(view, np.where(inside, h, 0.0), out=view)
    grid.flags.writeable = False
    return x0, y0, cell, grid


# cached per field (a field is a frozen dataclass), and decorated here, apart
# from the functions, so that mutation testing can reach their bodies
boxes = lru_cache(maxsize=64)(_boxes)
height_grid = lru_cache(maxsize=16)(_height_grid)
