"""What a reproduction of the paper is: a budget, an optimizer and an engine
for one seed or many, and the directory that holds it.

One seed: ``DIR/reproduce.toml`` and one subdirectory per stage
(:mod:`locustjump.runs.reproduce`). Many seeds: ``DIR/seeds.toml`` and one
single-seed reproduction per seed in ``DIR/seed-<s>/``, the same as
``locustjump reproduce --seed s --out DIR/seed-<s>`` makes
(:mod:`locustjump.runs.multiseed`). :class:`Reproduction` is both: it is
resolved once (the engine from the directory's marker where it has one),
checks the directory before anything is written, builds the command that
makes and continues it, writes the markers and runs one stage of one seed;
a Ray task receives it whole.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.evo import params_class
from locustjump.present.evaluate import HELD_OUT_SEEDS, evaluate_run, evaluate_terrains
from locustjump.present.rules import write_rules_run
from locustjump.present.stages import reporter_of
from locustjump.rundir.config import TrainConfig, scene_table, terrains_from_table
from locustjump.rundir.migrations import check_marker, reproduction_marker
from locustjump.runs.trainer import train
from locustjump.sim import model as lm
from locustjump.sim.engine.job import DEFAULT_ENGINE, ENGINES
from locustjump.sim.scene import Flat, Scene, Terrains
from locustjump.tasks import behaviour_class
from locustjump.version import __version__

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: The paper's trained stages, in order (each a subdirectory).
PAPER_STAGES = ("kick", "getup", "return-legs", "composed")
#: Beyond the paper: one network evolved directly on the composed task.
BASELINES = ("monolithic",)
TRAINED = PAPER_STAGES + BASELINES
STAGES = (rundir.RULES_DIR, *TRAINED)
#: the setting its errors name most (the command line prints its option)
OUT = setting_ref("out")

#: progress and diagnostics (the command line shows them; see logging)
_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Budget:
    """Population and generations per trained stage."""

    name: str
    population: int
    generations: dict[str, int]  # of the paper's stages; baselines are added

    def __post_init__(self) -> None:
        # a baseline gets as many genome evaluations as the four paper stages
        # together
        paper = {s: self.generations[s] for s in PAPER_STAGES}
        total = sum(paper.values())
        gens = {**paper, **{b: self.generations.get(b, total) for b in BASELINES}}
        object.__setattr__(self, "generations", gens)

    def of(self, stage: str) -> int:
        return self.generations[stage]


BUDGETS: dict[str, Budget] = {
    "quick": Budget(
        "quick", 50, {"kick": 30, "getup": 10, "return-legs": 20, "composed": 30}
    ),
    # what `make demo` runs (docs/results.md, "The demo"): the long budget's simple
    # behaviours and the quick budget's composed stage. On the quick budget's
    # simple behaviours (a kick of 0.99 m) seed 0's switcher keeps the creature
    # lying on its side, which scores more than any jumping it can compose
    "demo": Budget(
        "demo", 50, {"kick": 100, "getup": 20, "return-legs": 60, "composed": 30}
    ),
    "long": Budget(
        "long", 50, {"kick": 100, "getup": 20, "return-legs": 60, "composed": 120}
    ),
    "paper": Budget("paper", 50, dict.fromkeys(PAPER_STAGES, 1000)),
}


def budget_of(budget: str | Budget) -> Budget:
    """The budget called ``budget`` (``UserError`` naming the choices if none)."""
    if isinstance(budget, Budget):
        return budget
    if budget in BUDGETS:
        return BUDGETS[budget]
    raise UserError(f"unknown budget {budget!r}; choose from {', '.join(BUDGETS)}")


def stages_of(monolithic: bool = True) -> tuple[str, ...]:
    """Every stage of a reproduction, in order (the rule-based one first)."""
    return (rundir.RULES_DIR, *(TRAINED if monolithic else PAPER_STAGES))


def requires(stage: str) -> tuple[str, ...]:
    """The stages ``stage`` builds on (none for the rule-based one)."""
    if stage == rundir.RULES_DIR:
        return ()
    return tuple(behaviour_class(stage).requires)


@dataclass(frozen=True)
class Reproduction:
    """A reproduction in directory ``out``: ``seeds`` (one: ``out`` is that
    seed's reproduction; ``many``: ``out/seed-<s>/`` each), ``budget``,
    ``optimizer`` (a kind of :mod:`locustjump.evo`) and ``engine``
    (:data:`~locustjump.sim.engine.job.ENGINES`), as its markers record."""

    out: Path
    budget: Budget
    seeds: tuple[int, ...]
    optimizer: str = "rcga"
    engine: str = DEFAULT_ENGINE
    many: bool = False
    #: where every stage trains (and the rules run: its first terrain)
    terrains: Terrains = Terrains()

    @classmethod
    def open(
        cls,
        out: str | os.PathLike[str],
        budget: str | Budget,
        seeds: Sequence[int],
        *,
        optimizer: str = "rcga",
        engine: str | None = None,
        many: bool = False,
        terrains: Terrains | None = None,
    ) -> Reproduction:
        """The reproduction ``out`` holds or will hold, checked (a
        ``UserError`` naming what is wrong); ``engine=None``, ``terrains=None``:
        the ones it was started with, else the defaults. Writes nothing."""
        b = budget_of(budget)
        params_class(optimizer)  # a clear error for an unknown kind
        seeds = tuple(int(s) for s in seeds)
        if not seeds or len(set(seeds)) != len(seeds) or min(seeds) < 0:
            raise UserError(
                f"{setting_ref('seeds')}: need distinct non-negative seeds, got {seeds}"
            )
        if not many and len(seeds) != 1:
            raise UserError("a single-seed reproduction has one seed")
        if engine is not None and engine not in ENGINES:
            raise UserError(
                f"unknown engine {engine!r}; choose from {', '.join(ENGINES)}"
            )
        out = Path(out)
        marker = out / (rundir.SEEDS_MARKER if many else rundir.MARKER)
        if engine is None:
            engine = _read_marker(marker).get("engine", DEFAULT_ENGINE)
        if terrains is None:
            terrains = terrains_from_table(_read_marker(marker)["scene"], str(marker))
        rep = cls(out, b, seeds, optimizer, str(engine), many, terrains)
        rep.check()
        return rep

    def seed_dir(self, seed: int) -> Path:
        """The single-seed reproduction of ``seed``."""
        return rundir.seed_dir(self.out, seed) if self.many else self.out

    def for_seed(self, seed: int) -> Reproduction:
        """The single-seed reproduction of ``seed``."""
        return dataclasses.replace(
            self, out=self.seed_dir(seed), seeds=(seed,), many=False
        )

    def command(self, backend: str = "threads", *, monolithic: bool = True) -> str:
        """The command that makes (and continues) it (``monolithic=False``:
        without the monolithic baseline)."""
        flags = "" if self.optimizer == "rcga" else f" --optimizer {self.optimizer}"
        if self.engine != DEFAULT_ENGINE:
            flags += f" --engine {self.engine}"
        t = self.terrains
        default = Terrains(type(t.scene)().with_seed(0), t.count)
        if (
            t != Terrains()
            and dataclasses.replace(t, scene=t.scene.with_seed(0)) == default
        ):
            flags += f" --scene {t.scene.name}"
            seed = getattr(t.scene, "seed", 0)
            flags += f" --terrain-seed {seed}" if seed else ""
            flags += f" --terrains {t.count}" if t.count > 1 else ""
        elif t != Terrains():  # parameters of its own: its marker's [scene]
            marker = rundir.SEEDS_MARKER if self.many else rundir.MARKER
            flags += f" --scene {Path(self.out) / marker}"
        if self.many:
            seeds = f" --seeds {','.join(map(str, self.seeds))}"
            flags += "" if backend == "threads" else f" --backend {backend}"
        else:
            seeds = f" --seed {self.seeds[0]}"
        budget = f"--budget {self.budget.name}"
        flags += "" if monolithic else " --no-monolithic"
        return f"locustjump reproduce {budget}{seeds}{flags} --out {self.out}"

    def marker(self) -> dict[str, Any]:
        """What its marker records and a rerun must match."""
        seed = {} if self.many else {"seed": self.seeds[0]}
        b = self.budget
        return {"budget": b.name, **seed, "optimizer": self.optimizer,
                "engine": self.engine, "population": b.population,
                "scene": scene_table(self.terrains)}  # fmt: skip

    def check(self) -> None:
        """``out`` (and each seed's directory) may hold this reproduction or
        nothing (``UserError`` otherwise)."""
        out, want = self.out, self.marker()
        name, kind = (
            (rundir.SEEDS_MARKER, "a reproduction over seeds")
            if self.many
            else (rundir.MARKER, "a reproduction")
        )
        if out.exists() and not out.is_dir():
            raise UserError(f"{OUT} {out}: exists and is not a directory")
        rundir.check_not_in_use(out)  # its writer may be making its marker
        if (out / name).is_file():
            have = _read_marker(out / name)
            for k, v in want.items():
                if have.get(k, v) != v:  # a key older markers lack: not checked
                    raise UserError(
                        f"{OUT} {out}: holds {kind} with {k} {have.get(k)!r}, not "
                        f"{v!r} (choose another {OUT})"
                    )
        elif self.many and rundir.is_reproduction(out):
            raise UserError(
                f"{OUT} {out}: holds a single-seed reproduction; give "
                f"{setting_ref('seeds')} another {OUT} (or continue this one with "
                f"{setting_ref('seed')})"
            )
        elif out.is_dir() and any(out.iterdir()):
            rundir.check_not_in_use(out)  # a writer that came after the first look
            raise UserError(
                f"{OUT} {out}: directory is not empty and holds no reproduction "
                f"(no {name}); choose another {OUT}"
            )
        if self.many:
            for s in self.seeds:
                self.for_seed(s).check()

    def start(self, command: str = "") -> None:
        """Write the markers it lacks (a reproduction over seeds: its own,
        listing every seed so far, and each seed's); call :meth:`check` first,
        holding the directories' locks."""
        self.out.mkdir(parents=True, exist_ok=True)
        generations = {s: self.budget.of(s) for s in TRAINED}
        if self.many:
            old = _read_marker(self.out / rundir.SEEDS_MARKER).get("seeds", [])
            rundir.write_toml(
                self.out / rundir.SEEDS_MARKER,
                {**self.marker(), "seeds": sorted({*old, *self.seeds}),
                 "generations": generations,
                 "command": command or self.command(),
                 "locustjump": __version__},
            )  # fmt: skip
            for s in self.seeds:
                self.seed_dir(s).mkdir(exist_ok=True)
                self.for_seed(s).start()
        elif not rundir.is_reproduction(self.out):
            rundir.write_toml(
                self.out / rundir.MARKER,
                {**self.marker(), "generations": generations,
                 "command": command or self.command(),
                 "locustjump": __version__},
            )  # fmt: skip

    def stage_done(self, stage: str, seed: int | None = None) -> bool:
        """Whether ``stage`` (of ``seed``) is trained (its budget done, or its
        optimizer stopped early) and evaluated."""
        d = self.seed_dir(self.seeds[0] if seed is None else seed) / stage
        if stage == rundir.RULES_DIR:
            return (d / rundir.RULES_SUMMARY).is_file()
        if not rundir.eval_metrics_path(d).is_file():
            return False
        return (d / rundir.STOP).is_file() or rundir.generations_done(
            d
        ) >= self.budget.of(stage)

    def train_config(self, stage: str, seed: int | None = None) -> TrainConfig:
        """What trained ``stage`` (not the rule-based one) of ``seed`` trains
        (its ``config.toml``, less the digest of the genomes it builds on)."""
        seed = self.seeds[0] if seed is None else seed
        kind = params_class(self.optimizer)(population=self.budget.population)
        return TrainConfig(stage, seed, self.budget.of(stage), kind,
                           lm.LocustParams(), engine=self.engine,
                           scene=self.terrains)  # fmt: skip

    def run_stage(
        self,
        stage: str,
        backend: Backend,
        seed: int | None = None,
        *,
        progress: bool = False,
        log: Callable[[str], None] | None = None,
        of: tuple[int, int] | None = None,
    ) -> float | None:
        """Run (or continue) ``stage`` of ``seed``'s reproduction, whose marker
        exists and whose required stages are done; the best fitness (``None``
        for the rule-based stage). Each phase (training, evaluating) is
        announced through ``log`` before it begins, as stage ``k`` of ``n``
        where ``of`` is ``(k, n)``; ``log`` takes each line of progress
        (default: this module's logger, at INFO)."""
        log = log or _log.info
        seed = self.seeds[0] if seed is None else seed
        d = self.seed_dir(seed) / stage
        tag = f"[{stage}]" if of is None else f"[{stage}] stage {of[0]} of {of[1]}:"
        if stage == rundir.RULES_DIR:
            log(f"{tag} rule-based successive jumping, 3000 steps")
            run_rules_stage(
                d, backend=backend, engine=self.engine, scene=self.terrains.scene
            )
            return None
        gens = self.budget.of(stage)
        cfg = self.train_config(stage, seed)
        needs = behaviour_class(stage).requires
        frozen = None
        if needs:
            frozen = rundir.FrozenGenomes.from_runs(
                needs, {s: d.parent / s for s in needs}, cfg.model
            )
        resume = rundir.is_run(d)
        log(f"{tag} {'resuming' if resume else 'training'}: {gens} generations")
        res = train(
            cfg, d, resume=resume, backend=backend, progress=progress, frozen=frozen
        )
        if res.stopped:
            why = ", ".join(f"{k} {v}" for k, v in res.stopped.items())
            log(f"[{stage}] the optimizer stopped at generation {res.generation}: "
                f"{why}")  # fmt: skip
        log(f"{tag} evaluating its best genome")
        t0 = time.perf_counter()
        ev = evaluate_run(d, backend=backend, eval_dir=d / rundir.EVAL)
        run_cfg, beh, best = rundir.load_run(d)
        extra = reporter_of(beh).extra_evaluation(
            beh, d, best.genome, run_cfg.model, backend=backend, engine=run_cfg.engine
        )
        if beh.terrains.scene.seeded:  # on terrains training never saw
            log(f"[{stage}] scoring on {len(HELD_OUT_SEEDS)} held-out terrains")
            extra["held_out"] = evaluate_terrains(
                d, list(HELD_OUT_SEEDS), backend=backend
            ).to_dict()
        rundir.write_json(
            rundir.eval_metrics_path(d),
            {**ev.to_dict(), **extra, "eval_wall_s": time.perf_counter() - t0},
        )
        log(f"[{stage}] best fitness {ev.fitness:.6g}")
        return ev.fitness


def _read_marker(path: Path) -> dict[str, Any]:
    """A marker's table, older ones as they were meant ({} if there is none)."""
    if not os.path.lexists(path):
        return {"scene": scene_table(Terrains())}
    table = check_marker(rundir.read_toml(path), path)
    if path.name == rundir.MARKER:
        return reproduction_marker(table)
    return {"scene": scene_table(Terrains()), **table}  # before scenes: flat


def run_rules_stage(
    out: Path,
    *,
    backend: Backend | None = None,
    engine: str = DEFAULT_ENGINE,
    scene: Scene = Flat(),
) -> dict[str, Any]:
    """The rule-based baseline: ``rules/trajectory.{csv,png}``, ``summary.json``."""
    t0 = time.perf_counter()
    r = write_rules_run(out, steps=3000, backend=backend, engine=engine, scene=scene)
    summary = rundir.read_json(out / rundir.RULES_SUMMARY)
    summary["first_apex_height_m"] = r.jumps[0].apex_height if r.jumps else None
    summary["final_up_z"] = float(r.obs[-1, 8])
    summary["wall_s"] = time.perf_counter() - t0
    rundir.write_json(out / rundir.RULES_SUMMARY, summary)
    return summary
