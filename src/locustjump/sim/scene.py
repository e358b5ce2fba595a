"""The scenes by name, and the terrains a genome is scored on.

A scene is the world the creature stands in, apart from the creature
(:mod:`~.world`: what a ``Scene`` is, the MJCF pieces it writes, the flat
floor). Scenes are known by name (``register_scene``); ``flat`` is the
default, ``debris`` a seeded field of rubble (:mod:`~.debris`). A new scene
is a subclass with its parameters as fields and a ``mjcf`` method, registered
with ``@register_scene`` (another package's: :mod:`locustjump.plugins`); it
touches no creature code. :class:`Terrains`: the several terrains (seeds) of
one scene a genome is scored on, and how their fitness is combined.

The public names of :mod:`~.world` and :mod:`~.debris` are importable from here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from locustjump import plugins
from locustjump.ranges import INT64_MAX, Range, SettingTypeError, SettingValueError
from locustjump.sim.debris import MAX_BOXES as MAX_BOXES
from locustjump.sim.debris import MAX_CELLS as MAX_CELLS
from locustjump.sim.debris import MIN_EXTENT as MIN_EXTENT
from locustjump.sim.debris import Debris as Debris
from locustjump.sim.world import TERRAIN_SEED as TERRAIN_SEED
from locustjump.sim.world import Flat as Flat
from locustjump.sim.world import Scene as Scene
from locustjump.sim.world import SceneMJCF as SceneMJCF

#: Most terrains a genome may be scored on in training.
MAX_TERRAINS = 64
#: ``terrains``: how many a genome is scored on
TERRAINS = Range(1, MAX_TERRAINS, integer=True)

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
