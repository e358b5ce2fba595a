"""The world the creature stands in, apart from the creature: a ``Scene``.

A scene is a frozen dataclass (its fields are its parameters, so that a config
table can hold them) that writes its part of the MJCF document: assets, the
geoms under ``<worldbody>``, and the names of the geoms the creature may touch.
:mod:`locustjump.sim.model` puts it together with the creature and writes one
contact pair per (scene geom, creature geom); nothing else collides.

Scenes are known by name (``register_scene``); ``flat`` is the default. Sizes
are given in body lengths of the creature, so a scene scales with it.

A new scene (say seeded random boxes on the floor) is a subclass with its
parameters as fields and a ``mjcf`` method, registered with
``@register_scene`` (another package's: :mod:`locustjump.plugins`); it
touches no creature code. Its geoms inherit the
world's contact model (``contype="0" conaffinity="0"``: only the pairs
collide); each geom it lists in ``SceneMJCF.geoms`` gets one pair per
creature geom, so the number of pairs is their product. The solver takes the
contacts in the pairs' order: MuJoCo sorts the pairs by body (a scene's static
geoms are all the world body's), and within one creature body they follow that
list, each scene geom against the body's geoms in turn.
"""

from __future__ import annotations

import dataclasses
import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from locustjump import plugins
from locustjump.ranges import (
    INT64_MAX,
    Range,
    SettingTypeError,
    SettingValueError,
    check_settings,
    setting,
)
from locustjump.sim import names, rubble
from locustjump.sim.rubble import HEIGHT_CELL_BL


@dataclass(frozen=True)
class SceneMJCF:
    """A scene's pieces of one MJCF document, each a fragment of XML."""

    assets: str  #: children of ``<asset>``: textures, materials
    worldbody: str  #: children of ``<worldbody>``: its geoms (static bodies)
    geoms: tuple[str, ...]  #: geoms the creature may touch, in pair order
    #: whether more geoms (``worldbody``'s with ``conaffinity="1"``) collide
    #: with the creature through MuJoCo's broad phase: the creature's geoms then
    #: get ``contype="1"`` (they still never collide with each other), and the
    #: model lets the static geoms sleep (their poses are not recomputed)
    broad_phase: bool = False
    #: geoms that bound the world rather than make its ground (walls): the
    #: engine records the control steps in which the creature touches them
    #: (``wall_contact``)
    walls: tuple[str, ...] = ()


@dataclass(frozen=True)
class Scene(ABC):
    """A world for the creature: its fields are its parameters."""

    name: ClassVar[str]  #: the name it is registered and configured by

    @abstractmethod
    def mjcf(self, body_length: float) -> SceneMJCF:
        """This scene's MJCF for a creature ``body_length`` metres long."""

    def heights(self, x: np.ndarray, y: np.ndarray, body_length: float) -> np.ndarray:
        """The ground's height (m) under the points ``(x, y)`` (m, any shape
        alike): the top of what the creature stands on there."""
        return np.zeros(np.broadcast(x, y).shape)

    @property
    def is_flat(self) -> bool:
        """The plain floor: heights are 0 everywhere (fitness as in the paper)."""
        return False

    @property
    def seeded(self) -> bool:
        """Whether it has terrains to choose from (a ``seed`` field)."""
        return "seed" in {f.name for f in dataclasses.fields(self)}

    def with_seed(self, seed: int) -> Scene:
        """The same scene with terrain seed ``seed`` (a scene without a
        ``seed`` field has one terrain: itself)."""
        if not self.seeded:
            return self
        # a subclass's field, which Scene itself does not declare
        return dataclasses.replace(self, seed=seed)  # type: ignore[call-arg]


@dataclass(frozen=True)
class Flat(Scene):
    """An infinite flat floor (a plane at z = 0) with a checker texture."""

    name: ClassVar[str] = "flat"

    def mjcf(self, body_length: float) -> SceneMJCF:
        """The floor: a plane whose grid lines are 0.05 body length apart.

        It collides through its contact pairs alone, in any scene (so that a
        scene with a broad phase keeps this infinite plane out of its world
        body's bounding volume hierarchy, whose every node it would enlarge)."""
        return SceneMJCF(
            assets=(
                '<texture name="grid" type="2d" builtin="checker" width="512" '
                'height="512"\n'
                '             rgb1="0.82 0.82 0.78" rgb2="0.62 0.64 0.60" '
                'mark="edge"\n'
                '             markrgb="0.3 0.3 0.3"/>\n'
                '    <material name="grid" texture="grid" texrepeat="1 1" '
                'texuniform="true"\n'
                '              reflectance="0"/>'
            ),
            worldbody=(
                f'<geom name="{names.FLOOR}" type="plane" contype="0" '
                f'conaffinity="0" size="0 0 {0.05 * body_length:.9g}" '
                'material="grid"/>'
            ),
            geoms=(names.FLOOR,),
        )

    @property
    def is_flat(self) -> bool:
        return True


#: Most boxes a debris field may hold (each adds one contact pair per creature
#: geom; beyond this a terrain is refused rather than made slow or too large).
MAX_BOXES = 2000
#: Most terrains a genome may be scored on in training.
MAX_TERRAINS = 64
#: ``seed`` of a seeded scene: one terrain each (the last of several terrains,
#: ``seed + terrains - 1``, too)
TERRAIN_SEED = Range(0, INT64_MAX, integer=True)
#: ``terrains``: how many a genome is scored on
TERRAINS = Range(1, MAX_TERRAINS, integer=True)
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


_REGISTRY: dict[str, type[Scene]] = {}

#: The scene of a creature unless told otherwise.
DEFAULT_SCENE = Flat.name


def register_scene(cls: type[Scene]) -> type[Scene]:
    """Make scene class ``cls`` known by ``cls.name`` (usable as a decorator)."""
    if not isinstance(getattr(cls, "name", None), str):
        raise TypeError(f"{cls.__name__} must set a str 'name'")
    _REGISTRY[cls.name] = cls
    return cls


register_scene(Flat)
register_scene(Debris)


def scene_names() -> tuple[str, ...]:
    """Every registered scene's name, the plugins' too."""
    plugins.load(plugins.SCENES, register_scene)
    return tuple(_REGISTRY)


def scene_class(name: str) -> type[Scene]:
    """The class registered as ``name`` (``ValueError`` if there is none)."""
    if name not in _REGISTRY:
        plugins.load(plugins.SCENES, register_scene)
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ValueError(
            f"unknown scene {name!r}; choose from {', '.join(_REGISTRY)}"
        ) from None


#: How the fitness on several terrains is combined into one.
AGGREGATES = ("mean", "min")


@dataclass(frozen=True)
class Terrains:
    """The terrains a genome is scored on: ``count`` of ``scene``, with terrain
    seeds ``seed, seed + 1, ...`` (a scene without a seed: itself, once), each
    genome's fitness combined over them by ``aggregate`` (``mean`` or ``min``:
    the worst terrain)."""

    scene: Scene = Flat()
    count: int = 1
    aggregate: str = "mean"

    def __post_init__(self) -> None:
        if not isinstance(self.scene, Scene):
            raise SettingTypeError("scene", "a Scene (flat, debris, ...)", self.scene)
        object.__setattr__(self, "count", TERRAINS.check("terrains", self.count))
        if self.aggregate not in AGGREGATES:
            raise SettingValueError(
                "aggregate", f"one of {', '.join(AGGREGATES)}", self.aggregate
            )
        if self.count > 1 and not self.scene.seeded:
            raise SettingValueError(
                "terrains", f"1 (the {self.scene.name} scene has one terrain)",
                self.count,
            )  # fmt: skip
        first: int = getattr(self.scene, "seed", 0)
        if first + self.count - 1 > INT64_MAX:  # the last terrain's seed
            raise SettingValueError(
                "terrains",
                f"at most {INT64_MAX - first + 1} from seed {first} (terrain "
                "seeds are at most 2**63-1)",
                self.count,
            )

    @property
    def scenes(self) -> tuple[Scene, ...]:
        """One scene per terrain, in seed order."""
        seed = getattr(self.scene, "seed", 0)
        return tuple(self.scene.with_seed(seed + i) for i in range(self.count))

    def combine(self, fitness: np.ndarray) -> np.ndarray:
        """``fitness (count, n)`` on each terrain as one ``(n,)``."""
        one: np.ndarray
        if len(fitness) == 1:
            one = fitness[0]
        elif self.aggregate == "min":
            one = fitness.min(axis=0)
        else:
            one = fitness.mean(axis=0)
        return one
