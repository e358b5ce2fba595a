"""A run's configuration: what determines its result, checked and hashed.

``TrainConfig`` is what ``config.toml`` holds::

    behaviour = "kick"
    seed = 0
    generations = 1000
    engine = "numba"     # how the controllers are computed (sim.engine.ENGINES)

    [optimizer]          # kind + that optimizer's settings (locustjump.evo)
    kind = "rcga"
    population = 50

    [model]              # LocustParams: the creature and its physics
    scale = 1.0

Runs made before optimizers were pluggable hold an ``[rcga]`` table instead of
``[optimizer]``; it is read as ``kind = "rcga"`` and hashes the same, so they
stay valid. Runs made before the engine was the run's hold it as
``model.engine``, and runs made before the compiled engine hold none ("numpy");
both are read as ``engine`` and hash the same. Files are read and written by
:mod:`locustjump.rundir`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

from locustjump.errors import UserError
from locustjump.evo import RCGAParams, params_class
from locustjump.sim import model as lm
from locustjump.sim.engine.job import DEFAULT_ENGINE, ENGINES
from locustjump.tasks import behaviour_class, behaviour_names
from locustjump.tasks.base import CommonOptions

#: LocustParams fields newer than the shipped runs: in the config hash only
#: when not at their default (the default is the creature those runs used)
_LATER_MODEL_FIELDS = ("strut_stiffness", "strut_damping", "strut_swing")
#: the engine of a run whose config holds none (made before the compiled
#: engine): in the hash only when it is another one, under ``model.engine``
#: where it was hashed before it was the run's
_ENGINE_BEFORE = "numpy"


@dataclass(frozen=True)
class TrainConfig:
    """Everything that determines a run's result (threads and backends do not:
    any number of threads, any backend gives the same result)."""

    behaviour: str = "kick"
    seed: int = 0
    generations: int = 1000  # paper: 1000
    optimizer: Any = field(default_factory=RCGAParams)  # an optimizer's settings
    model: lm.LocustParams = field(default_factory=lm.LocustParams)
    #: how the controllers are computed between physics calls
    #: (:data:`~locustjump.sim.engine.job.ENGINES`): not the creature, but
    #: recorded, since the engines differ by a few ulp a step
    engine: str = DEFAULT_ENGINE
    #: behaviours built on frozen runs (composed): digest of their genomes
    simple: str = ""
    #: the behaviour's settings beyond the paper (its ``Options``; default: its
    #: defaults, the paper's)
    options: Any = None

    def __post_init__(self) -> None:
        if self.behaviour not in behaviour_names():
            raise ValueError(
                f"unknown behaviour {self.behaviour!r}; "
                f"choose from {', '.join(behaviour_names())}"
            )
        if self.generations < 1:
            raise ValueError(f"generations must be >= 1, got {self.generations}")
        if self.seed < 0:
            raise ValueError(f"seed must be >= 0, got {self.seed}")
        if self.engine not in ENGINES:
            raise ValueError(
                f"engine must be one of {', '.join(ENGINES)}, got {self.engine!r}"
            )
        params_class(getattr(self.optimizer, "kind", None))
        kind = behaviour_class(self.behaviour).Options
        if self.options is None:
            object.__setattr__(self, "options", kind())
        elif not isinstance(self.options, kind):
            raise ValueError(
                f"{self.behaviour} takes {kind.__name__} options, "
                f"got {type(self.options).__name__}"
            )

    @property
    def population(self) -> int:
        return self.optimizer.population

    def replace(self, **changes: Any) -> TrainConfig:
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """As written to ``config.toml``."""
        d = {
            "behaviour": self.behaviour,
            "seed": self.seed,
            "generations": self.generations,
            "engine": self.engine,
            "optimizer": {"kind": self.optimizer.kind, **_table(self.optimizer)},
            "model": _table(self.model),
        }
        if self.simple:
            d["simple"] = self.simple
        if dataclasses.fields(self.options):
            d["options"] = _table(self.options)
        return d

    def hash(self) -> str:
        """Identity of the experiment: everything but ``generations`` (a run may
        be extended), as 16 hex digits. The RCGA's settings hash under the key
        ``rcga`` and model fields and options added after runs were shipped
        count only when changed, so runs made before keep their hash."""
        d = self.to_dict()
        del d["generations"]
        engine = d.pop("engine")
        if engine != _ENGINE_BEFORE:  # where it was hashed when in LocustParams
            d["model"]["engine"] = engine
        opt = d.pop("optimizer")
        if opt.pop("kind") == "rcga":
            d["rcga"] = opt
        else:
            d["optimizer"] = {"kind": self.optimizer.kind, **opt}
        default = lm.LocustParams()
        for name in _LATER_MODEL_FIELDS:
            if d["model"][name] == getattr(default, name):
                del d["model"][name]
        if self.options == type(self.options)():  # runs made before options
            d.pop("options", None)
        elif "options" in d:  # options added later count only when changed
            common = _table(CommonOptions())
            for name, value in common.items():
                if d["options"][name] == value:
                    del d["options"][name]
        text = json.dumps(d, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str) -> TrainConfig:
        """Checked conversion; a ``UserError`` names ``source`` and the key."""
        top = {"behaviour": "kick", "seed": 0, "generations": 1000, "simple": "",
               "engine": DEFAULT_ENGINE}  # fmt: skip
        kwargs: dict[str, Any] = {}
        options = None
        if "rcga" in d and "optimizer" in d:
            raise UserError(f"{source}: give [optimizer] or the older [rcga], not both")
        model = d.get("model")
        if "engine" in d and isinstance(model, dict) and "engine" in model:
            raise UserError(f"{source}: give engine or the older model.engine, not two")
        for key, value in d.items():
            if key in top:
                kwargs[key] = coerce(value, top[key], key, source)
            elif key == "rcga":
                kwargs["optimizer"] = from_table(RCGAParams, value, key, source)
            elif key == "optimizer":
                kwargs["optimizer"] = optimizer_from_table(value, source)
            elif key == "model":
                if isinstance(value, dict):  # the engine was once the creature's
                    value = dict(value)
                    older = value.pop("engine", _ENGINE_BEFORE)
                    if "engine" not in d:
                        kwargs["engine"] = coerce(older, "", "model.engine", source)
                kwargs[key] = from_table(lm.LocustParams, value, key, source)
            elif key == "options":
                options = value
            else:
                raise UserError(f"{source}: unknown key {key!r}")
        if options is not None:  # the behaviour's own settings
            try:
                kind = behaviour_class(
                    kwargs.get("behaviour", top["behaviour"])
                ).Options
            except ValueError as e:
                raise UserError(f"{source}: {e}") from None
            kwargs["options"] = from_table(kind, options, "options", source)
        try:
            return cls(**kwargs)
        except ValueError as e:
            raise UserError(f"{source}: {e}") from None


def _table(obj: Any) -> dict[str, Any]:
    return {
        f.name: list(v) if isinstance(v := getattr(obj, f.name), tuple) else v
        for f in dataclasses.fields(obj)
    }


def optimizer_from_table(table: Any, source: str) -> Any:
    """An ``[optimizer]`` table (``kind`` + settings) as that optimizer's settings."""
    if not isinstance(table, dict):
        raise UserError(f"{source}: optimizer must be a table")
    table = dict(table)
    kind = table.pop("kind", "rcga")
    if not isinstance(kind, str):
        raise UserError(f"{source}: optimizer.kind must be a string, got {kind!r}")
    try:
        cls = params_class(kind)
    except ValueError as e:
        raise UserError(f"{source}: optimizer.kind: {e}") from None
    return from_table(cls, table, "optimizer", source)


def coerce(value: Any, default: Any, key: str, source: str) -> Any:
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
    elif default == ():  # a list of integers of any length
        if not isinstance(value, list):
            raise UserError(
                f"{source}: {key} must be an array of integers, got {value!r}"
            )
        return tuple(coerce(v, 0, f"{key}[{i}]", source) for i, v in enumerate(value))
    elif isinstance(default, tuple):
        if not isinstance(value, list) or len(value) != len(default):
            raise UserError(
                f"{source}: {key} must be an array of {len(default)} numbers, "
                f"got {value!r}"
            )
        return tuple(
            coerce(v, d, f"{key}[{i}]", source)
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


def from_table(cls: type, table: Any, section: str, source: str) -> Any:
    """A frozen dataclass ``cls`` from a TOML table, every key checked."""
    if not isinstance(table, dict):
        raise UserError(f"{source}: {section} must be a table")
    defaults = cls()
    names = {f.name for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, value in table.items():
        if key not in names:
            raise UserError(f"{source}: unknown key '{section}.{key}'")
        kwargs[key] = coerce(value, getattr(defaults, key), f"{section}.{key}", source)
    try:
        return cls(**kwargs)
    except ValueError as e:
        raise UserError(f"{source}: [{section}] {e}") from None
