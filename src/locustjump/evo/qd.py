"""Quality diversity on the ask/tell base: a grid archive of elites filled by
pyribs' emitters (extra ``locustjump[qd]``).

pyribs' own split (Tjanaka et al. 2023): an *archive* (``GridArchive``, the
MAP-Elites grid of Mouret & Clune 2015 over the task's behaviour
descriptors), *emitters* that propose genomes (each optimizer module says
which) and a *scheduler* that asks them and tells them, with the archive, the
fitness and descriptors of what they proposed. A QD optimizer's genomes are
scored by the task's fitness (pyribs' objective) and described by the task's
behaviour descriptors (pyribs' measures), which each :meth:`Optimizer.tell`
brings (:attr:`QDOptimizer.descriptor_names`).

**Determinism.** The archive and every emitter take a seed drawn from the
run's seed (``numpy.random.SeedSequence(seed)``), and the first genomes come
from ``self.rng``: the same seed gives the same genomes, bit for bit; nothing
reads NumPy's global generator.

**State without pickle.** pyribs keeps its state in objects (an emitter's
evolution strategy, its ranker, the archive's store and statistics) that it
saves only by pickling. As :mod:`.cma` does for pycma, the state here is the
seed and every fitness and descriptor vector told so far: ask/tell is a
deterministic function of them, so :meth:`QDOptimizer.load_state` rebuilds
archive, emitters and scheduler and *replays* every generation without
re-simulating (measured on the shared 2-core development machine, 144 genes,
population 50: 2 ms a generation for MAP-Elites, 11 ms for CMA-ME with 5
emitters, so 11 s to resume a 1000-generation CMA-ME run; pyribs compiles its
CMA-ES with Numba in each new process, 10-15 s there). The state also
holds the archive's own arrays (its elites' genomes, fitness, descriptors,
cells and generations, in the order pyribs holds them); the replayed archive
must equal them bit for bit, else the checkpoint is refused (another pyribs
could replay otherwise).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from locustjump.evo.archive import Archive
from locustjump.evo.base import MAX_POPULATION, POPULATION, Optimizer
from locustjump.ranges import Range, check_settings, setting

#: cells of a grid at most (each holds a genome: 100 x 100 of 144 genes is
#: 11.5 MB in the archive and again in each checkpoint)
MAX_CELLS = 10_000
#: cells per descriptor unless ``cells`` says otherwise
DEFAULT_CELLS = 10
#: ``emitters``: pyribs emitters, each asked for its share of the population
EMITTERS = Range(1, MAX_POPULATION, integer=True)

#: what ``[optimizer]``'s array keys hold (the config reader reads this)
_NAMES = {"item": ""}
_RANGES = {"item": (0.0, 0.0)}


@dataclass(frozen=True)
class QDParams:
    """Settings every QD optimizer shares: the population, the emitters, the
    descriptors and the grid over them.

    ``descriptors``, ``ranges`` and ``cells`` left empty are the task's: its
    default descriptors, each one's declared range, :data:`DEFAULT_CELLS`
    cells each (a run's ``config.toml`` records them resolved,
    :meth:`with_task`).
    """

    kind: ClassVar[str]
    #: genomes per generation, shared among the emitters
    population: int = setting(50, POPULATION)
    emitters: int = setting(1, EMITTERS)  # each asked for its share in turn
    #: the task's behaviour descriptors the grid is over, by name
    descriptors: tuple[str, ...] = field(default=(), metadata=_NAMES)
    #: (low, high) of the grid per descriptor, in the descriptor's unit
    ranges: tuple[tuple[float, float], ...] = field(default=(), metadata=_RANGES)
    cells: tuple[int, ...] = ()  # cells of the grid per descriptor
    #: subtracted from every elite's fitness in the QD score (pyribs'
    #: qd_score_offset): set it to the task's lowest fitness so that every
    #: elite adds (the kick's is 0, the default)
    qd_offset: float = setting(0.0, Range())

    def __post_init__(self) -> None:
        check_settings(self)
        if self.population < self.emitters * self.min_batch:
            raise ValueError(
                f"population must be >= {self.min_batch} per emitter "
                f"({self.emitters} emitters: >= "
                f"{self.emitters * self.min_batch}), got {self.population}"
            )
        if len(set(self.descriptors)) != len(self.descriptors):
            raise ValueError(f"descriptors repeat a name: {list(self.descriptors)}")
        for lo, hi in self.ranges:
            if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
                raise ValueError(
                    f"ranges must be finite (low, high) with low < high, got "
                    f"{[list(r) for r in self.ranges]}"
                )
        if any(c < 1 for c in self.cells):
            raise ValueError(f"cells must be >= 1 each, got {list(self.cells)}")
        if self.cells and int(np.prod(self.cells)) > MAX_CELLS:
            raise ValueError(
                f"cells {list(self.cells)} make {int(np.prod(self.cells)):,} "
                f"cells; at most {MAX_CELLS:,}"
            )
        if self.descriptors:
            d = len(self.descriptors)
            for name in ("ranges", "cells"):
                n = len(getattr(self, name))
                if n not in (0, d):
                    raise ValueError(
                        f"{name} has {n} entries for {d} descriptors "
                        f"({', '.join(self.descriptors)})"
                    )

    #: genomes an emitter is asked for at least
    min_batch: ClassVar[int] = 1

    def replace(self, **changes: Any) -> QDParams:
        return dataclasses.replace(self, **changes)

    def with_task(
        self,
        task: str,
        declared: Mapping[str, tuple[float, float]],
        default: Sequence[str],
    ) -> QDParams:
        """These settings with task ``task``'s filled in: ``declared`` maps
        each of its descriptors to its range, ``default`` names those the
        grid is over unless ``descriptors`` says; ``ValueError`` naming an
        unknown descriptor, or a task that declares none."""
        if not declared:
            raise ValueError(
                f"the {self.kind} optimizer needs behaviour descriptors and "
                f"{task} declares none"
            )
        names = self.descriptors or tuple(default)
        unknown = [n for n in names if n not in declared]
        if unknown:
            raise ValueError(
                f"unknown descriptor {unknown[0]!r}; {task} declares "
                f"{', '.join(declared)}"
            )
        if len(self.cells) not in (0, len(names)):
            raise ValueError(
                f"cells has {len(self.cells)} entries for {len(names)} "
                f"descriptors ({', '.join(names)})"
            )
        return self.replace(
            descriptors=names,
            ranges=self.ranges or tuple(tuple(declared[n]) for n in names),
            cells=self.cells or (DEFAULT_CELLS,) * len(names),
        )

    def batch_sizes(self) -> list[int]:
        """Genomes each emitter is asked for: the population shared out, the
        first emitters taking one more where it does not divide."""
        q, r = divmod(self.population, self.emitters)
        return [q + (i < r) for i in range(self.emitters)]


def import_ribs() -> Any:
    try:
        import ribs.archives
        import ribs.emitters
        import ribs.schedulers
    except ImportError:
        raise ImportError(
            "the quality-diversity optimizers need pyribs: "
            "pip install -e '.[qd]' in the clone"
        ) from None
    return ribs


class QDOptimizer(Optimizer):
    """A pyribs scheduler over a grid archive, behind ask/tell. Maximises.

    A subclass writes :meth:`_emitters`. Each :meth:`tell` needs the
    descriptors of :attr:`descriptor_names`; :meth:`archive` is the
    repertoire so far. ``fitness`` is the generation's (what was told);
    diagnostics (``metrics.csv`` columns): ``qd_score`` (the elites' fitness
    minus ``qd_offset``, summed), ``coverage`` (occupied cells over cells) and
    ``archive_best`` (the best elite's fitness: the best so far).
    """

    Params: ClassVar[type] = QDParams

    def __init__(self, num_params: int, params: QDParams, seed: int = 0) -> None:
        super().__init__(num_params, params, seed)
        if not (params.descriptors and params.ranges and params.cells):
            raise ValueError(
                f"the {params.kind} optimizer needs its descriptors, their ranges "
                "and cells (TrainConfig fills them from the task)"
            )
        self._start()

    def _emitters(self, archive: Any, seeds: list[int]) -> list[Any]:
        """pyribs emitters over ``archive``, one per seed, asked for
        ``params.batch_sizes()`` genomes each."""
        raise NotImplementedError

    def _start(self) -> None:
        """Archive, emitters and scheduler at generation 0, seeded from the seed."""
        ribs = import_ribs()
        self._restart()
        p = self.params
        seeds = [
            int(s)
            for s in np.random.SeedSequence(self.seed).generate_state(1 + p.emitters)
        ]
        self._grid = ribs.archives.GridArchive(
            solution_dim=self.num_params,
            dims=list(p.cells),
            ranges=[tuple(r) for r in p.ranges],
            qd_score_offset=p.qd_offset,
            seed=seeds[0],
            extra_fields={"generation": ((), np.int64)},
        )
        emitters = self._emitters(self._grid, seeds[1:])
        self._scheduler = ribs.schedulers.Scheduler(self._grid, emitters)
        self._told_fitness: list[np.ndarray] = []
        self._told_descriptors: list[np.ndarray] = []

    @property
    def descriptor_names(self) -> tuple[str, ...]:
        return tuple(self.params.descriptors)

    def _ask(self) -> np.ndarray:
        return np.asarray(self._scheduler.ask(), dtype=np.float64)

    def _tell(self, genomes: np.ndarray, fitness: np.ndarray) -> None:
        raise TypeError(f"the {self.params.kind} optimizer is told descriptors too")

    def _tell_described(
        self, genomes: np.ndarray, fitness: np.ndarray, descriptors: np.ndarray
    ) -> None:
        found = np.full(len(fitness), self.generation + 1, dtype=np.int64)
        self._scheduler.tell(fitness, descriptors, generation=found)
        self._told_fitness.append(fitness.copy())
        self._told_descriptors.append(descriptors.copy())

    def archive(self) -> Archive:
        """The elites so far, in the order pyribs holds them."""
        p, d = self.params, self._grid.data()
        return Archive(
            tuple(p.descriptors),
            np.array([r[0] for r in p.ranges], dtype=np.float64),
            np.array([r[1] for r in p.ranges], dtype=np.float64),
            tuple(int(c) for c in p.cells),
            np.asarray(d["index"], dtype=np.int64),
            np.asarray(d["solution"], dtype=np.float64),
            np.asarray(d["objective"], dtype=np.float64),
            np.asarray(d["measures"], dtype=np.float64),
            np.asarray(d["generation"], dtype=np.int64),
        )

    def diagnostics(self) -> dict[str, float]:
        s = self._grid.stats
        best = np.nan if s.obj_max is None else float(s.obj_max)
        return {
            "qd_score": float(s.qd_score),
            "coverage": float(s.coverage),
            "archive_best": best,
        }

    # -- the state: the seed, what was told, and the archive to check against ----

    def _state(self) -> dict[str, np.ndarray]:
        n, d = self.params.population, len(self.params.descriptors)
        a = self.archive()
        return {
            "seed": np.array(self.seed),
            "fitness_history": np.array(self._told_fitness).reshape(self.generation, n),
            "descriptor_history": np.array(self._told_descriptors).reshape(
                self.generation, n, d
            ),
            **{f"archive_{k}": getattr(a, k) for k in _ARCHIVE_ARRAYS},
        }

    def _set_state(self, state: Mapping[str, np.ndarray]) -> None:
        """Rebuild from the seed, replay every tell, check the archive."""
        n, d = self.params.population, len(self.params.descriptors)
        g = self.generation
        if int(state["seed"]) != self.seed:
            raise ValueError(f"state is of seed {int(state['seed'])}, not {self.seed}")
        f = np.asarray(state["fitness_history"], dtype=np.float64)
        m = np.asarray(state["descriptor_history"], dtype=np.float64)
        if f.shape != (g, n) or m.shape != (g, n, d):
            raise ValueError(
                f"fitness_history {f.shape} and descriptor_history {m.shape} "
                f"are not {g} generations of {n} genomes and {d} descriptors"
            )
        self._start()
        for fg, mg in zip(f, m, strict=True):
            self.ask()
            self.tell(fg, descriptors=mg)
        a = self.archive()
        for k in _ARCHIVE_ARRAYS:
            saved = np.asarray(state[f"archive_{k}"])
            mine = getattr(a, k)
            if saved.shape != mine.shape or not np.array_equal(saved, mine):
                raise ValueError(
                    f"archive_{k} is not what replaying its history gives "
                    "(written by another pyribs?)"
                )


#: the archive's arrays a QD state holds (``archive_<name>``)
_ARCHIVE_ARRAYS = ("index", "solution", "objective", "measures", "generation")
