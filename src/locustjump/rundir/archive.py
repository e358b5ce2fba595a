"""``archive.npz``: a quality-diversity run's repertoire, the elites of its
grid archive (:class:`~locustjump.evo.archive.Archive`) after the last
generation, sorted by cell; plain arrays, read back only once each is what
was written and of this run's grid (its ``config.toml``)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from locustjump.errors import UserError, setting_ref
from locustjump.evo import Archive, QDParams
from locustjump.rundir.arrays import genomes, plain, scalar
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.files import save_npz
from locustjump.rundir.layout import ARCHIVE, CONFIG, FORMAT
from locustjump.rundir.migrations import npz_format
from locustjump.rundir.reads import load_npz

_KEYS = (
    "format", "behaviour", "config_hash", "names", "lows", "highs", "dims",
    "index", "solution", "objective", "measures", "generation",
)  # fmt: skip


def write_archive(path: Path, cfg: TrainConfig, archive: Archive) -> None:
    """The elites of run ``cfg``'s archive, in cell order."""
    a = archive.in_cell_order()
    save_npz(
        path,
        format=np.array(FORMAT),
        behaviour=np.array(cfg.behaviour),
        config_hash=np.array(cfg.hash()),
        names=np.array(a.names),
        lows=a.lows,
        highs=a.highs,
        dims=np.array(a.dims, dtype=np.int64),
        index=a.index,
        solution=a.solution,
        objective=a.objective,
        measures=a.measures,
        generation=a.generation,
    )


def has_archive(cfg: TrainConfig) -> bool:
    """Whether run ``cfg`` keeps an archive (its optimizer is a QD one)."""
    return isinstance(cfg.optimizer, QDParams)


def read_archive(
    out: str | os.PathLike[str], cfg: TrainConfig, num_params: int
) -> Archive:
    """The archive of the run in directory ``out`` whose configuration is
    ``cfg`` (``UserError`` naming the file: missing, of another run or grid,
    an array not as written)."""
    path = Path(out) / ARCHIVE
    opt = cfg.optimizer
    if not isinstance(opt, QDParams):  # has_archive(cfg), as mypy narrows it
        raise UserError(
            f"{out}: a {opt.kind} run keeps no archive of elites "
            f"(train with {setting_ref('optimizer')} map-elites or cma-me)"
        )
    d, cells = len(opt.descriptors), int(np.prod(opt.cells))
    z = load_npz(path, _KEYS, max_bytes=(1 << 16) + cells * 8 * (num_params + d + 3))
    npz_format(z, path)
    plain(z, list(_KEYS), path)
    if (scalar(z, "behaviour", path, "U"), scalar(z, "config_hash", path, "U")) != (
        cfg.behaviour,
        cfg.hash(),
    ):
        raise UserError(f"{path}: belongs to another run than {Path(out) / CONFIG}")
    names = tuple(str(n) for n in np.asarray(z["names"]).reshape(-1))
    grid = (
        names,
        [float(x) for x in np.asarray(z["lows"]).reshape(-1)],
        [float(x) for x in np.asarray(z["highs"]).reshape(-1)],
        [int(x) for x in np.asarray(z["dims"]).reshape(-1)],
    )
    ours = (
        tuple(opt.descriptors),
        [float(r[0]) for r in opt.ranges],
        [float(r[1]) for r in opt.ranges],
        [int(c) for c in opt.cells],
    )
    if grid != ours:
        raise UserError(f"{path}: its grid is not the one {CONFIG} names")
    k = np.asarray(z["index"]).shape[0] if np.asarray(z["index"]).ndim == 1 else -1
    if not 0 <= k <= cells:
        raise UserError(f"{path}: index must be at most {cells} cells")
    for key in ("index", "generation"):
        if np.asarray(z[key]).dtype.kind not in "iu":
            raise UserError(f"{path}: {key} must be integers")
    try:
        return Archive(
            names,
            np.array(grid[1]),
            np.array(grid[2]),
            tuple(grid[3]),
            np.asarray(z["index"], dtype=np.int64),
            genomes(z, "solution", path, (k, num_params)),
            genomes(z, "objective", path, (k,)),
            genomes(z, "measures", path, (k, d)),
            np.asarray(z["generation"], dtype=np.int64),
        )
    except ValueError as e:
        raise UserError(f"{path}: {e}") from None
