"""The floor with a slab on it ahead of the creature (registered by its entry
point, ``slab = tinyplug.slab:Slab``)."""

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from locustjump.sim.scene import Flat, Scene, SceneMJCF


@dataclass(frozen=True)
class Slab(Scene):
    name: ClassVar[str] = "slab"
    height: float = 0.05  # (body lengths)

    def mjcf(self, body_length: float) -> SceneMJCF:
        floor = Flat().mjcf(body_length)
        h = self.height * body_length / 2
        slab = (f'<geom name="slab" type="box" pos="{body_length} 0 {h}" '
                f'size="{body_length / 2} {body_length} {h}" contype="0" '
                'conaffinity="0" rgba="0.5 0.4 0.3 1"/>')  # fmt: skip
        return SceneMJCF(floor.assets, floor.worldbody + slab, (*floor.geoms, "slab"))

    def heights(self, x, y, body_length: float) -> np.ndarray:
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        on = (abs(x - body_length) <= body_length / 2) & (abs(y) <= body_length)
        return np.where(on, self.height * body_length, 0.0)
