"""A training run's files: config, genomes, checkpoint, metrics."""

from __future__ import annotations

import dataclasses
import hashlib
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from locustjump.errors import UserError
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.files import (
    atomic_write_text,
    load_npz,
    read_toml,
    save_npz,
    write_toml,
)
from locustjump.rundir.layout import (
    BEST,
    CONFIG,
    FORMAT,
    METRICS,
    METRICS_COLUMNS,
    is_run,
)
from locustjump.rundir.migrations import (
    STATE_PREFIX,
    checkpoint_optimizer,
    checkpoint_state,
    frozen_path,
    npz_format,
)
from locustjump.tasks import behaviour_class, get_behaviour

# --- config ---------------------------------------------------------------------


#: model fields that say how the creature is computed, not which creature it
#: is: a frozen run may differ from the run built on it in these (and in its
#: engine, which is the run's, not the creature's)
NUMERICAL_MODEL_FIELDS = ("substeps",)


def load_config(path: str | os.PathLike, *, behaviour: str = "kick"):
    """Read a (possibly partial) TOML config; missing keys take the defaults
    (``behaviour`` where the file names none)."""

    d = read_toml(Path(path))
    return TrainConfig.from_dict({"behaviour": behaviour, **d}, str(path))


def write_config(path: Path, cfg) -> None:
    header = (
        f"# locustjump run configuration (config hash {cfg.hash()}).\n"
        "# Edit a copy and pass it with --config to start a new run.\n"
    )
    write_toml(path, cfg.to_dict(), header)


# --- genomes --------------------------------------------------------------------


@dataclass(frozen=True)
class BestGenome:
    """The content of ``best.npz``."""

    genome: np.ndarray  # (num_params,)
    fitness: float
    generation: int
    behaviour: str
    config_hash: str

    def save(self, path: Path) -> None:
        save_npz(
            path,
            format=np.array(FORMAT),
            genome=self.genome,
            fitness=np.array(self.fitness),
            generation=np.array(self.generation),
            behaviour=np.array(self.behaviour),
            config_hash=np.array(self.config_hash),
        )

    @classmethod
    def load(cls, path: str | os.PathLike, num_params: int | None = None) -> BestGenome:
        """Read and check ``best.npz`` (``UserError`` naming the file if bad)."""
        path = Path(path)
        z = load_npz(
            path,
            ("format", "genome", "fitness", "generation", "behaviour", "config_hash"),
        )
        npz_format(z, path)
        try:
            best = cls(
                np.asarray(z["genome"], dtype=np.float64),
                float(z["fitness"]),
                int(z["generation"]),
                str(z["behaviour"]),
                str(z["config_hash"]),
            )
        except (TypeError, ValueError) as e:
            raise UserError(f"{path}: malformed genome file ({e})") from None
        if best.genome.ndim != 1 or not np.isfinite(best.genome).all():
            raise UserError(f"{path}: genome must be a finite 1-D array")
        if num_params is not None and best.genome.shape[0] != num_params:
            raise UserError(
                f"{path}: genome has {best.genome.shape[0]} genes, the "
                f"{best.behaviour} controller needs {num_params}"
            )
        return best


@dataclass(frozen=True)
class FrozenGenomes:
    """The frozen networks a behaviour builds on (``DIR/frozen.npz``).

    ``genomes`` (k, P) in the order of the behaviour's ``requires``;
    ``sources`` the run directories they came from and ``hashes`` those runs'
    config hashes (for the record: the run never reads them again).
    """

    behaviours: tuple[str, ...]
    genomes: np.ndarray
    sources: tuple[str, ...]
    hashes: tuple[str, ...]

    @property
    def digest(self) -> str:
        """16 hex digits identifying the genomes (``simple`` in ``config.toml``)."""
        data = np.ascontiguousarray(self.genomes, dtype="<f8").tobytes()
        return hashlib.sha256(data).hexdigest()[:16]

    @classmethod
    def from_runs(
        cls,
        required: tuple[str, ...],
        dirs: dict[str, Any],
        model,
        frozen_size: int | None = None,
    ) -> FrozenGenomes:
        """Best genomes of the runs ``dirs[name]`` for each name in ``required``;
        each must hold that behaviour, or a variant of it with the same network
        (e.g. a ``kick-apex`` run for the kick), and the creature ``model``
        (``UserError`` naming the directory otherwise)."""

        genomes, sources, hashes = [], [], []
        for name in required:
            if dirs.get(name) is None:
                raise UserError(
                    "this behaviour builds on "
                    + ", ".join(f"--{r} DIR" for r in required)
                    + f" (missing --{name})"
                )
            d = Path(dirs[name])
            cfg, _, best = load_run(d)
            variant = issubclass(behaviour_class(cfg.behaviour), behaviour_class(name))
            size = best.genome.size
            if not variant or size != (frozen_size or size):
                raise UserError(
                    f"--{name} {d}: holds a {cfg.behaviour!r} run, not {name!r}"
                    + (f" ({size} genes, not {frozen_size})" if variant else "")
                )
            # the same creature; how it is computed may differ: the engine
            # (not compared: frozen networks evolved on NumPy run as well
            # compiled, within a few ulp a step) and the physics substeps (a network
            # evolved at 3 may be composed at 6, docs/science.md)
            free = dict.fromkeys(NUMERICAL_MODEL_FIELDS)
            free = {k: getattr(model, k) for k in free}
            if dataclasses.replace(cfg.model, **free) != model:
                ours = cfg.replace(model=model).to_dict()["model"]
                diff = [
                    k
                    for k, v in cfg.to_dict()["model"].items()
                    if ours[k] != v and k not in free
                ]
                raise UserError(
                    f"--{name} {d}: its model parameters differ from this run's "
                    f"({', '.join(diff)})"
                )
            genomes.append(best.genome)
            sources.append(str(d))
            hashes.append(best.config_hash)
        return cls(tuple(required), np.stack(genomes), tuple(sources), tuple(hashes))

    def save(self, path: Path) -> None:
        save_npz(
            path,
            format=np.array(FORMAT),
            behaviours=np.array(self.behaviours),
            genomes=self.genomes,
            sources=np.array(self.sources),
            hashes=np.array(self.hashes),
        )

    @classmethod
    def load(cls, path: Path, required: tuple[str, ...], num_params: int):
        z = load_npz(path, ("format", "behaviours", "genomes", "sources", "hashes"))
        npz_format(z, path)
        if tuple(str(b) for b in z["behaviours"]) != tuple(required):
            raise UserError(f"{path}: not the genomes of {', '.join(required)}")
        g = np.asarray(z["genomes"], dtype=np.float64)
        if g.shape != (len(required), num_params) or not np.isfinite(g).all():
            raise UserError(
                f"{path}: genomes must be finite, shape ({len(required)}, {num_params})"
            )
        return cls(
            tuple(required),
            g,
            tuple(str(x) for x in z["sources"]),
            tuple(str(x) for x in z["hashes"]),
        )


def behaviour_of(cfg, out: Path):
    """The behaviour of the run in ``out``; one built on frozen runs reads
    their genomes (``frozen.npz``) and checks them against the config."""

    cls = behaviour_class(cfg.behaviour)
    if not cls.requires:
        return get_behaviour(cfg.behaviour, None, cfg.options, cfg.scene)
    path = frozen_path(out)
    frozen = FrozenGenomes.load(path, cls.requires, cls.frozen_num_params())
    if frozen.digest != cfg.frozen_digest:
        raise UserError(
            f"{path}: its genomes (digest {frozen.digest}) are not the ones "
            f"{out / CONFIG} names ({cfg.frozen_digest or 'none'})"
        )
    return get_behaviour(cfg.behaviour, frozen.genomes, cfg.options, cfg.scene)


def load_run(path: str | os.PathLike):
    """``(TrainConfig, Behaviour, BestGenome)`` of run directory ``path``."""
    out = Path(path)
    if not out.is_dir():
        raise UserError(f"{out}: no such directory")
    if not is_run(out):
        raise UserError(f"{out}: holds no run (no {CONFIG})")
    cfg = load_config(out / CONFIG)
    beh = behaviour_of(cfg, out)
    if not (out / BEST).is_file():
        raise UserError(f"{out}: no {BEST} yet (the run has not finished a generation)")
    best = BestGenome.load(out / BEST, beh.controller.num_params)
    if best.behaviour != cfg.behaviour or best.config_hash != cfg.hash():
        raise UserError(
            f"{out / BEST}: belongs to another run ({best.behaviour}, hash "
            f"{best.config_hash}; {CONFIG}: {cfg.behaviour}, hash {cfg.hash()})"
        )
    return cfg, beh, best


# --- checkpoint -----------------------------------------------------------------

_CHECKPOINT_KEYS = (
    "format",
    "behaviour",
    "config_hash",
    "best_genome",
    "best_fitness",
    "best_generation",
    "metrics_row",
)


def write_checkpoint(
    path: Path, cfg, best: BestGenome, metrics_row: str, state: dict[str, np.ndarray]
) -> None:
    """The optimizer's ``state`` plus the run's best genome and the metrics row
    of the checkpointed generation (a kill between two writes loses nothing)."""
    save_npz(
        path,
        format=np.array(FORMAT),
        behaviour=np.array(cfg.behaviour),
        config_hash=np.array(cfg.hash()),
        optimizer=np.array(cfg.optimizer.kind),
        best_genome=best.genome,
        best_fitness=np.array(best.fitness),
        best_generation=np.array(best.generation),
        metrics_row=np.array(metrics_row),
        **{STATE_PREFIX + k: v for k, v in state.items()},
    )


def read_checkpoint(path: Path, cfg, num_params: int):
    """``(best, metrics_row, state)`` of ``checkpoint.npz``, checked against the
    configuration ``cfg`` (``UserError`` naming the file); older checkpoints
    through :mod:`~locustjump.rundir.migrations`."""
    z = load_npz(path, _CHECKPOINT_KEYS)
    state = checkpoint_state(z, path)
    if str(z["behaviour"]) != cfg.behaviour:
        raise UserError(
            f"{path}: holds a {str(z['behaviour'])!r} run, not {cfg.behaviour!r}"
        )
    kind = checkpoint_optimizer(z)
    if kind != cfg.optimizer.kind:
        raise UserError(
            f"{path}: was written by the {kind!r} optimizer, the run's "
            f"{CONFIG} names {cfg.optimizer.kind!r}"
        )
    if str(z["config_hash"]) != cfg.hash():
        raise UserError(
            f"{path}: was written by another configuration (hash "
            f"{z['config_hash']}, {CONFIG} has {cfg.hash()})"
        )
    best = BestGenome(
        np.asarray(z["best_genome"], dtype=np.float64),
        float(z["best_fitness"]),
        int(z["best_generation"]),
        cfg.behaviour,
        cfg.hash(),
    )
    if best.genome.shape != (num_params,):
        raise UserError(f"{path}: best_genome has the wrong length")
    return best, str(z["metrics_row"]), state


# --- metrics ----------------------------------------------------------------------


def read_metrics(path: Path) -> np.ndarray:
    """metrics.csv as a structured array (one record per generation)."""
    try:
        return np.atleast_1d(
            np.genfromtxt(path, delimiter=",", names=True, dtype=None, ndmin=1)
        )
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: not a readable metrics file ({e})") from None


def generations_done(run: Path) -> int:
    m = read_metrics(Path(run) / METRICS)
    return int(m["generation"][-1]) if len(m) else 0


def metrics_line(
    row: list, wall: float, rate: float, diagnostics: Sequence[float] = ()
) -> str:
    """One row of metrics.csv: ``row`` is generation, best, mean, std,
    evaluations, control steps; ``diagnostics`` the optimizer's extra columns."""
    g, best, mean, std, evaluations, steps = row
    cols = [g, best, mean, std, round(wall, 4), evaluations, steps, round(rate, 1)]
    return ",".join(map(str, [*cols, *diagnostics])) + "\n"


def metrics_extra_columns(path: Path) -> tuple[str, ...] | None:
    """The optimizer's columns after :data:`METRICS_COLUMNS` in the header of
    metrics.csv ``path``; ``None`` if it has no such header (absent, empty,
    damaged). Files written before diagnostics existed have none: ``()``."""
    try:
        with open(path) as f:
            first = f.readline()
    except FileNotFoundError:
        return None
    names = tuple(first.strip().split(","))
    n = len(METRICS_COLUMNS)
    return names[n:] if first.endswith("\n") and names[:n] == METRICS_COLUMNS else None


def truncate_metrics(
    path: Path, generation: int, last_row: str, extra: Sequence[str] = ()
) -> None:
    """Keep the header (:data:`METRICS_COLUMNS` and the optimizer's ``extra``
    columns) and the rows of generations 1..``generation``; the row of
    ``generation`` itself is ``last_row`` (from the checkpoint) if missing."""
    lines = path.read_text().splitlines(keepends=True) if path.exists() else []
    header = ",".join((*METRICS_COLUMNS, *extra)) + "\n"
    keep = []
    for n, ln in enumerate(lines[1:], start=2):
        if not ln.strip():
            continue
        try:
            g = int(ln.split(",")[0])
        except ValueError:
            raise UserError(f"{path}: line {n} is malformed: {ln.strip()!r}") from None
        if g <= generation and ln.endswith("\n"):
            keep.append(ln)
    if generation > 0 and len(keep) == generation - 1:
        keep.append(last_row)
    if len(keep) != generation:
        raise UserError(
            f"{path}: holds {len(keep)} rows for the {generation} generations of "
            f"the checkpoint"
        )
    atomic_write_text(path, header + "".join(keep))
