"""A quality-diversity run's repertoire shown: its archive's heatmap, and a
composition over it (the elites its switcher chooses among, and what it
chooses over an episode)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.present.plots import archive_heatmap, repertoire_composition_figure
from locustjump.rundir.config import TrainConfig
from locustjump.sim.engine.backends import Backend
from locustjump.tasks import ComposedRepertoire, behaviour_class


def archive_figure(out: Path, into: Path | None = None) -> Path | None:
    """``DIR/archive.png`` (or ``into/archive.png``) from ``DIR/archive.npz``:
    the elites' fitness over the descriptor grid (None: the run keeps no
    archive, or none yet)."""
    cfg = rundir.load_config(out / rundir.CONFIG)
    if not rundir.has_archive(cfg) or not (out / rundir.ARCHIVE).exists():
        return None
    beh = rundir.behaviour_of(cfg, out)
    archive = rundir.read_archive(out, cfg, beh.controller.num_params)
    path = (out if into is None else into) / rundir.ARCHIVE_PNG
    units = {d.name: d.unit for d in behaviour_class(cfg.behaviour).descriptors}
    title = f"{cfg.behaviour}, {cfg.optimizer.kind} (seed {cfg.seed})"
    archive_heatmap(path, archive, units=units, title=title,
                    qd_offset=_offset(cfg))  # fmt: skip
    return path


def _offset(cfg: TrainConfig) -> float:
    """The run's QD score offset (``[optimizer] qd_offset``; 0 for others)."""
    return float(getattr(cfg.optimizer, "qd_offset", 0.0))


def composition_figure(
    kick_run: str | os.PathLike[str],
    composed_run: str | os.PathLike[str],
    path: str | os.PathLike[str],
    *,
    backend: Backend | None = None,
) -> Path:
    """``path``, a PNG of a composition over a repertoire: the archive of the
    quality-diversity kick run ``kick_run`` with the elites that the
    ``composed-repertoire`` run ``composed_run`` chooses among marked, and
    one episode of that run's best switcher (its first start state): the
    body's height and the behaviour chosen at each control step
    (:func:`~locustjump.present.plots.repertoire_composition_figure`).
    ``UserError`` naming the directory if ``composed_run`` is not a
    composition over a repertoire or does not compose ``kick_run``'s best
    elites; nothing is written then."""
    kick, composed = Path(kick_run), Path(composed_run)
    cfg, beh, best = rundir.load_run(composed)
    if not isinstance(beh, ComposedRepertoire):
        raise UserError(
            f"{composed}: a {cfg.behaviour} run, not a composition over a "
            f"repertoire ({ComposedRepertoire.name})"
        )
    kick_cfg, kick_beh, _ = rundir.load_run(kick)
    archive = rundir.read_archive(kick, kick_cfg, kick_beh.controller.num_params)
    k = cfg.options.elites
    chosen = archive.ranked()[:k]
    frozen = rundir.frozen_of(cfg, composed)
    assert frozen is not None  # a composition builds on frozen networks
    if len(chosen) < k or not np.array_equal(
        frozen.genomes[:k], archive.solution[chosen]
    ):
        raise UserError(
            f"{composed}: its {k} kick networks are not the {k} best elites of "
            f"{kick}'s archive"
        )
    fit, res = beh.evaluate(
        best.genome[None], cfg.model, backend=backend, engine=cfg.engine,
        record=("qpos", "memory"), label=f"evaluate {cfg.behaviour}",
    )  # fmt: skip
    units = {d.name: d.unit for d in behaviour_class(kick_cfg.behaviour).descriptors}
    out = Path(path)
    repertoire_composition_figure(
        out,
        archive,
        chosen,
        res["qpos"][0, :, 2],
        res["memory"][0, 1:, 0].astype(int),
        tuple(beh.memory_labels or ()),  # a repertoire's switcher names its own
        units=units,
        title=(
            f"its best switcher (Eq. 4 = {float(fit[0]):.0f}) choosing among "
            f"{k} kick elites, getup and return-legs"
        ),
        suptitle=f"{kick} and {composed}",
        qd_offset=_offset(kick_cfg),
    )
    return out
