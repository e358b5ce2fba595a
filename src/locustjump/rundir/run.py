"""A training run's files: config, genomes, checkpoint, metrics."""

from __future__ import annotations

import dataclasses
import hashlib
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from locustjump.errors import UserError, setting_ref
from locustjump.rundir.archive import has_archive, read_archive
from locustjump.rundir.arrays import genomes, scalar
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.files import save_npz, write_toml
from locustjump.rundir.layout import BEST, CONFIG, FORMAT, is_run
from locustjump.rundir.migrations import frozen_path, npz_format
from locustjump.rundir.reads import MAX_NPZ_BYTES, load_npz, read_toml
from locustjump.sim.params import LocustParams
from locustjump.tasks import behaviour_class, get_behaviour
from locustjump.tasks.base import Behaviour

# --- config ---------------------------------------------------------------------


#: model fields that say how the creature is computed, not which creature it
#: is: a frozen run may differ from the run built on it in these (and in its
#: engine, which is the run's, not the creature's)
NUMERICAL_MODEL_FIELDS = ("substeps",)


def load_config(
    path: str | os.PathLike[str], *, behaviour: str = "kick"
) -> TrainConfig:
    """Read a (possibly partial) TOML config; missing keys take the defaults
    (``behaviour`` where the file names none)."""

    d = read_toml(Path(path))
    return TrainConfig.from_dict({"behaviour": behaviour, **d}, str(path))


def write_config(path: Path, cfg: TrainConfig) -> None:
    header = (
        f"# locustjump run configuration (config hash {cfg.hash()}).\n"
        "# Edit a copy and pass it with --config to start a new run.\n"
    )
    write_toml(path, cfg.to_dict(), header)


# --- genomes --------------------------------------------------------------------

#: what a genome file holds beside its genomes, at most (bytes: headers, names)
_SMALL = 1 << 16


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
    def load(
        cls, path: str | os.PathLike[str], num_params: int | None = None
    ) -> BestGenome:
        """Read and check ``best.npz`` (``UserError`` naming the file if bad):
        a float64 genome of ``num_params`` finite genes, a finite fitness."""
        path = Path(path)
        z = load_npz(
            path,
            ("format", "genome", "fitness", "generation", "behaviour", "config_hash"),
            max_bytes=MAX_NPZ_BYTES if num_params is None else _SMALL + 8 * num_params,
        )
        npz_format(z, path)
        g = np.asarray(z["genome"])
        size = num_params if num_params is not None else (g.size if g.ndim else -1)
        if g.ndim == 1 and g.shape[0] != size:
            raise UserError(
                f"{path}: genome has {g.shape[0]} genes, the "
                f"{scalar(z, 'behaviour', path, 'U')} controller needs {num_params}"
            )
        best = cls(
            genomes(z, "genome", path, (size,)),
            scalar(z, "fitness", path, "f"),
            scalar(z, "generation", path, "i"),
            scalar(z, "behaviour", path, "U"),
            scalar(z, "config_hash", path, "U"),
        )
        if best.generation < 1:
            raise UserError(f"{path}: generation must be >= 1, got {best.generation}")
        return best


def frozen_setting(behaviour: str) -> str:
    """The setting naming the run of ``behaviour`` that another builds on
    (``frozen_return_legs``: the command line's ``--return-legs DIR``)."""
    return "frozen_" + behaviour.replace("-", "_")


@dataclass(frozen=True)
class FrozenGenomes:
    """The frozen networks a behaviour builds on (``DIR/frozen.npz``).

    ``genomes`` (k, P), one per name of ``behaviours``: the behaviour's
    ``requires`` in order, a run that gives several (the best elites of its
    archive: ``Behaviour.frozen_names``) repeated; ``sources`` the run
    directories they came from and ``hashes`` those runs' config hashes (for
    the record: the run never reads them again).
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
        model: LocustParams,
        frozen_size: int | None = None,
        elites: Mapping[str, int] | None = None,
    ) -> FrozenGenomes:
        """Best genomes of the runs ``dirs[name]`` for each name in ``required``;
        each must hold that behaviour, or a variant of it with the same network
        (e.g. a ``kick-apex`` run for the kick), and the creature ``model``
        (``UserError`` naming the directory otherwise). ``elites`` maps a name
        to how many genomes its run gives: the best elites of its archive (a
        quality-diversity run), best first, in place of its best genome."""

        elites = dict(elites or {})
        genomes, names, sources, hashes = [], [], [], []
        for name in required:
            if dirs.get(name) is None:
                raise UserError(
                    "this behaviour builds on "
                    + ", ".join(
                        f"{setting_ref(frozen_setting(r))} DIR" for r in required
                    )
                    + f" (missing {setting_ref(frozen_setting(name))})"
                )
            d = Path(dirs[name])
            cfg, beh, best = load_run(d)
            variant = issubclass(behaviour_class(cfg.behaviour), behaviour_class(name))
            size = best.genome.size
            if not variant or size != (frozen_size or size):
                raise UserError(
                    f"{setting_ref(frozen_setting(name))} {d}: holds a "
                    f"{cfg.behaviour!r} run, not {name!r}"
                    + (f" ({size} genes, not {frozen_size})" if variant else "")
                )
            # the same creature; how it is computed may differ: the engine
            # (not compared: frozen networks evolved on NumPy run as well
            # compiled, within a few ulp a step) and the physics substeps (a network
            # evolved at 3 may be composed at 6, docs/science.md)
            free: dict[str, Any] = dict.fromkeys(NUMERICAL_MODEL_FIELDS)
            free = {k: getattr(model, k) for k in free}
            if dataclasses.replace(cfg.model, **free) != model:
                ours = cfg.replace(model=model).to_dict()["model"]
                diff = [
                    k
                    for k, v in cfg.to_dict()["model"].items()
                    if ours[k] != v and k not in free
                ]
                raise UserError(
                    f"{setting_ref(frozen_setting(name))} {d}: its model parameters "
                    "differ from this run's "
                    f"({', '.join(diff)})"
                )
            taken = [best.genome]
            if name in elites:
                taken = _best_elites(d, cfg, beh, elites[name], name)
            genomes += taken
            names += [name] * len(taken)
            sources += [str(d)] * len(taken)
            hashes += [best.config_hash] * len(taken)
        return cls(tuple(names), np.stack(genomes), tuple(sources), tuple(hashes))

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
    def load(
        cls, path: Path, required: tuple[str, ...], num_params: int
    ) -> FrozenGenomes:
        """``frozen.npz`` of the genomes of runs ``required``, one name per
        genome (a run that gives several elites, :meth:`from_runs`, repeated)."""
        z = load_npz(
            path,
            ("format", "behaviours", "genomes", "sources", "hashes"),
            max_bytes=_SMALL + 8 * len(required) * num_params,
        )
        npz_format(z, path)
        k = len(required)
        for key in ("behaviours", "sources", "hashes"):
            a = z[key]
            if a.dtype.kind != "U" or a.shape != (k,):
                raise UserError(f"{path}: {key} must be {k} names")
        if tuple(str(b) for b in z["behaviours"]) != tuple(required):
            raise UserError(f"{path}: not the genomes of {', '.join(required)}")
        return cls(
            tuple(required),
            genomes(z, "genomes", path, (k, num_params)),
            tuple(str(x) for x in z["sources"]),
            tuple(str(x) for x in z["hashes"]),
        )


def _best_elites(
    d: Path, cfg: TrainConfig, beh: Behaviour, k: int, name: str
) -> list[np.ndarray]:
    """The ``k`` best elites of run ``d``'s archive (``UserError`` if it
    keeps none, or fewer)."""
    if not has_archive(cfg):
        raise UserError(
            f"{setting_ref(frozen_setting(name))} {d}: a {cfg.optimizer.kind} "
            f"run; the composition takes {k} elites of a quality-diversity run's "
            "archive (map-elites, cma-me)"
        )
    archive = read_archive(d, cfg, beh.controller.num_params)
    if len(archive) < k:
        raise UserError(
            f"{setting_ref(frozen_setting(name))} {d}: its archive holds "
            f"{len(archive)} elites; the composition takes {k} "
            f"({setting_ref('option_elites')})"
        )
    return [archive.solution[i] for i in archive.ranked()[:k]]


def frozen_of(cfg: TrainConfig, out: Path) -> FrozenGenomes | None:
    """The frozen genomes the run in ``out`` builds on (``frozen.npz``),
    checked against its config; None for a behaviour built on none."""

    cls = behaviour_class(cfg.behaviour)
    if not cls.requires:
        return None
    path = frozen_path(out)
    names = cls.frozen_names(cfg.options)
    frozen = FrozenGenomes.load(path, names, cls.frozen_num_params())
    if frozen.digest != cfg.frozen_digest:
        raise UserError(
            f"{path}: its genomes (digest {frozen.digest}) are not the ones "
            f"{out / CONFIG} names ({cfg.frozen_digest or 'none'})"
        )
    return frozen


def behaviour_of(cfg: TrainConfig, out: Path) -> Behaviour:
    """The behaviour of the run in ``out``; one built on frozen runs reads
    their genomes (:func:`frozen_of`)."""

    frozen = frozen_of(cfg, out)
    genomes = None if frozen is None else frozen.genomes
    return get_behaviour(cfg.behaviour, genomes, cfg.options, cfg.scene)


def load_run(
    path: str | os.PathLike[str],
) -> tuple[TrainConfig, Behaviour, BestGenome]:
    """``(TrainConfig, Behaviour, BestGenome)`` of run directory ``path``."""
    out = Path(path)
    if not out.is_dir():
        raise UserError(f"{out}: no such directory")
    if not is_run(out):
        raise UserError(f"{out}: holds no run (no {CONFIG})")
    cfg = load_config(out / CONFIG)
    beh = behaviour_of(cfg, out)
    return cfg, beh, load_best(out, cfg, beh.controller.num_params)


def load_best(out: Path, cfg: TrainConfig, num_params: int) -> BestGenome:
    """``best.npz`` of run directory ``out`` (configuration ``cfg``, genomes
    of ``num_params`` genes), checked (:meth:`BestGenome.load`) and of this
    run: its behaviour and config hash, a generation within the budget."""
    if not os.path.lexists(out / BEST):
        raise UserError(f"{out}: no {BEST} yet (the run has not finished a generation)")
    best = BestGenome.load(out / BEST, num_params)
    if best.behaviour != cfg.behaviour or best.config_hash != cfg.hash():
        raise UserError(
            f"{out / BEST}: belongs to another run ({best.behaviour}, hash "
            f"{best.config_hash}; {CONFIG}: {cfg.behaviour}, hash {cfg.hash()})"
        )
    if best.generation > cfg.generations:
        raise UserError(
            f"{out / BEST}: of generation {best.generation}, beyond the run's "
            f"{cfg.generations} ({CONFIG})"
        )
    return best
