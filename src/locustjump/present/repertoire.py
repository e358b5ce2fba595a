"""A quality-diversity run's repertoire shown: its archive's heatmap, and the
one elite that ``evaluate`` and ``render`` play (``--elite K``, ``--cell
i,j``) in place of the best genome."""

from __future__ import annotations

from pathlib import Path

from locustjump import rundir
from locustjump.present.plots import archive_heatmap
from locustjump.tasks import behaviour_class


def archive_figure(out: Path) -> Path | None:
    """``DIR/archive.png`` from ``DIR/archive.npz``: the elites' fitness over
    the descriptor grid (None: the run keeps no archive, or none yet)."""
    cfg = rundir.load_config(out / rundir.CONFIG)
    if not rundir.has_archive(cfg) or not (out / rundir.ARCHIVE).exists():
        return None
    beh = rundir.behaviour_of(cfg, out)
    archive = rundir.read_archive(out, cfg, beh.controller.num_params)
    path = out / rundir.ARCHIVE_PNG
    units = {d.name: d.unit for d in behaviour_class(cfg.behaviour).descriptors}
    title = f"{cfg.behaviour}, {cfg.optimizer.kind} (seed {cfg.seed})"
    archive_heatmap(path, archive, units=units, title=title)
    return path
