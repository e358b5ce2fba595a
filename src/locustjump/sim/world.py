"""The world the creature stands in, apart from the creature: what a
``Scene`` is, and the flat floor every other scene starts from.

A scene is a frozen dataclass (its fields are its parameters, so that a config
table can hold them) that writes its part of the MJCF document: assets, the
geoms under ``<worldbody>``, and the names of the geoms the creature may touch
(a :class:`SceneMJCF`). :mod:`locustjump.sim.model` puts it together with the
creature and writes one contact pair per (scene geom, creature geom); nothing
else collides. Sizes are given in body lengths of the creature, so a scene
scales with it. Scenes are known by name in :mod:`locustjump.sim.scene`,
which re-exports what is here.

A new scene (say seeded random boxes on the floor: :mod:`~.debris`) is a
subclass with its parameters as fields and a ``mjcf`` method, registered with
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
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from locustjump.ranges import INT64_MAX, Range
from locustjump.sim import names

#: ``seed`` of a seeded scene: one terrain each (the last of several terrains,
#: ``seed + terrains - 1``, too)
TERRAIN_SEED = Range(0, INT64_MAX, integer=True)


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
