"""A debris field: seeded rubble on the flat floor, walled in
(:class:`Debris`, the scene ``debris``). Its parameters, their ranges and
checks, and its MJCF; the geometry its boxes and height grid come from is
:mod:`~.rubble`'s. Registered, and re-exported, by :mod:`locustjump.sim.scene`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from locustjump.ranges import Range, SettingValueError, check_settings, setting
from locustjump.sim import names, rubble
from locustjump.sim.rubble import HEIGHT_CELL_BL
from locustjump.sim.world import TERRAIN_SEED, Flat, SceneMJCF

#: Most boxes a debris field may hold (each adds one contact pair per creature
#: geom; beyond this a terrain is refused rather than made slow or too large).
MAX_BOXES = 2000
#: The smallest extent of a debris field's box or wall (body lengths; half a
#: millimetre at the default size): smaller ones are no geoms MuJoCo can
#: make (5e-324 body lengths is a size of 0) nor divide by (``spacing``).
MIN_EXTENT = 1.0e-3
#: a debris field's extent that must be more than 0 (body lengths)
_EXTENT = Range(MIN_EXTENT, 1000.0, unit="body lengths")
#: one that may be 0 (body lengths)
_SPAN = Range(0.0, 1000.0, unit="body lengths")
#: Most cells of a terrain's height grid (8 bytes each: 160 MB).
MAX_CELLS = 20_000_000


@dataclass(frozen=True)
class Debris(Flat):
    """Seeded rubble on the floor: random boxes along the direction of travel.

    ``count = round(area / spacing**2)`` boxes (area: ``behind + length`` by
    ``width``) with centres uniform over the field, turned by a uniform angle
    about z, sides uniform in ``[size_min, size_max]`` and heights uniform in
    ``[height_min, height_max]``; all from ``numpy.random.default_rng(seed)``,
    so one ``seed`` is one terrain. Boxes that reach into the ``clearing``
    (a circle around the start) are left out: the creature starts on the
    floor, upright, with rubble around it. Lengths are in body lengths (0.5 m at the
    default size), ``friction`` is the boxes' sliding friction against the
    creature. The field covers ``x`` in ``[-behind, length]`` and ``y`` in
    ``[-width/2, width/2]``: the creature starts on it (heading +x), walled
    in (``wall_height`` high, their inner faces on the field's edges) unless
    ``wall_height`` is 0. The walls push from ``wall_margin`` in front of
    their faces on, so that a fast limb stops before it reaches one (0: at
    the face, as runs made before 2026-11-26 have it). Defaults and why:
    ``docs/science.md``, "Successive jumping across debris"; the margin:
    ``docs/physics.md``, "Walls that hold".
    """

    name: ClassVar[str] = "debris"

    # lengths in body lengths (the ranges' unit)
    seed: int = setting(0, TERRAIN_SEED)  #: the terrain (not the evolution's)
    length: float = setting(26.0, _EXTENT)  #: of rubble ahead of the start
    behind: float = setting(2.0, _SPAN)  #: of rubble behind the start
    width: float = setting(6.0, _EXTENT)  #: across, centred on the start
    spacing: float = setting(1.2, _EXTENT)  #: mean distance between boxes
    size_min: float = setting(0.3, _EXTENT)  #: shortest side of a box
    size_max: float = setting(1.0, _EXTENT)  #: longest side, >= size_min
    height_min: float = setting(0.05, _EXTENT)  #: lowest box
    height_max: float = setting(0.4, _EXTENT)  #: highest box, >= height_min
    clearing: float = setting(1.0, _SPAN)  #: radius kept free around the start
    friction: float = setting(1.0, Range(1e-6, 100.0))  #: (-) of the boxes
    #: of the walls around the field; 0: an open field
    wall_height: float = setting(8.0, _SPAN)
    #: in front of the walls' faces at which they start pushing
    #: (MuJoCo's contact ``margin`` on the wall geoms, ``gap`` 0): a limb that
    #: moves centimetres in one substep meets the wall's soft contact before
    #: its face rather than overshooting into it (docs/physics.md, "Walls that
    #: hold"); less than half a wall's thickness, and 0 on an open field
    wall_margin: float = setting(
        0.1, Range(0.0, rubble.WALL_THICKNESS_BL / 2, hi_open=True, unit="body lengths")
    )

    def __post_init__(self) -> None:
        check_settings(self)
        if 0 < self.wall_height < MIN_EXTENT:
            raise SettingValueError(
                "wall_height", f"0 (no walls) or in [{MIN_EXTENT:g}, 1000] body "
                "lengths", self.wall_height,
            )  # fmt: skip
        if self.wall_height == 0:  # no walls, no margin: one open field
            object.__setattr__(self, "wall_margin", 0.0)
        for lo, hi in (("size_min", "size_max"), ("height_min", "height_max")):
            if getattr(self, hi) < getattr(self, lo):
                raise SettingValueError(
                    hi, f"at least {lo} ({getattr(self, lo):g})", getattr(self, hi)
                )
        reach = 2 * self.size_max  # the grid's margin: a box's diagonal, both sides
        cells = ((self.behind + self.length + reach) / HEIGHT_CELL_BL) * (
            (self.width + reach) / HEIGHT_CELL_BL
        )
        if cells > MAX_CELLS:
            raise ValueError(
                f"the field is too large: its height grid would hold {cells:,.0f} "
                f"cells of {HEIGHT_CELL_BL:g} body lengths (at most {MAX_CELLS:,}); "
                "make it shorter or narrower (length, behind, width, size_max)"
            )
        if self.count > MAX_BOXES:
            raise ValueError(
                f"the field holds {self.count:,} boxes ((length + behind) x width "
                f"/ spacing^2); at most {MAX_BOXES:,}: raise spacing or make the "
                "field smaller"
            )

    @property
    def is_flat(self) -> bool:
        return False

    @property
    def count(self) -> int:
        """Boxes in the field."""
        area = (self.behind + self.length) * self.width
        return max(1, round(area / self.spacing**2))

    def boxes(self, body_length: float) -> np.ndarray:
        """(n, 6): centre x, y, yaw (rad), side x, side y, height (m) of the
        boxes (``count`` drawn, those reaching into the clearing left out)."""
        scale = np.array([body_length] * 2 + [1.0] + [body_length] * 3)
        boxes: np.ndarray = rubble.boxes(self) * scale
        return boxes

    def walls(self, body_length: float) -> np.ndarray:
        """(n, 4): centre x, y and sides x, y (m) of the walls around the
        field, outside it (none when ``wall_height`` is 0): left, right, back,
        front."""
        if self.wall_height == 0:
            return np.empty((0, 4))
        t = rubble.WALL_THICKNESS_BL
        x0, x1, w = -self.behind - t, self.length + t, self.width / 2
        mid, span = (x0 + x1) / 2, x1 - x0
        out = np.array([
            [mid, w + t / 2, span, t],
            [mid, -w - t / 2, span, t],
            [-self.behind - t / 2, 0.0, t, 2 * w],
            [self.length + t / 2, 0.0, t, 2 * w],
        ])  # fmt: skip
        return out * body_length

    def mjcf(self, body_length: float) -> SceneMJCF:
        """The floor (its pairs), the boxes ``debris0`` ... and the walls
        ``wall0`` ... (broad phase)."""
        floor = super().mjcf(body_length)
        # the boxes collide through the broad phase (117 boxes as explicit
        # pairs: 1,416 pairs, mj_step 2.5x the floor's; broad phase: 1.6x;
        # what that costs now: docs/performance.md, "Debris at the floor's
        # cost");
        # priority: their friction, not the larger of theirs and the creature's
        contact = (
            f'contype="0" conaffinity="1" priority="1" '
            f'friction="{self.friction:.9g} 0.005 0.0001"'
        )
        geoms = []
        for i, (x, y, yaw, sx, sy, h) in enumerate(self.boxes(body_length)):
            name = f"{names.DEBRIS}{i}"
            geoms.append(
                f'<geom name="{name}" type="box" material="rubble" {contact} '
                f'pos="{x:.9g} {y:.9g} {h / 2:.9g}" '
                f'euler="0 0 {math.degrees(yaw):.9g}" '
                f'size="{sx / 2:.9g} {sy / 2:.9g} {h / 2:.9g}"/>'
            )
        # the walls are frictionless (condim 1, theirs by priority): pushed
        # against, they push back horizontally only, so that no leg can climb
        # them (with the boxes' friction a network learnt to wall-jump 4.9 m
        # high and over them). Their margin (MuJoCo takes the larger of two
        # geoms' margins, whatever the priority) makes them push from that far
        # before the face: without it a tarsus at 15-22 m/s went 4.2 cm (8 %
        # of a body length) into a wall in one substep. Written only when not
        # 0, so that a margin-0 field is the document it always was.
        wall = 'contype="0" conaffinity="1" priority="2" condim="1"'
        if self.wall_margin:
            wall += f' margin="{self.wall_margin * body_length:.9g}" gap="0"'
        walls = self.walls(body_length)
        for i, (x, y, sx, sy) in enumerate(walls):
            h = self.wall_height * body_length
            geoms.append(
                f'<geom name="{names.WALL}{i}" type="box" material="wall" '
                f'{wall} pos="{x:.9g} {y:.9g} {h / 2:.9g}" '
                f'size="{sx / 2:.9g} {sy / 2:.9g} {h / 2:.9g}"/>'
            )
        return SceneMJCF(
            assets=floor.assets
            + '\n    <material name="rubble" rgba="0.55 0.47 0.38 1" reflectance="0"/>'
            + '\n    <material name="wall" rgba="0.6 0.65 0.7 0.2" reflectance="0"/>',
            worldbody=floor.worldbody + "\n    " + "\n    ".join(geoms),
            geoms=floor.geoms,
            broad_phase=True,
            walls=tuple(f"{names.WALL}{i}" for i in range(len(walls))),
        )

    def heights(self, x: np.ndarray, y: np.ndarray, body_length: float) -> np.ndarray:
        """The top of the highest box over each point (0 on the floor), read
        from a grid of ``HEIGHT_CELL_BL`` cells (the box edges are exact to one
        cell)."""
        x0, y0, cell, grid = rubble.height_grid(self, body_length)
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        i = np.floor((x - x0) / cell).astype(np.int64)
        j = np.floor((y - y0) / cell).astype(np.int64)
        inside = (i >= 0) & (i < grid.shape[0]) & (j >= 0) & (j < grid.shape[1])
        out = np.zeros(x.shape)
        out[inside] = grid[i[inside], j[inside]]
        return out
