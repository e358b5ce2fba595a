"""A behaviour repertoire as plain arrays: the elites of a grid archive.

What pyribs' ``GridArchive`` holds (Mouret & Clune 2015's MAP-Elites grid;
pyribs' own field names), snapshotted so that the run directory, the figures
and the commands that pick one elite read it without pyribs: the descriptor
space is cut into ``dims[i]`` equal cells between ``lows[i]`` and
``highs[i]`` per descriptor (a value outside falls into the edge cell, as in
pyribs), and each occupied cell holds its elite, the genome of the highest
fitness found there.

Cells are numbered as pyribs numbers them: the flat index of the grid index
``(i, j, ...)`` in C order (``numpy.ravel_multi_index``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class Archive:
    """The elites of a grid archive, ``k`` of them, in the order held.

    Attributes:
      names: the descriptors, one per grid dimension.
      lows, highs: ``(d,)`` the grid's bounds per descriptor.
      dims: cells per descriptor.
      index: ``(k,)`` each elite's cell (flat, C order over ``dims``).
      solution: ``(k, P)`` its genome.
      objective: ``(k,)`` its fitness (maximised).
      measures: ``(k, d)`` its descriptors.
      generation: ``(k,)`` the generation that found it (1-based).
    """

    names: tuple[str, ...]
    lows: np.ndarray
    highs: np.ndarray
    dims: tuple[int, ...]
    index: np.ndarray
    solution: np.ndarray
    objective: np.ndarray
    measures: np.ndarray
    generation: np.ndarray

    def __post_init__(self) -> None:
        d, k = len(self.names), len(self.index)
        if not (len(self.lows) == len(self.highs) == len(self.dims) == d >= 1):
            raise ValueError("names, lows, highs and dims must be one per descriptor")
        if not np.all(np.asarray(self.lows) < np.asarray(self.highs)):
            raise ValueError("every low bound must be below its high bound")
        if min(self.dims) < 1:
            raise ValueError(f"dims must be >= 1, got {list(self.dims)}")
        shapes = {
            "solution": (self.solution.ndim == 2, self.solution.shape[:1]),
            "objective": (self.objective.ndim == 1, self.objective.shape),
            "measures": (self.measures.shape[1:] == (d,), self.measures.shape[:1]),
            "generation": (self.generation.ndim == 1, self.generation.shape),
        }
        for name, (ok, rows) in shapes.items():
            if not ok or rows != (k,):
                raise ValueError(f"{name} is not one row per elite ({k})")
        if self.index.ndim != 1:
            raise ValueError("index must be one cell per elite")
        if k and (self.index.min() < 0 or self.index.max() >= self.cells):
            raise ValueError(f"a cell index is outside the grid's {self.cells}")
        if len(np.unique(self.index)) != k:
            raise ValueError("two elites share a cell")
        for name in ("solution", "objective", "measures"):
            if not np.isfinite(getattr(self, name)).all():
                raise ValueError(f"{name} is not finite")

    # -- the grid ---------------------------------------------------------------

    @property
    def cells(self) -> int:
        """Cells of the grid."""
        return int(np.prod(self.dims))

    def __len__(self) -> int:
        return len(self.index)

    @property
    def coverage(self) -> float:
        """Occupied cells over cells (QDax's and pyribs' coverage)."""
        return len(self) / self.cells

    def qd_score(self, offset: float = 0.0) -> float:
        """Sum over the elites of fitness minus ``offset`` (Pugh et al. 2016;
        pyribs' ``qd_score_offset``), added in cell order."""
        order = np.argsort(self.index, kind="stable")
        return float(np.sum(self.objective[order] - offset))

    def grid_index(self) -> np.ndarray:
        """``(k, d)`` each elite's cell as a grid index."""
        return np.stack(np.unravel_index(self.index, self.dims), axis=1)

    def edges(self, i: int) -> np.ndarray:
        """The ``dims[i] + 1`` cell edges of descriptor ``i``."""
        return np.linspace(self.lows[i], self.highs[i], self.dims[i] + 1)

    def heat(self) -> np.ndarray:
        """The grid of fitness, shape ``dims``, NaN where no elite is."""
        grid = np.full(self.cells, np.nan)
        grid[self.index] = self.objective
        return grid.reshape(self.dims)

    # -- picking one elite -------------------------------------------------------

    def ranked(self) -> np.ndarray:
        """Positions of the elites by fitness, best first (ties: the lower
        cell first)."""
        return np.lexsort((self.index, -self.objective))

    def at_rank(self, k: int) -> int:
        """Position of the ``k``-th best elite (0: the best); ``IndexError``
        naming how many there are."""
        if not 0 <= k < len(self):
            raise IndexError(
                f"elite {k} does not exist: the archive holds {len(self)} "
                f"(0 .. {len(self) - 1}, best first)"
            )
        return int(self.ranked()[k])

    def at_cell(self, cell: tuple[int, ...]) -> int:
        """Position of the elite in grid cell ``cell``; ``IndexError`` naming
        why not (another number of descriptors, outside the grid, empty)."""
        if len(cell) != len(self.dims):
            raise IndexError(
                f"cell {_shown(cell)}: the grid has {len(self.dims)} "
                f"descriptors ({', '.join(self.names)})"
            )
        for i, (c, n) in enumerate(zip(cell, self.dims, strict=True)):
            if not 0 <= c < n:
                raise IndexError(
                    f"cell {_shown(cell)} is outside the grid: {self.names[i]} "
                    f"has cells 0 .. {n - 1}"
                )
        flat = int(np.ravel_multi_index(cell, self.dims))
        hit = np.flatnonzero(self.index == flat)
        if not hit.size:
            raise IndexError(f"cell {_shown(cell)} is empty (no elite there)")
        return int(hit[0])

    def in_cell_order(self) -> Archive:
        """The same elites sorted by cell (a canonical order for a file)."""
        o = np.argsort(self.index, kind="stable")
        return Archive(
            self.names, self.lows, self.highs, self.dims, self.index[o],
            self.solution[o], self.objective[o], self.measures[o],
            self.generation[o],
        )  # fmt: skip


def _shown(cell: tuple[int, ...]) -> str:
    return ",".join(str(c) for c in cell)
