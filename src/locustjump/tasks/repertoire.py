"""Behaviour Composed over a repertoire (beyond the paper): the composed
behaviour's switcher chooses among the best elites of a kick *repertoire*
(a quality-diversity run's archive, :mod:`locustjump.evo.qd`) and the get-up
and return-legs networks, instead of the paper's one kick network.

* controller: the 9-10-N switcher of :mod:`.composed` (sigmoid outputs; every
  ``switch_every`` control steps the largest takes control), over ``N =
  elites + 2`` frozen 9-10-4 networks: output ``i < elites`` plays the
  kick archive's ``i``-th best elite (``locustjump render --elite i`` of that
  run), then get-up, then return-legs;
* start, episode and fitness: the composed behaviour's (Eq. 4; on a terrain
  with progress), unchanged.

Why a switcher over elites and not one that outputs a target descriptor and
plays the nearest elite: the paper's switcher picks a behaviour by its
largest output, and this keeps that rule, its compiled kernel and its
evolution as they are, with only the output layer widened; a descriptor
target would add a continuous map whose nearest-elite lookup makes the
fitness piecewise constant in the switcher's genes over the grid's cells.
Its elites are the best ``elites`` by kick fitness (ties: the lower cell);
how many is a setting (``[options] elites``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from locustjump.ranges import Range
from locustjump.sim.controller import Controller
from locustjump.sim.scene import Terrains
from locustjump.tasks.base import option
from locustjump.tasks.composed import (
    SIMPLE,
    Composed,
    SwitchingController,
    SwitchOptions,
)

#: the kick elites a repertoire's composition takes unless told otherwise
DEFAULT_ELITES = 8
#: at most (the switcher computes every frozen network each control step)
MAX_ELITES = 64


@dataclass(frozen=True)
class RepertoireOptions(SwitchOptions):
    """The settings of the composition over a repertoire (``[options]``)."""

    #: the kick archive's best elites the switcher chooses among
    elites: int = option(
        DEFAULT_ELITES,
        "the kick repertoire's best elites the switcher "
        f"chooses among, with getup and return-legs (default {DEFAULT_ELITES})",
        "K",
        Range(1, MAX_ELITES, integer=True),
    )  # checked with the others' ranges (SwitchOptions' check_settings)


class ComposedRepertoire(Composed):
    """Beyond the paper: the composed switcher over a kick repertoire's best
    elites, get-up and return-legs; builds on a quality-diversity kick run."""

    name = "composed-repertoire"
    Options = RepertoireOptions

    def __init__(
        self,
        frozen: np.ndarray | None = None,
        options: Any = None,
        terrains: Terrains | None = None,
    ):
        super().__init__(frozen, options, terrains)
        k = self.options.elites
        self.memory_labels = (*(f"kick elite {i}" for i in range(k)), *SIMPLE[1:])

    @classmethod
    def frozen_elites(cls, options: Any = None) -> dict[str, int]:
        k = (options or cls.Options()).elites
        return {SIMPLE[0]: k}

    @property
    def controller(self) -> Controller:
        n = self.options.elites + len(SIMPLE) - 1
        if self.frozen is None or len(self.frozen) != n:
            raise ValueError(
                f"the composition over a repertoire needs {n} frozen genomes: "
                f"{self.options.elites} kick elites, getup and return-legs"
            )
        return SwitchingController(
            self.frozen, every=self.options.switch_every, networks=n
        )


__all__ = ["ComposedRepertoire", "RepertoireOptions"]
