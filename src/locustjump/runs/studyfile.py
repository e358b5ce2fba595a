"""A study file: a declared grid of runs — named arms x seeds — and how they
are scored and compared (``locustjump study FILE``, :mod:`~locustjump.runs.study`).

A study file is TOML::

    name = "optimizers-small"     # default: the file's stem
    root = "runs/studies/optimizers-small"  # its runs (default runs/studies/<name>)
    out = "runs/studies/optimizers-small"   # its table (default: root)
    seeds = "0-2"                 # or a list [0, 1, 2]: one run per arm and seed
    currency = "evaluations"      # what the arms are equalised in: "evaluations"
                                  # (genomes scored) or "control-steps"
    margin = 0.5                  # equivalence margin, fitness units (optional)
    reference = "rcga"            # the arm every other is compared with
                                  # (default: every pair of scored arms)
    flat_gain = 0.05              # learning curves count as flat when the median
                                  # share of a run's improvement made in its last
                                  # third is at most this (optional; the table
                                  # says which arms' are)

    [primary]                     # the comparisons the study is run to make,
                                  # declared before its runs (optional): the
                                  # table tests them as their own family and
                                  # the rest apart, as secondary
    pairs = [["random", "rcga"]]  # pairs of scored arms the table compares
    substeps = [3, 12]            # of [evaluation]'s (default: the first)
    score = "full"                # or "height-term" (Eq. 4 above the ground)

    [defaults]                    # config.toml keys every arm starts from
    behaviour = "kick"
    generations = 10
    optimizer = { population = 10 }

    [evaluation]                  # how each run's best genome is scored
    terrain_seeds = "100-139"     # held-out terrains (a seeded scene); default:
                                  # the run's own scene
    substeps = [3, 12]            # physics substeps (default: as trained)

    [arms.rcga]                   # an arm: config.toml keys over [defaults]
    optimizer = { kind = "rcga" }

    [arms.random]
    optimizer = { kind = "random" }
    label = "random search"       # how tables name it (default: the arm's name)

An arm may also say ``frozen = { kick = "ARM", ... }`` (a behaviour built on
other runs takes the same seed's runs of those arms: the paper's pipeline is
four arms), ``score = false`` (trained for another arm, not compared),
``path = "DIR/{seed}"`` (where its runs are, default ``ROOT/<arm>/seed-<s>``;
``paths = { "0" = "..." }`` for single seeds), ``terrain_stride = K`` (each
seed its own training terrains: seed s from the scene's seed + K x s),
``seed = S`` (not scored: one
run, seed S, that every seed's runs build on) — so a study can name runs
made before it (the shipped ones) — and ``extends = "DIR/{seed}"`` (each run
starts as a copy of that finished run and trains on to the arm's
generations: a longer budget for a finished study). Paths are relative to the working
directory. Every key is checked before anything runs: a wrong one is a
one-line :class:`~locustjump.errors.UserError` naming it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.present.compare import MARGIN
from locustjump.ranges import Range, SettingError
from locustjump.runs.multiseed import parse_seeds
from locustjump.runs.studyarms import Arm, parse_arms

#: what a study may equalise its arms in
CURRENCIES = ("evaluations", "control-steps")
#: the keys of a study file's top level
TOP_KEYS = ("name", "root", "out", "seeds", "currency", "margin", "reference",
            "flat_gain", "primary", "defaults", "evaluation", "arms")  # fmt: skip
#: ``flat_gain``: a share of a run's improvement, more than 0, at most 1
FLAT_GAIN = Range(0.0, 1.0, lo_open=True)
EVALUATION_KEYS = ("terrain_seeds", "substeps")
PRIMARY_KEYS = ("pairs", "substeps", "score")
#: what a primary comparison compares: the full fitness or its height term
PRIMARY_SCORES = ("full", "height-term")
#: most substeps a study scores at (a control step is 1/120 s)
MAX_SUBSTEPS = 96


@dataclass(frozen=True)
class Evaluation:
    """How a run's best genome is scored: on ``terrain_seeds`` (``None``: the
    run's own scene), at each of ``substeps`` (``None``: as trained)."""

    terrain_seeds: tuple[int, ...] | None = None
    substeps: tuple[int | None, ...] = (None,)


@dataclass(frozen=True)
class Primary:
    """The comparisons a study declares primary: each of ``pairs`` (two arm
    names) at each of ``substeps`` (``None``: as trained) on ``score``."""

    pairs: tuple[tuple[str, str], ...]
    substeps: tuple[int | None, ...]
    score: str = "full"

    def describe(self) -> str:
        """In words: ``a - b; c - b (3 and 12 substeps, the full fitness)``."""
        pairs = "; ".join(f"{x} - {y}" for x, y in self.pairs)
        subs = [str(s) for s in self.substeps if s is not None]
        where = (" and ".join(subs) + " substeps") if subs else "as trained"
        score = "the full fitness" if self.score == "full" else "the height term"
        return f"{pairs} ({where}, {score})"

    def names(self, x: str, y: str, substeps: int | None, score: str) -> bool:
        """Whether the comparison of arms ``x`` and ``y`` (either order) at
        ``substeps`` on ``score`` is one of these."""
        return (
            substeps in self.substeps
            and score == self.score
            and any({x, y} == set(p) for p in self.pairs)
        )


@dataclass(frozen=True)
class Study:
    """A parsed, checked study file (:func:`load_study`)."""

    name: str
    source: Path
    root: Path
    out: Path
    seeds: tuple[int, ...]
    currency: str
    margin: float | None
    reference: str | None
    evaluation: Evaluation
    arms: dict[str, Arm]  # in an order where every arm follows those it builds on
    #: an arm's learning curves are flat when the median over its seeds of the
    #: share of a run's improvement made in its last third is at most this
    #: (declared by the study; the table applies it)
    flat_gain: float | None = None
    #: the comparisons declared primary (``None``: none; every comparison of
    #: the table is then one family)
    primary: Primary | None = None

    @property
    def scored(self) -> list[Arm]:
        return [a for a in self.arms.values() if a.score]

    def runs(self) -> list[tuple[Arm, int]]:
        """Every (arm, seed), seed by seed, each arm after those it builds on;
        an arm with a fixed seed once."""
        out, seen = [], set()
        for s in self.seeds:
            for a in self.arms.values():
                seed = a.seed_of(s)
                if (a.name, seed) not in seen:
                    seen.add((a.name, seed))
                    out.append((a, seed))
        return out


def load_study(path: str | os.PathLike[str], seeds: str | None = None) -> Study:
    """The study in TOML file ``path``, every key checked (``UserError`` naming
    the file and the key). ``seeds`` (``"0-4"``) narrows its seeds to those."""
    path = Path(path)
    if path.suffix != ".toml":
        raise UserError(f"{path}: a study file is a .toml file")
    if not os.path.lexists(path):
        raise UserError(f"{path}: no such study file")
    d = rundir.read_toml(path, "study file")
    src = str(path)
    unknown = sorted(set(d) - set(TOP_KEYS))
    if unknown:
        raise UserError(
            f"{src}: unknown key {unknown[0]!r}; a study file holds "
            + ", ".join(TOP_KEYS)
        )
    name = _text(d.get("name", path.stem), "name", src)
    root = Path(_text(d.get("root", f"runs/studies/{name}"), "root", src))
    out = Path(_text(d.get("out", str(root)), "out", src))
    all_seeds = _seeds(d.get("seeds"), "seeds", src)
    if seeds is not None:
        try:
            chosen = parse_seeds(seeds)
        except ValueError as e:
            raise UserError(f"{setting_ref('seeds')}: {e}") from None
        extra = sorted(set(chosen) - set(all_seeds))
        if extra:
            raise UserError(
                f"{setting_ref('seeds')}: seed {extra[0]} is not one of the study's"
            )
        all_seeds = tuple(chosen)
    currency = d.get("currency", "evaluations")
    if currency not in CURRENCIES:
        raise UserError(
            f"{src}: currency {currency!r}: choose from {', '.join(CURRENCIES)}"
        )
    margin = d.get("margin")
    if margin is not None:  # compare --margin's, declared there
        try:
            margin = MARGIN.check("margin", margin)
        except SettingError as e:
            raise UserError(f"{src}: {e}") from None
    flat_gain = d.get("flat_gain")
    if flat_gain is not None:
        try:
            flat_gain = FLAT_GAIN.check("flat_gain", flat_gain)
        except SettingError as e:
            raise UserError(f"{src}: {e}") from None
    arms = parse_arms(d.get("arms"), d.get("defaults", {}), root, src)
    reference = d.get("reference")
    if reference is not None and (reference not in arms or not arms[reference].score):
        raise UserError(f"{src}: reference {reference!r} is not a scored arm")
    if sum(a.score for a in arms.values()) < 1:
        raise UserError(f"{src}: no arm is scored (every arm says score = false)")
    evaluation = _evaluation(d.get("evaluation", {}), src)
    primary = None
    if "primary" in d:
        primary = _primary(d["primary"], arms, reference, evaluation, src)
    _held_out(arms, all_seeds, evaluation, src)
    _own_directories(arms, all_seeds, src)
    return Study(
        name, path, root, out, all_seeds, currency,
        margin, reference, evaluation, arms, flat_gain, primary,
    )  # fmt: skip


def _held_out(
    arms: dict[str, Arm], seeds: tuple[int, ...], ev: Evaluation, src: str
) -> None:
    """``UserError`` if an evaluation terrain is one some run trains on."""
    if ev.terrain_seeds is None:
        return
    held = set(ev.terrain_seeds)
    for arm in arms.values():
        for s in seeds:
            t = arm.config(s).scene
            seen = held & {getattr(x, "seed", None) for x in t.scenes}
            if seen and not t.scene.is_flat:
                raise UserError(
                    f"{src}: evaluation terrain {min(seen)} is a training terrain "
                    f"of arm {arm.name!r}, seed {s}: held-out terrains must be unseen"
                )


def _own_directories(arms: dict[str, Arm], seeds: tuple[int, ...], src: str) -> None:
    """``UserError`` if two runs of the study are one directory."""
    runs: dict[str, tuple[str, int]] = {}
    for s in seeds:
        for arm in arms.values():
            run = (arm.name, arm.seed_of(s))
            first = runs.setdefault(os.path.abspath(arm.run_dir(s)), run)
            if first != run:
                raise UserError(
                    f"{src}: arm {run[0]!r}, seed {run[1]} and arm {first[0]!r}, "
                    f"seed {first[1]} are one directory ({arm.run_dir(s)}): each "
                    "run needs its own"
                )


def _text(v: Any, key: str, src: str) -> str:
    if not isinstance(v, str) or not v.strip():
        raise UserError(f"{src}: {key} must be a non-empty string, got {v!r}")
    return v


def _seeds(v: Any, key: str, src: str) -> tuple[int, ...]:
    if v is None:
        raise UserError(f'{src}: {key} is missing (e.g. seeds = "0-4")')
    if isinstance(v, list):
        if not v or not all(isinstance(s, int) and not isinstance(s, bool)
                            for s in v):  # fmt: skip
            raise UserError(f"{src}: {key} must be a non-empty list of integers")
        v = ",".join(map(str, v))
    if not isinstance(v, str):
        raise UserError(f'{src}: {key} must be like "0-4" or [0, 1], got {v!r}')
    try:
        return tuple(parse_seeds(v))
    except ValueError as e:
        raise UserError(f"{src}: {key} {e}") from None


def _known(d: dict[str, Any], keys: tuple[str, ...], table: str, src: str) -> None:
    """``UserError`` naming the first key of table ``d`` not among ``keys``."""
    unknown = sorted(set(d) - set(keys))
    if unknown:
        raise UserError(
            f"{src}: {table}.{unknown[0]}: unknown key; choose from " + ", ".join(keys)
        )


def _evaluation(d: Any, src: str) -> Evaluation:
    if not isinstance(d, dict):
        raise UserError(f"{src}: [evaluation] must be a table")
    _known(d, EVALUATION_KEYS, "evaluation", src)
    terrains = None
    if "terrain_seeds" in d:
        terrains = _seeds(d["terrain_seeds"], "evaluation.terrain_seeds", src)
    subs: tuple[int | None, ...] = (None,)
    if "substeps" in d:
        v = d["substeps"]
        v = [v] if isinstance(v, int) else v
        if (
            not isinstance(v, list)
            or not v
            or not all(isinstance(s, int) and not isinstance(s, bool) for s in v)
            or not all(1 <= s <= MAX_SUBSTEPS for s in v)
            or len(set(v)) != len(v)
        ):
            raise UserError(
                f"{src}: evaluation.substeps must be distinct integers in "
                f"1..{MAX_SUBSTEPS}, got {d['substeps']!r}"
            )
        subs = tuple(v)
    return Evaluation(terrains, subs)


def _primary(
    d: Any, arms: dict[str, Arm], reference: str | None, ev: Evaluation, src: str
) -> Primary:
    """The ``[primary]`` table checked against the arms and the evaluation."""
    if not isinstance(d, dict):
        raise UserError(f"{src}: [primary] must be a table")
    _known(d, PRIMARY_KEYS, "primary", src)
    v = d.get("pairs")
    if (
        not isinstance(v, list)
        or not v
        or not all(isinstance(p, list) and len(p) == 2 for p in v)
        or not all(isinstance(a, str) for p in v for a in p)
    ):
        raise UserError(
            f"{src}: primary.pairs must be a list of arm pairs, e.g. "
            f'[["a", "b"]], got {v!r}'
        )
    for x, y in v:
        for a in (x, y):
            if a not in arms or not arms[a].score:
                raise UserError(f"{src}: primary.pairs: {a!r} is not a scored arm")
        if x == y:
            raise UserError(f"{src}: primary.pairs: {x!r} is compared with itself")
        if reference is not None and reference not in (x, y):
            raise UserError(
                f"{src}: primary.pairs: the table compares each arm with the "
                f"reference {reference!r}, not {x!r} with {y!r}"
            )
    subs = d.get("substeps", ev.substeps[0])
    listed: list[Any] = subs if isinstance(subs, list) and subs else [subs]
    for sub in listed:
        if sub not in ev.substeps or isinstance(sub, (bool, float)):
            shown = [s for s in ev.substeps if s is not None] or "as trained only"
            raise UserError(
                f"{src}: primary.substeps {subs!r} is not one the study scores "
                f"at, or a list of them ({shown})"
            )
    score = d.get("score", "full")
    if score not in PRIMARY_SCORES:
        raise UserError(
            f"{src}: primary.score {score!r}: choose from {', '.join(PRIMARY_SCORES)}"
        )
    pairs = tuple((x, y) for x, y in v)
    return Primary(pairs, tuple(dict.fromkeys(listed)), score)
