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
``@register_scene``; it touches no creature code. Its geoms inherit the
world's contact model (``contype="0" conaffinity="0"``: only the pairs
collide); each geom it lists in ``SceneMJCF.geoms`` gets one pair per
creature geom, so the number of pairs is their product. The solver takes the
contacts in the pairs' order: MuJoCo sorts the pairs by body (a scene's static
geoms are all the world body's), and within one creature body they follow that
list, each scene geom against the body's geoms in turn.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar

from locustjump.sim import names


@dataclass(frozen=True)
class SceneMJCF:
    """A scene's pieces of one MJCF document, each a fragment of XML."""

    assets: str  #: children of ``<asset>``: textures, materials
    worldbody: str  #: children of ``<worldbody>``: its geoms (static bodies)
    geoms: tuple[str, ...]  #: geoms the creature may touch, in pair order


@dataclass(frozen=True)
class Scene(ABC):
    """A world for the creature: its fields are its parameters."""

    name: ClassVar[str]  #: the name it is registered and configured by

    @abstractmethod
    def mjcf(self, body_length: float) -> SceneMJCF:
        """This scene's MJCF for a creature ``body_length`` metres long."""


@dataclass(frozen=True)
class Flat(Scene):
    """An infinite flat floor (a plane at z = 0) with a checker texture."""

    name: ClassVar[str] = "flat"

    def mjcf(self, body_length: float) -> SceneMJCF:
        """The floor: a plane whose grid lines are 0.05 body length apart."""
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
                f'<geom name="{names.FLOOR}" type="plane" '
                f'size="0 0 {0.05 * body_length:.9g}" material="grid"/>'
            ),
            geoms=(names.FLOOR,),
        )


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


def scene_names() -> tuple[str, ...]:
    """Every registered scene's name."""
    return tuple(_REGISTRY)


def scene_class(name: str) -> type[Scene]:
    """The class registered as ``name`` (``ValueError`` if there is none)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ValueError(
            f"unknown scene {name!r}; choose from {', '.join(_REGISTRY)}"
        ) from None
