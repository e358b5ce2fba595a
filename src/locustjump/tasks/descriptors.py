"""Behaviour descriptors: what a task says about *how* an episode went, beside
its fitness (how well), for quality diversity (:mod:`locustjump.evo.qd`).

A task declares its descriptors (:class:`Descriptor`: name, unit, the range a
grid archive spans) in ``Behaviour.descriptors`` and in its docstring spec,
and computes them in ``Behaviour.episode_descriptors`` from the records its
fitness reads (``Behaviour.record``); :func:`describe` turns them into one
row per controller, as ``Behaviour.fitness`` turns episode fitness into one
number per controller.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Descriptor:
    """One behaviour descriptor a task declares.

    ``low``/``high``: the range a grid archive spans by default (values
    outside fall into its edge cells), in ``unit``.
    """

    name: str
    low: float
    high: float
    unit: str
    doc: str

    def __post_init__(self) -> None:
        if not (np.isfinite(self.low) and np.isfinite(self.high)):
            raise ValueError(f"descriptor {self.name}: range must be finite")
        if not self.low < self.high:
            raise ValueError(f"descriptor {self.name}: low must be below high")


def describe(
    per_episode: Mapping[str, np.ndarray],
    declared: Sequence[Descriptor],
    names: Sequence[str],
    unstable: np.ndarray,
    per_controller: int,
    terrains: int = 1,
) -> np.ndarray:
    """``(n, len(names))`` descriptors per controller.

    ``per_episode`` maps each declared name to its ``(E,)`` values, episodes
    terrain-major then controller-major (as ``Behaviour.evaluate`` concatenates
    them), ``per_controller`` start states each. An unstable episode counts
    at each descriptor's ``low`` (as its fitness counts as the task's worst);
    a controller's value is the mean over its start states, then over
    ``terrains``. ``ValueError`` naming an unknown descriptor.
    """
    by_name = {d.name: d for d in declared}
    unknown = [n for n in names if n not in by_name]
    if unknown:
        raise ValueError(
            f"unknown descriptor {unknown[0]!r}; the task declares "
            f"{', '.join(by_name) or 'none'}"
        )
    cols = []
    for name in names:
        v = np.where(unstable, by_name[name].low, per_episode[name])
        v = v.reshape(terrains, -1, per_controller).mean(axis=2).mean(axis=0)
        cols.append(v)
    return np.stack(cols, axis=1)
