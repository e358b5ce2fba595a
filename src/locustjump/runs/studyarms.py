"""A study's arms (:mod:`~locustjump.runs.studyfile`): each arm's
``config.toml`` keys merged over the study's ``[defaults]``, its own keys
(:data:`ARM_KEYS`: ``frozen``, ``score``, ``path``/``paths``, ``label``,
``terrain_stride``, ``extends``, a fixed ``seed``) checked, and the arms ordered so that
each follows the arms it builds on."""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from locustjump.errors import UserError
from locustjump.ranges import INT64_MAX
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.migrations import CONFIG_FORMAT
from locustjump.tasks import behaviour_class

#: an arm's keys that are the study's, not config.toml's
ARM_KEYS = ("frozen", "score", "path", "paths", "label", "terrain_stride", "extends")


@dataclass(frozen=True)
class Arm:
    """One arm: its configuration for seed 0 (:meth:`config` for others), the
    arms it builds on, and where its runs are."""

    name: str
    label: str
    base: TrainConfig
    frozen: dict[str, str]  # behaviour it requires -> arm
    score: bool
    path: str  # a template with {seed}
    paths: dict[int, str]
    #: one run shared by every seed of the study (an arm's ``seed = S``)
    fixed_seed: int | None = None
    #: each seed trains on its own terrains: seed s's first is the scene's
    #: seed + terrain_stride x s (0: every seed on the scene's terrains)
    terrain_stride: int = 0
    #: a template with {seed}: each run starts as a copy of that finished run
    #: (the same configuration, fewer generations) and trains on
    extends: str | None = None

    def seed_of(self, seed: int) -> int:
        """The seed of this arm's run for the study's ``seed``."""
        return seed if self.fixed_seed is None else self.fixed_seed

    def config(self, seed: int) -> TrainConfig:
        s = self.seed_of(seed)
        cfg = self.base.replace(seed=s)
        if self.terrain_stride:
            t = cfg.scene
            seed = getattr(t.scene, "seed", 0)  # seeded: _stride saw to it
            first = t.scene.with_seed(seed + self.terrain_stride * s)
            cfg = cfg.replace(scene=dataclasses.replace(t, scene=first))
        return cfg

    def run_dir(self, seed: int) -> Path:
        s = self.seed_of(seed)
        return Path(self.paths.get(s, self.path).format(seed=s))

    def source_dir(self, seed: int) -> Path | None:
        """The run that this arm's run of ``seed`` continues, if it extends one."""
        return (
            None
            if self.extends is None
            else Path(self.extends.format(seed=self.seed_of(seed)))
        )


def _text(v: Any, key: str, src: str) -> str:
    if not isinstance(v, str) or not v.strip():
        raise UserError(f"{src}: {key} must be a non-empty string, got {v!r}")
    return v


def _template(v: Any, key: str, where: str) -> str:
    """A directory whose only field is ``{seed}`` (none is fine), formatted
    as any seed can be: the least and the largest are tried."""
    text = _text(v, key, where)
    try:
        for seed in (0, INT64_MAX):
            text.format(seed=seed)
    except (KeyError, IndexError, ValueError, AttributeError, TypeError,
            OverflowError):  # fmt: skip
        message = f"{where}: {key} {text!r}: the only field is {{seed}}, an integer"
        raise UserError(message) from None
    return text


def _merged(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``over`` on ``base``, tables merged key by key (a scene or optimizer
    table naming another ``kind`` than the default's replaces it whole)."""
    out = copy.deepcopy(base)
    for k, v in over.items():
        if (
            isinstance(v, dict)
            and isinstance(out.get(k), dict)
            and not ("kind" in v and "kind" in out[k] and v["kind"] != out[k]["kind"])
        ):
            out[k] = _merged(out[k], v)
        else:
            out[k] = copy.deepcopy(v)
    return out


def parse_arms(d: Any, defaults: Any, root: Path, src: str) -> dict[str, Arm]:
    """The arms of a study file ``src`` (its ``[arms]`` over ``defaults``;
    new runs under ``root``), checked and ordered."""
    if not isinstance(d, dict) or not d:
        raise UserError(f"{src}: no arms (add an [arms.NAME] table)")
    if not isinstance(defaults, dict):
        raise UserError(f"{src}: [defaults] must be a table")
    for key in (*ARM_KEYS, "seed", "format"):  # an arm's own
        if key in defaults:
            raise UserError(f"{src}: defaults.{key}: an arm's own key, not a default")
    arms: dict[str, Arm] = {}
    for name, table in d.items():
        where = f"{src} [arms.{name}]"
        if not isinstance(table, dict):
            raise UserError(f"{where}: must be a table")
        if "format" in table:
            raise UserError(f"{where}: format: an arm is today's config.toml spelling")
        own = {k: table[k] for k in ARM_KEYS if k in table}
        # today's spelling: an arm is never read as an older config.toml
        merged = _merged(defaults, {k: v for k, v in table.items() if k not in own})
        cfg = TrainConfig.from_dict({"format": CONFIG_FORMAT, **merged}, where)
        fixed = cfg.seed if "seed" in table else None
        if fixed is not None and own.get("score", True):
            raise UserError(
                f"{where}: seed: a scored arm has a run per seed of the study; "
                "a fixed seed is for an arm others build on (score = false)"
            )
        arms[name] = Arm(
            name,
            _text(own.get("label", name), "label", where),
            cfg,
            _frozen(own.get("frozen", {}), cfg, where),
            _bool(own.get("score", True), "score", where),
            _template(own.get("path", str(root / name / "seed-{seed}")), "path", where),
            _paths(own.get("paths", {}), where),
            fixed,
            _stride(own.get("terrain_stride", 0), cfg, where),
            _template(own["extends"], "extends", where) if "extends" in own else None,
        )
    labelled: dict[str, str] = {}
    for a in arms.values():
        for b in a.frozen.values():
            if b not in arms:
                raise UserError(
                    f"{src} [arms.{a.name}]: frozen: no arm {b!r} in this study"
                )
        if a.label in labelled:  # the table and its figure name arms by label
            raise UserError(f"{src} [arms.{a.name}]: label {a.label!r} is arm "
                            f"{labelled[a.label]!r}'s already")  # fmt: skip
        labelled[a.label] = a.name
    return _ordered(arms, src)


def _stride(v: Any, cfg: TrainConfig, where: str) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < 2**31:
        raise UserError(f"{where}: terrain_stride must be an integer >= 0, got {v!r}")
    scene = cfg.scene.scene
    if v and not scene.seeded:
        raise UserError(
            f"{where}: terrain_stride: the {scene.name} scene has no terrains to "
            "choose from"
        )
    if v and v < cfg.scene.count:
        raise UserError(
            f"{where}: terrain_stride {v} < terrains {cfg.scene.count}: the seeds' "
            "training terrains would overlap"
        )
    return v


def _bool(v: Any, key: str, where: str) -> bool:
    if not isinstance(v, bool):
        raise UserError(f"{where}: {key} must be true or false, got {v!r}")
    return v


def _paths(v: Any, where: str) -> dict[int, str]:
    if not isinstance(v, dict):
        raise UserError(f'{where}: paths must be a table of seed = "DIR"')
    out = {}
    for k, p in v.items():
        if not k.isdigit():
            raise UserError(f"{where}: paths: {k!r} is not a seed")
        out[int(k)] = _template(p, f"paths.{k}", where)
    return out


def _frozen(v: Any, cfg: TrainConfig, where: str) -> dict[str, str]:
    """The arm each behaviour ``cfg`` builds on comes from."""
    required = behaviour_class(cfg.behaviour).requires
    if not isinstance(v, dict) or not all(isinstance(x, str) for x in v.values()):
        raise UserError(f'{where}: frozen must be a table of behaviour = "ARM"')
    if set(v) != set(required):
        if not required:
            raise UserError(f"{where}: frozen: {cfg.behaviour} builds on no runs")
        raise UserError(
            f"{where}: frozen must name the arm of each of "
            + ", ".join(required)
            + (f" (got {', '.join(sorted(v))})" if v else "")
        )
    return {r: v[r] for r in required}


def _ordered(arms: dict[str, Arm], src: str) -> dict[str, Arm]:
    """The arms in file order, each moved after the arms it builds on."""
    done: dict[str, Arm] = {}

    def visit(name: str, path: tuple[str, ...]) -> None:
        if name in done:
            return
        if name in path:
            raise UserError(
                f"{src}: the arms build on each other in a circle: "
                + " -> ".join((*path, name))
            )
        for dep in arms[name].frozen.values():
            visit(dep, (*path, name))
        done[name] = arms[name]

    for name in arms:
        visit(name, ())
    return done
