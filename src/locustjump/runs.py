"""Training runs. A run is a directory::

    DIR/config.toml      the resolved configuration (TrainConfig)
    DIR/metrics.csv      one row per generation
    DIR/checkpoint.npz   the GA state after the last generation (atomic)
    DIR/best.npz         the best genome so far (atomic)
    DIR/fitness.png      best and mean fitness per generation
    DIR/simple.npz       composed runs: the frozen kick, getup, return-legs genomes
    DIR/eval/            written by ``evaluate_run`` (``locustjump evaluate``)

Every file is loaded without pickle (TOML, CSV, ``.npz`` with
``allow_pickle=False``). Resuming from ``checkpoint.npz`` gives a bit-identical
result to an uninterrupted run: the GA's random generator state is part of the
checkpoint, the simulation is deterministic, and elites keep their fitness.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import time
import tomllib
import zipfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from locustjump import model as lm
from locustjump.behaviours import (
    BEHAVIOURS,
    SIMPLE_BEHAVIOURS,
    Behaviour,
    get_behaviour,
)
from locustjump.io import UserError
from locustjump.rcga import RCGA, RCGAParams
from locustjump.rollout import Backend, get_backend

CONFIG = "config.toml"
METRICS = "metrics.csv"
CHECKPOINT = "checkpoint.npz"
BEST = "best.npz"
FITNESS_PNG = "fitness.png"
SIMPLE = "simple.npz"
FORMAT = 1  # version of checkpoint.npz / best.npz
#: LocustParams fields newer than the shipped runs: in the config hash only
#: when not at their default (the default is the creature those runs used)
_LATER_MODEL_FIELDS = ("strut_stiffness", "strut_damping", "strut_swing")
METRICS_COLUMNS = (
    "generation",
    "best",
    "mean",
    "std",
    "wall_s",
    "evaluations",
    "control_steps",
    "steps_per_s",
)


# --- configuration ------------------------------------------------------------


@dataclass(frozen=True)
class TrainConfig:
    """Everything that determines a run's result (threads do not: any number of
    threads gives the same result)."""

    behaviour: str = "kick"
    seed: int = 0
    generations: int = 1000  # paper: 1000
    rcga: RCGAParams = field(default_factory=RCGAParams)
    model: lm.LocustParams = field(default_factory=lm.LocustParams)
    #: composed runs: digest of the three frozen simple genomes (``simple.npz``)
    simple: str = ""

    def __post_init__(self) -> None:
        if self.behaviour not in BEHAVIOURS:
            raise ValueError(
                f"unknown behaviour {self.behaviour!r}; "
                f"choose from {', '.join(BEHAVIOURS)}"
            )
        if self.generations < 1:
            raise ValueError(f"generations must be >= 1, got {self.generations}")
        if self.seed < 0:
            raise ValueError(f"seed must be >= 0, got {self.seed}")

    def replace(self, **changes: Any) -> TrainConfig:
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        def table(obj: Any) -> dict[str, Any]:
            return {
                f.name: list(v) if isinstance(v := getattr(obj, f.name), tuple) else v
                for f in dataclasses.fields(obj)
            }

        d = {
            "behaviour": self.behaviour,
            "seed": self.seed,
            "generations": self.generations,
            "rcga": table(self.rcga),
            "model": table(self.model),
        }
        if self.simple:
            d["simple"] = self.simple
        return d

    def hash(self) -> str:
        """Identity of the experiment: everything but ``generations`` (a run may
        be extended), as 16 hex digits. Model fields added after runs were
        shipped count only when changed, so those runs keep their hash."""
        d = self.to_dict()
        del d["generations"]
        default = lm.LocustParams()
        for name in _LATER_MODEL_FIELDS:
            if d["model"][name] == getattr(default, name):
                del d["model"][name]
        text = json.dumps(d, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str) -> TrainConfig:
        """Checked conversion; a ``UserError`` names ``source`` and the key."""
        top = {"behaviour": "kick", "seed": 0, "generations": 1000, "simple": ""}
        kwargs: dict[str, Any] = {}
        for key, value in d.items():
            if key in top:
                kwargs[key] = _coerce(value, top[key], key, source)
            elif key == "rcga":
                kwargs[key] = _table(RCGAParams, value, key, source)
            elif key == "model":
                kwargs[key] = _table(lm.LocustParams, value, key, source)
            else:
                raise UserError(f"{source}: unknown key {key!r}")
        try:
            return cls(**kwargs)
        except ValueError as e:
            raise UserError(f"{source}: {e}") from None


def _coerce(value: Any, default: Any, key: str, source: str) -> Any:
    """``value`` as the type of ``default``, or a ``UserError`` naming ``key``."""
    ok: bool
    if isinstance(default, bool):
        ok = isinstance(value, bool)
    elif isinstance(default, int):
        ok = isinstance(value, int) and not isinstance(value, bool)
    elif isinstance(default, float):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        value = float(value) if ok else value
    elif isinstance(default, str):
        ok = isinstance(value, str)
    elif isinstance(default, tuple):
        if not isinstance(value, list) or len(value) != len(default):
            raise UserError(
                f"{source}: {key} must be an array of {len(default)} numbers, "
                f"got {value!r}"
            )
        return tuple(
            _coerce(v, d, f"{key}[{i}]", source)
            for i, (v, d) in enumerate(zip(value, default, strict=True))
        )
    else:  # pragma: no cover - every field type is handled above
        raise TypeError(type(default))
    if not ok:
        raise UserError(
            f"{source}: {key} must be {type(default).__name__}, "
            f"got {type(value).__name__} {value!r}"
        )
    return value


def _table(cls: type, table: Any, section: str, source: str) -> Any:
    if not isinstance(table, dict):
        raise UserError(f"{source}: {section} must be a table")
    defaults = cls()
    names = {f.name for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, value in table.items():
        if key not in names:
            raise UserError(f"{source}: unknown key '{section}.{key}'")
        kwargs[key] = _coerce(value, getattr(defaults, key), f"{section}.{key}", source)
    try:
        return cls(**kwargs)
    except ValueError as e:
        raise UserError(f"{source}: [{section}] {e}") from None


def load_config(path: str | os.PathLike, *, behaviour: str = "kick") -> TrainConfig:
    """Read a (possibly partial) TOML config; missing keys take the defaults
    (``behaviour`` where the file names none)."""
    path = Path(path)
    try:
        with open(path, "rb") as f:
            d = tomllib.load(f)
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise UserError(f"{path}: not valid TOML ({e})") from None
    return TrainConfig.from_dict({"behaviour": behaviour, **d}, str(path))


def _atomic_write_bytes(path: Path, write: Callable[[Any], None]) -> None:
    """``write(file)`` into ``path`` via a temporary file, fsync and rename."""
    tmp = path.with_name(f".{path.name}.tmp")
    with open(tmp, "wb") as f:
        write(f)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def write_config(path: Path, cfg: TrainConfig) -> None:
    header = (
        f"# locustjump run configuration (config hash {cfg.hash()}).\n"
        "# Edit a copy and pass it with --config to start a new run.\n"
    ).encode()
    _atomic_write_bytes(
        path, lambda f: f.write(header + tomli_w.dumps(cfg.to_dict()).encode())
    )


# --- genome and checkpoint files -----------------------------------------------


def _load_npz(path: Path, keys: tuple[str, ...]) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in keys if k not in z.files]
            if missing:
                raise UserError(f"{path}: missing {', '.join(missing)}")
            return {k: z[k] for k in keys}
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except UserError:
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as e:
        raise UserError(f"{path}: not a readable .npz file ({e})") from None


@dataclass(frozen=True)
class BestGenome:
    """The content of ``best.npz``."""

    genome: np.ndarray  # (num_params,)
    fitness: float
    generation: int
    behaviour: str
    config_hash: str

    def save(self, path: Path) -> None:
        _atomic_write_bytes(
            path,
            lambda f: np.savez(
                f,
                format=np.array(FORMAT),
                genome=self.genome,
                fitness=np.array(self.fitness),
                generation=np.array(self.generation),
                behaviour=np.array(self.behaviour),
                config_hash=np.array(self.config_hash),
            ),
        )

    @classmethod
    def load(cls, path: str | os.PathLike, num_params: int | None = None) -> BestGenome:
        """Read and check ``best.npz`` (``UserError`` naming the file if bad)."""
        path = Path(path)
        z = _load_npz(
            path,
            ("format", "genome", "fitness", "generation", "behaviour", "config_hash"),
        )
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
class SimpleGenomes:
    """The frozen simple networks of a composed run (``DIR/simple.npz``).

    ``genomes`` (3, 144) in ``SIMPLE_BEHAVIOURS`` order; ``sources`` the run
    directories they came from and ``hashes`` those runs' config hashes (for
    the record: the composed run never reads them again).
    """

    genomes: np.ndarray
    sources: tuple[str, ...]
    hashes: tuple[str, ...]

    @property
    def digest(self) -> str:
        """16 hex digits identifying the three genomes (in ``config.toml``)."""
        data = np.ascontiguousarray(self.genomes, dtype="<f8").tobytes()
        return hashlib.sha256(data).hexdigest()[:16]

    @classmethod
    def from_runs(
        cls, dirs: dict[str, str | os.PathLike], model: lm.LocustParams
    ) -> SimpleGenomes:
        """Best genomes of a kick, a getup and a return-legs run; each must hold
        that behaviour and the same model parameters (``UserError`` naming the
        directory otherwise)."""
        genomes, sources, hashes = [], [], []
        for name in SIMPLE_BEHAVIOURS:
            if name not in dirs or dirs[name] is None:
                raise UserError(
                    "train composed needs --kick, --getup and --return-legs run "
                    f"directories (missing --{name})"
                )
            d = Path(dirs[name])
            cfg, _, best = load_run(d)
            if cfg.behaviour != name:
                raise UserError(
                    f"--{name} {d}: holds a {cfg.behaviour!r} run, not {name!r}"
                )
            if cfg.model != model:
                diff = [
                    k for k, v in cfg.to_dict()["model"].items()
                    if TrainConfig(model=model).to_dict()["model"][k] != v
                ]  # fmt: skip
                raise UserError(
                    f"--{name} {d}: its model parameters differ from this run's "
                    f"({', '.join(diff)})"
                )
            genomes.append(best.genome)
            sources.append(str(d))
            hashes.append(best.config_hash)
        return cls(np.stack(genomes), tuple(sources), tuple(hashes))

    def save(self, path: Path) -> None:
        _atomic_write_bytes(
            path,
            lambda f: np.savez(
                f,
                format=np.array(FORMAT),
                behaviours=np.array(SIMPLE_BEHAVIOURS),
                genomes=self.genomes,
                sources=np.array(self.sources),
                hashes=np.array(self.hashes),
            ),
        )

    @classmethod
    def load(cls, path: Path) -> SimpleGenomes:
        z = _load_npz(path, ("format", "behaviours", "genomes", "sources", "hashes"))
        if tuple(str(b) for b in z["behaviours"]) != SIMPLE_BEHAVIOURS:
            raise UserError(
                f"{path}: not the genomes of {', '.join(SIMPLE_BEHAVIOURS)}"
            )
        g = np.asarray(z["genomes"], dtype=np.float64)
        n = get_behaviour("kick").controller.num_params
        if g.shape != (len(SIMPLE_BEHAVIOURS), n) or not np.isfinite(g).all():
            raise UserError(f"{path}: genomes must be finite, shape (3, {n})")
        return cls(
            g,
            tuple(str(x) for x in z["sources"]),
            tuple(str(x) for x in z["hashes"]),
        )


def behaviour_of(cfg: TrainConfig, out: Path) -> Behaviour:
    """The behaviour of the run in ``out`` (a composed run reads its frozen
    simple genomes from ``simple.npz`` and checks them against the config)."""
    if cfg.behaviour != "composed":
        return get_behaviour(cfg.behaviour)
    simple = SimpleGenomes.load(out / SIMPLE)
    if simple.digest != cfg.simple:
        raise UserError(
            f"{out / SIMPLE}: its genomes (digest {simple.digest}) are not the ones "
            f"{out / CONFIG} names ({cfg.simple or 'none'})"
        )
    return get_behaviour("composed", simple.genomes)


# --- metrics --------------------------------------------------------------------


def read_metrics(path: Path) -> np.ndarray:
    """metrics.csv as a structured array (one record per generation)."""
    try:
        return np.atleast_1d(
            np.genfromtxt(path, delimiter=",", names=True, dtype=None, ndmin=1)
        )
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: not a readable metrics file ({e})") from None


def _truncate_metrics(path: Path, generation: int, last_row: str) -> None:
    """Keep the header and the rows of generations 1..``generation``; the row of
    ``generation`` itself is ``last_row`` (from the checkpoint) if missing."""
    lines = path.read_text().splitlines(keepends=True) if path.exists() else []
    header = ",".join(METRICS_COLUMNS) + "\n"
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
    _atomic_write_bytes(path, lambda f: f.write((header + "".join(keep)).encode()))


# --- training -------------------------------------------------------------------


@dataclass
class TrainResult:
    out: Path
    generation: int  # generations completed
    best: BestGenome
    wall_s: float  # wall time of this call


class _Run:
    """A run directory being trained: the GA plus its files."""

    def __init__(self, out: Path, cfg: TrainConfig, behaviour: Behaviour):
        self.out, self.cfg, self.beh = out, cfg, behaviour
        self.num_params = behaviour.controller.num_params
        self.hash = cfg.hash()
        self.ga = RCGA(self.num_params, cfg.rcga, np.random.default_rng(cfg.seed))
        self.best: BestGenome | None = None
        self.metrics_row = ""  # of the checkpointed generation

    def checkpoint(self, metrics_row: str) -> None:
        assert self.best is not None
        best = self.best
        state = self.ga.state()
        _atomic_write_bytes(
            self.out / CHECKPOINT,
            lambda f: np.savez(
                f,
                format=np.array(FORMAT),
                behaviour=np.array(self.cfg.behaviour),
                config_hash=np.array(self.hash),
                best_genome=best.genome,
                best_fitness=np.array(best.fitness),
                best_generation=np.array(best.generation),
                metrics_row=np.array(metrics_row),
                **state,
            ),
        )

    def restore(self) -> None:
        path = self.out / CHECKPOINT
        z = _load_npz(
            path,
            (
                "format",
                "behaviour",
                "config_hash",
                "best_genome",
                "best_fitness",
                "best_generation",
                "generation",
                "population",
                "fitness",
                "rng_state",
                "metrics_row",
            ),
        )
        self.metrics_row = str(z["metrics_row"])
        if str(z["behaviour"]) != self.cfg.behaviour:
            raise UserError(
                f"{path}: holds a {str(z['behaviour'])!r} run, not "
                f"{self.cfg.behaviour!r}"
            )
        if str(z["config_hash"]) != self.hash:
            raise UserError(
                f"{path}: was written by another configuration (hash "
                f"{z['config_hash']}, {CONFIG} has {self.hash})"
            )
        try:
            self.ga = RCGA.from_state(self.num_params, self.cfg.rcga, z)
        except (ValueError, KeyError, TypeError) as e:
            raise UserError(f"{path}: malformed checkpoint ({e})") from None
        self.best = BestGenome(
            np.asarray(z["best_genome"], dtype=np.float64),
            float(z["best_fitness"]),
            int(z["best_generation"]),
            self.cfg.behaviour,
            self.hash,
        )
        if self.best.genome.shape != (self.num_params,):
            raise UserError(f"{path}: best_genome has the wrong length")


def train(
    cfg: TrainConfig,
    out: str | os.PathLike,
    *,
    resume: bool = False,
    backend: Backend | None = None,
    progress: bool = True,
    stop_after: int | None = None,
    simple: SimpleGenomes | None = None,
) -> TrainResult:
    """Evolve ``cfg.behaviour`` into run directory ``out``.

    Args:
      cfg: the configuration; with ``resume`` it must equal the run's
        ``config.toml`` except for ``generations`` (a finished run can be
        extended).
      out: the run directory; a new run needs it absent or empty.
      resume: continue the run in ``out`` from its checkpoint.
      backend: where episodes run (default: local threads).
      progress: show a progress bar (on stderr).
      stop_after: stop after this many generations in this call (the run stays
        resumable; used to test interruption).
      simple: composed runs: the frozen simple genomes (required for a new
        run; on resume, if given, they must be the run's own).

    Returns:
      The directory, the generations completed and the best genome.
    """
    out = Path(out)
    composed = cfg.behaviour == "composed"
    if composed and simple is not None:
        if cfg.simple not in ("", simple.digest):
            raise UserError(
                f"the simple genomes (digest {simple.digest}) are not the ones the "
                f"configuration names ({cfg.simple})"
            )
        cfg = cfg.replace(simple=simple.digest)
    if resume:
        if composed and not cfg.simple and (out / CONFIG).is_file():
            cfg = cfg.replace(simple=load_config(out / CONFIG).simple)
        extend = _check_resume(out, cfg)
        beh = behaviour_of(cfg, out)
        run = _Run(out, cfg, beh)
        if (out / CHECKPOINT).exists():
            run.restore()  # checked before anything is written
        if extend:
            write_config(out / CONFIG, cfg)
    else:
        _check_new(out)
        if composed and simple is None:
            raise UserError(
                "train composed needs the kick, getup and return-legs runs it "
                "switches between (--kick DIR --getup DIR --return-legs DIR)"
            )
        out.mkdir(parents=True, exist_ok=True)
        if simple is not None and composed:
            simple.save(out / SIMPLE)
        write_config(out / CONFIG, cfg)
        beh = behaviour_of(cfg, out)
        run = _Run(out, cfg, beh)
    _truncate_metrics(out / METRICS, run.ga.generation, run.metrics_row)
    return _loop(run, get_backend(backend), progress, stop_after)


def _check_new(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise UserError(f"--out {out}: exists and is not a directory")
    if out.is_dir() and any(out.iterdir()):
        what = "holds a run" if (out / CONFIG).exists() else "is not empty"
        raise UserError(
            f"--out {out}: directory {what} (use --resume to continue a run, or "
            "choose another --out)"
        )


def _check_resume(out: Path, cfg: TrainConfig) -> bool:
    """Check that ``cfg`` continues the run in ``out``; True if it extends it."""
    if not (out / CONFIG).is_file():
        raise UserError(f"--resume: {out} holds no run (no {CONFIG})")
    stored = load_config(out / CONFIG)
    if stored.behaviour != cfg.behaviour:
        raise UserError(
            f"--resume: {out} holds a {stored.behaviour!r} run, not {cfg.behaviour!r}"
        )
    if stored.replace(generations=cfg.generations) != cfg:
        diff = [
            k
            for k, v in cfg.to_dict().items()
            if k != "generations" and v != stored.to_dict()[k]
        ]
        raise UserError(
            f"--resume: the options differ from {out / CONFIG} in {', '.join(diff)}"
        )
    return stored.generations != cfg.generations


def _loop(
    run: _Run, backend: Backend, progress: bool, stop_after: int | None
) -> TrainResult:
    from tqdm.auto import tqdm

    cfg, ga, beh, p = run.cfg, run.ga, run.beh, run.cfg.model
    t_start = time.perf_counter()
    bar = tqdm(
        total=cfg.generations,
        initial=ga.generation,
        desc=f"{cfg.behaviour}",
        unit="gen",
        disable=not progress,
        dynamic_ncols=True,
    )
    done = 0
    try:
        with open(run.out / METRICS, "a") as metrics:
            while ga.generation < cfg.generations and (
                stop_after is None or done < stop_after
            ):
                t0 = time.perf_counter()
                x = ga.ask()
                fit, res = beh.evaluate(x, p, backend=backend)
                ga.tell(fit)
                g = ga.generation
                i = int(np.argmax(fit))
                if run.best is None or fit[i] > run.best.fitness:
                    run.best = BestGenome(
                        x[i].copy(), float(fit[i]), g, cfg.behaviour, run.hash
                    )
                    run.best.save(run.out / BEST)
                f = ga.fitness
                # floats as shortest round-trip text: the CSV holds exact values
                row = [g, float(f[0]), float(f.mean()), float(f.std())]
                row += [len(x), res.control_steps]
                # the checkpoint carries its own metrics row (a kill between the
                # two writes loses nothing); wall time covers the whole
                # generation but for this last small write
                wall = time.perf_counter() - t0
                rate = res.control_steps / wall
                line = _metrics_line(row, wall, rate)
                run.checkpoint(line)
                wall = time.perf_counter() - t0
                rate = res.control_steps / wall
                metrics.write(_metrics_line(row, wall, rate))
                metrics.flush()
                done += 1
                bar.set_postfix(
                    best=f"{f[0]:.4g}",
                    mean=f"{f.mean():.4g}",
                    steps_s=f"{rate:,.0f}",
                    refresh=False,
                )
                bar.update(1)
    finally:
        bar.close()
        if ga.generation > 0:
            fitness_figure(run.out)
    assert run.best is not None
    return TrainResult(run.out, ga.generation, run.best, time.perf_counter() - t_start)


def _metrics_line(row: list, wall: float, rate: float) -> str:
    g, best, mean, std, evaluations, steps = row
    cols = [g, best, mean, std, round(wall, 4), evaluations, steps, round(rate, 1)]
    return ",".join(map(str, cols)) + "\n"


def fitness_figure(out: Path) -> Path:
    """``DIR/fitness.png`` from ``DIR/metrics.csv``."""
    from locustjump.plots import fitness_curves

    m = read_metrics(out / METRICS)
    cfg = load_config(out / CONFIG)
    path = out / FITNESS_PNG
    fitness_curves(
        path, m, title=f"{cfg.behaviour}: fitness per generation (seed {cfg.seed})"
    )
    return path


# --- evaluation ---------------------------------------------------------------


@dataclass
class Evaluation:
    behaviour: str
    fitness: float
    recorded_fitness: float
    metrics: dict[str, Any]
    files: list[Path]

    @property
    def matches(self) -> bool:
        return self.fitness == self.recorded_fitness

    def to_dict(self) -> dict[str, Any]:
        return {
            "behaviour": self.behaviour,
            "fitness": self.fitness,
            "recorded_fitness": self.recorded_fitness,
            "fitness_matches": self.matches,
            "metrics": self.metrics,
            "files": [str(f) for f in self.files],
        }


def load_run(path: str | os.PathLike) -> tuple[TrainConfig, Behaviour, BestGenome]:
    """The configuration, behaviour and best genome of run directory ``path``."""
    out = Path(path)
    if not out.is_dir():
        raise UserError(f"{out}: no such directory")
    if not (out / CONFIG).is_file():
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


def evaluate_run(
    path: str | os.PathLike,
    *,
    backend: Backend | None = None,
    eval_dir: str | os.PathLike | None = None,
) -> Evaluation:
    """Re-simulate a run's best genome; write ``DIR/eval/`` (CSV + figures),
    or ``eval_dir`` if given.

    ``eval/`` holds derived files only: they are rewritten on every call.
    """
    from locustjump import io

    out = Path(path)
    cfg, beh, best = load_run(out)
    p = cfg.model
    res = beh.simulate(best.genome[None], p, backend=backend, record=beh.eval_record)
    fitness = float(beh.fitness(res, p)[0])
    metrics = beh.metrics(res, p, best.genome)
    ev = out / "eval" if eval_dir is None else Path(eval_dir)
    ev.mkdir(parents=True, exist_ok=True)
    labels = beh.state_labels()
    files = []
    for e, label in enumerate(labels):
        name = "trajectory.csv" if len(labels) == 1 else f"trajectory_{label}.csv"
        files.append(ev / name)
        io.write_trajectory_csv(
            files[-1], res["qpos"][e], res["obs"][e], res["ctrl"][e]
        )
    files += beh.write_figures(res, p, ev)
    return Evaluation(cfg.behaviour, fitness, best.fitness, metrics, files)


def sweep_run(
    path: str | os.PathLike,
    angles: np.ndarray,
    *,
    backend: Backend | None = None,
) -> tuple[Any, list[Path]]:
    """The get-up generalisation test of getup run ``path``'s best genome from
    roll ``angles`` (plus the training states): ``DIR/sweep/sweep.csv`` and
    ``sweep.png``. Returns the :class:`~locustjump.behaviours.getup.Sweep` and
    the files."""
    from locustjump.behaviours.getup import sweep_getup
    from locustjump.plots import sweep_figure

    cfg, _, best = load_run(path)
    if cfg.behaviour != "getup":
        raise UserError(
            f"{path}: holds a {cfg.behaviour!r} run; sweep-getup needs a getup run"
        )
    sw = sweep_getup(best.genome, cfg.model, angles, backend=backend)
    out = Path(path) / "sweep"
    out.mkdir(exist_ok=True)
    table = np.column_stack(
        [sw.roll_deg, sw.training, sw.success, sw.start_uz, sw.final_uz,
         sw.time_to_get_up_s]
    )  # fmt: skip
    np.savetxt(
        out / "sweep.csv",
        table,
        delimiter=",",
        header="angle_deg,training,success,start_uz,final_uz,time_to_get_up_s",
        comments="",
        fmt=["%.6g", "%d", "%d", "%.6f", "%.6f", "%.6g"],
    )
    sweep_figure(out / "sweep.png", sw)
    return sw, [out / "sweep.csv", out / "sweep.png"]
