"""``metrics.csv``: one row per generation, read strictly, written by appending.

A row is :data:`~.layout.METRICS_COLUMNS` and then the optimizer's columns
that the header names; every cell is a number (generation, evaluations and
control steps integers), the columns of :data:`~.layout.METRICS_COLUMNS`
finite, and the generations 1, 2, 3, ... in order. A last line without its
newline is a write cut short (a kill, a full disk): readers leave it out,
and a resumed run replaces it with the checkpoint's row.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from locustjump.errors import UserError
from locustjump.rundir.files import atomic_write_text
from locustjump.rundir.layout import CHECKPOINT, METRICS, METRICS_COLUMNS
from locustjump.rundir.reads import open_regular, read_bytes
from locustjump.sim.resources import require_memory

#: integer columns (the others are floats)
_INTEGERS = ("generation", "evaluations", "control_steps")
#: how many times the file's size parsing it takes, at most (for the memory check)
_PARSE_FACTOR = 16
#: the largest metrics.csv read: about 500,000 generations (a row is about
#: 120 bytes; the paper's runs have 1,000)
MAX_METRICS_BYTES = 64 << 20


def _lines(path: Path) -> list[str]:
    """The complete lines of ``path`` (``[]`` if absent), read only if it is a
    regular file, and at most :data:`MAX_METRICS_BYTES` of it."""
    if not os.path.lexists(path):
        return []
    data = read_bytes(path, "metrics file", MAX_METRICS_BYTES)
    require_memory(len(data) * _PARSE_FACTOR, f"{path}")
    try:
        text = data.decode()
    except UnicodeDecodeError:
        raise UserError(f"{path}: not a metrics file (not UTF-8 text)") from None
    lines = text.splitlines(keepends=True)
    if lines and not lines[-1].endswith("\n"):
        lines.pop()  # cut short: the checkpoint holds that row
    return lines


def _header(path: Path, line: str) -> tuple[str, ...]:
    names = tuple(line.strip().split(","))
    n = len(METRICS_COLUMNS)
    if names[:n] != METRICS_COLUMNS or len(set(names)) != len(names):
        raise UserError(
            f"{path}: line 1 must name the columns {','.join(METRICS_COLUMNS)} "
            f"(then the optimizer's), got {line.strip()[:80]!r}"
        )
    return names


def parse_row(
    line: str, names: Sequence[str], where: str, generation: int | None = None
) -> tuple[float | int, ...]:
    """The numbers of one row of ``names`` (``where``: the file and line, for
    the error); ``generation``: what its first column must be."""
    cells = line.strip().split(",")
    if len(cells) != len(names):
        raise UserError(
            f"{where}: {len(cells)} columns, the header names {len(names)}: "
            f"{line.strip()[:80]!r}"
        )
    values: list[float | int] = []
    for name, cell in zip(names, cells, strict=True):
        try:
            v = int(cell) if name in _INTEGERS else float(cell)
        except ValueError:
            kind = "an integer" if name in _INTEGERS else "a number"
            raise UserError(
                f"{where}: {name} must be {kind}, got {cell[:40]!r}"
            ) from None
        if name in METRICS_COLUMNS and not math.isfinite(v):
            raise UserError(f"{where}: {name} must be finite, got {cell!r}")
        if name in _INTEGERS and v < 0:
            raise UserError(f"{where}: {name} must be >= 0, got {v}")
        values.append(v)
    if generation is not None and values[0] != generation:
        raise UserError(f"{where}: generation {values[0]}, expected {generation}")
    return tuple(values)


Row = tuple[float | int, ...]


def _rows(path: Path) -> tuple[tuple[str, ...], list[str], list[Row]]:
    """Header names, the row lines and their numbers (checked)."""
    lines = _lines(path)
    if not lines:
        return (), [], []
    names = _header(path, lines[0])
    texts: list[str] = []
    rows: list[Row] = []
    for n, ln in enumerate(lines[1:], start=2):
        if not ln.strip():
            continue
        rows.append(parse_row(ln, names, f"{path}: line {n}", len(rows) + 1))
        texts.append(ln)
    return names, texts, rows


def read_metrics(path: str | os.PathLike[str]) -> np.ndarray:
    """metrics.csv as a structured array, one record per generation (empty
    if the file is absent or holds no row); ``UserError`` naming the file
    and line of anything malformed."""
    path = Path(path)
    names, _, rows = _rows(path)
    dtype = [(k, np.int64 if k in _INTEGERS else np.float64) for k in names]
    return np.array(rows, dtype=dtype) if rows else np.zeros(0, dtype=dtype)


def generations_done(run: str | os.PathLike[str]) -> int:
    m = read_metrics(Path(run) / METRICS)
    return int(m["generation"][-1]) if len(m) else 0


def metrics_line(
    row: Sequence[float], wall: float, rate: float, diagnostics: Sequence[float] = ()
) -> str:
    """One row of metrics.csv: ``row`` is generation, best, mean, std,
    evaluations, control steps; ``diagnostics`` the optimizer's extra columns."""
    g, best, mean, std, evaluations, steps = row
    cols = [g, best, mean, std, round(wall, 4), evaluations, steps, round(rate, 1)]
    return ",".join(map(str, [*cols, *diagnostics])) + "\n"


def metrics_extra_columns(path: Path) -> tuple[str, ...] | None:
    """The optimizer's columns after :data:`METRICS_COLUMNS` in the header of
    metrics.csv ``path``; ``None`` if it has no such header (absent, empty,
    damaged); ``UserError`` if it is not a regular file. Files written before
    diagnostics existed have none: ``()``."""
    if not os.path.lexists(path):
        return None
    with open_regular(path, "metrics file") as f:
        try:
            first = f.readline(4096).decode()
        except (OSError, UnicodeDecodeError):
            return None
    names = tuple(first.strip().split(","))
    n = len(METRICS_COLUMNS)
    return names[n:] if first.endswith("\n") and names[:n] == METRICS_COLUMNS else None


#: columns a resumed run recomputes identically (the others are wall time)
_SAME = ("generation", "best", "mean", "std", "evaluations", "control_steps")


def truncate_metrics(
    path: Path, generation: int, last_row: str, extra: Sequence[str] = ()
) -> None:
    """Keep the header (:data:`METRICS_COLUMNS` and the optimizer's ``extra``
    columns) and the rows of generations 1..``generation``; the row of
    ``generation`` itself is ``last_row`` (from the checkpoint) if missing.
    Every row is checked first, and must agree with ``last_row``; rows
    beyond ``generation`` are refused (the checkpoint is written before its
    row: more rows than it holds mean it was lost or replaced)."""
    names = (*METRICS_COLUMNS, *extra)
    found, texts, rows = _rows(path)
    if len(texts) > generation:
        has = f"holds only {generation}" if generation else "is missing"
        raise UserError(
            f"{path}: holds {len(texts)} generations but {CHECKPOINT} {has} "
            "(nothing changed)"
        )
    if found and found != names:
        raise UserError(
            f"{path}: its columns {','.join(found)} are not the run's {','.join(names)}"
        )
    keep = texts[:generation]
    if generation > 0:
        # the checkpoint's row, with the optimizer's columns it was written with
        n = max(len(last_row.split(",")), len(METRICS_COLUMNS))
        own = (*METRICS_COLUMNS, *(f"column {i}" for i in range(9, n + 1)))
        where = f"{path}: the checkpoint's row"
        mine = parse_row(last_row, own, where, generation)
        if len(keep) == generation - 1:
            if len(own) != len(names):
                raise UserError(f"{where} has {len(own)} columns, not {len(names)}")
            keep.append(last_row)
        elif len(keep) == generation:
            theirs = rows[generation - 1]
            same = [names.index(k) for k in _SAME]
            if [theirs[i] for i in same] != [mine[i] for i in same]:
                raise UserError(
                    f"{path}: the row of generation {generation} is not the "
                    "checkpoint's (another run's metrics?)"
                )
    if len(keep) != generation:
        raise UserError(
            f"{path}: holds {len(keep)} rows for the {generation} generations of "
            f"the checkpoint"
        )
    atomic_write_text(path, ",".join(names) + "\n" + "".join(keep))
