"""One elite of a quality-diversity run's archive, read as a best genome is:
what ``evaluate`` and ``render --elite K`` / ``--cell I,J`` play."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from locustjump.errors import UserError, setting_ref
from locustjump.ranges import INT64_MAX, Range
from locustjump.rundir.archive import has_archive, read_archive
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.layout import ARCHIVE
from locustjump.rundir.run import BestGenome, load_run
from locustjump.tasks.base import Behaviour


@dataclass(frozen=True)
class Elite(BestGenome):
    """One elite of a run's archive, as ``best.npz``'s best genome is read
    (its ``fitness`` the archive's, ``generation`` the one that found it),
    with where it sits: its ``rank`` by fitness (0: the best), its ``cell``
    and its ``descriptors`` (``names``)."""

    rank: int = 0
    cell: tuple[int, ...] = ()
    names: tuple[str, ...] = ()
    descriptors: tuple[float, ...] = ()

    @property
    def label(self) -> str:
        return f"elite {self.rank} (cell {','.join(map(str, self.cell))})"


#: ``elite``: an elite's rank in its archive (0: the best)
ELITE = Range(0, INT64_MAX, integer=True)
#: each index of ``cell``: a cell of the descriptor grid, from 0
CELL_INDEX = Range(0, INT64_MAX, integer=True)


def load_elite(
    path: str | os.PathLike[str],
    *,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> tuple[TrainConfig, Behaviour, BestGenome]:
    """:func:`~locustjump.rundir.run.load_run`'s ``(TrainConfig, Behaviour,
    genome)``, the genome the ``elite``-th best of the run's archive or the
    elite in grid cell ``cell`` (an :class:`Elite`); neither given: the best
    genome (``best.npz``). ``UserError`` naming the option if that elite
    does not exist."""
    if elite is not None:
        elite = ELITE.check("elite", elite)
    if cell is not None:
        cell = tuple(CELL_INDEX.check("cell", i) for i in cell)
    cfg, beh, best = load_run(path)
    if elite is None and cell is None:
        return cfg, beh, best
    if elite is not None and cell is not None:
        raise UserError(
            f"{setting_ref('elite')} and {setting_ref('cell')}: give one of them"
        )
    option = (
        f"{setting_ref('elite')} {elite}"
        if cell is None
        else f"{setting_ref('cell')} {','.join(map(str, cell))}"
    )
    if not has_archive(cfg):
        raise UserError(
            f"{option}: {path} is a {cfg.optimizer.kind} run; only a quality-"
            "diversity run (map-elites, cma-me) keeps an archive of elites"
        )
    archive = read_archive(path, cfg, beh.controller.num_params)
    try:
        if cell is not None:
            i = archive.at_cell(tuple(cell))
        else:
            assert elite is not None  # one of the two, by the checks above
            i = archive.at_rank(elite)
    except IndexError as e:
        raise UserError(f"{option}: {e} ({Path(path) / ARCHIVE})") from None
    rank = int(np.flatnonzero(archive.ranked() == i)[0])
    return (
        cfg,
        beh,
        Elite(
            archive.solution[i],
            float(archive.objective[i]),
            int(archive.generation[i]),
            cfg.behaviour,
            cfg.hash(),
            rank,
            tuple(int(c) for c in archive.grid_index()[i]),
            archive.names,
            tuple(float(m) for m in archive.measures[i]),
        ),
    )
