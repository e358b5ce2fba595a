"""A run's configuration: what determines its result, checked and hashed.

``TrainConfig`` is what ``config.toml`` holds::

    behaviour = "kick"
    seed = 0
    generations = 1000
    engine = "numba"     # how the controllers are computed (sim.engine.ENGINES)
    format = 2           # of this file (locustjump.rundir.migrations)

    [optimizer]          # kind + that optimizer's settings (locustjump.evo)
    kind = "rcga"
    population = 50

    [model]              # LocustParams: the creature and its physics
    scale = 1.0

    [scene]              # the world (locustjump.sim.scene): its kind, its
    kind = "debris"      # parameters, and the training terrains: seeds
    seed = 0             # seed .. seed + terrains - 1, fitness combined by
    terrains = 4         # aggregate ("mean" or "min"); default: the flat floor
    aggregate = "mean"

    [plugins]            # only with a plugin's optimizer, behaviour or scene:
    "myplugin.hill" = "myplugin"   # module = its distribution (not hashed)

Older spellings (``[rcga]``, ``model.engine``, ``simple``) are read by
:mod:`locustjump.rundir.migrations` and hash as they did, so older runs stay
valid. Files are read and written by :mod:`locustjump.rundir`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

from locustjump import plugins
from locustjump.errors import UserError
from locustjump.evo import QDParams, RCGAParams, optimizer_kinds, params_class
from locustjump.evo.base import SEED, OptimizerParams
from locustjump.ranges import (
    INT64_MAX,
    Range,
    SettingError,
    SettingTypeError,
    check_choice,
    check_settings,
    check_type,
    setting,
)
from locustjump.rundir.migrations import (
    CONFIG_FORMAT,
    hashed_config,
    migrate_config,
    scene_before,
)
from locustjump.sim import model as lm
from locustjump.sim.engine.job import DEFAULT_ENGINE, ENGINES
from locustjump.sim.scene import DEFAULT_SCENE, Terrains, scene_class
from locustjump.tasks import behaviour_class, behaviour_names
from locustjump.tasks.base import CommonOptions

#: ``generations``: a run's length (a resumed run may extend it)
GENERATIONS = Range(1, INT64_MAX, integer=True)


@dataclass(frozen=True)
class TrainConfig:
    """Everything that determines a run's result (threads and backends do not:
    any number of threads, any backend gives the same result)."""

    behaviour: str = "kick"
    #: of the optimizer: same seed, same run
    seed: int = setting(0, SEED)
    #: generations to train (paper: 1000)
    generations: int = setting(1000, GENERATIONS)
    #: an optimizer's settings
    optimizer: OptimizerParams = field(default_factory=RCGAParams)
    model: lm.LocustParams = field(default_factory=lm.LocustParams)
    #: how the controllers are computed between physics calls
    #: (:data:`~locustjump.sim.engine.job.ENGINES`): not the creature, but
    #: recorded, since the engines differ by a few ulp a step
    engine: str = DEFAULT_ENGINE
    #: behaviours built on frozen runs (composed): digest of their genomes
    frozen_digest: str = ""
    #: the behaviour's settings beyond the paper (its ``Options``; default: its
    #: defaults, the paper's)
    options: Any = None
    #: the world and the terrains a genome is scored on (default: the flat floor)
    scene: Terrains = field(default_factory=Terrains)

    def __post_init__(self) -> None:
        check_choice("behaviour", self.behaviour, behaviour_names())
        check_settings(self)
        check_choice("engine", self.engine, ENGINES)
        check_type("frozen_digest", self.frozen_digest, str, "text")
        kinds = ", ".join(params_class(k).__name__ for k in optimizer_kinds())
        what = f"an optimizer's settings ({kinds})"
        if not hasattr(self.optimizer, "kind"):
            raise SettingTypeError("optimizer", what, self.optimizer)
        # a kind no optimizer has: ValueError; another class of that kind's
        check_type("optimizer", self.optimizer, params_class(self.optimizer.kind), what)
        check_type("model", self.model, lm.LocustParams, "LocustParams")
        check_type("scene", self.scene, Terrains, "Terrains (e.g. Terrains(Debris()))")
        if isinstance(self.optimizer, QDParams):  # the task's descriptors
            cls = behaviour_class(self.behaviour)
            declared = {d.name: (d.low, d.high) for d in cls.descriptors}
            opt = self.optimizer.with_task(
                self.behaviour, declared, cls.default_descriptors
            )
            object.__setattr__(self, "optimizer", opt)
        kind = behaviour_class(self.behaviour).Options
        if self.options is None:
            object.__setattr__(self, "options", kind())
        elif not isinstance(self.options, kind):
            raise SettingTypeError(
                "options", f"{kind.__name__} (the {self.behaviour} behaviour's)",
                self.options,
            )  # fmt: skip

    @property
    def population(self) -> int:
        population: int = self.optimizer.population
        return population

    def replace(self, **changes: Any) -> TrainConfig:
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict[str, Any]:
        """As written to ``config.toml``."""
        d = {
            "format": CONFIG_FORMAT,
            "behaviour": self.behaviour,
            "seed": self.seed,
            "generations": self.generations,
            "engine": self.engine,
            "optimizer": {"kind": self.optimizer.kind, **_table(self.optimizer)},
            "model": _table(self.model),
        }
        if self.frozen_digest:
            d["frozen_digest"] = self.frozen_digest
        if dataclasses.fields(self.options):
            d["options"] = _table(self.options)
        d["scene"] = scene_table(self.scene)
        if used := self.plugin_modules():
            d["plugins"] = used
        return d

    def plugin_modules(self) -> dict[str, str]:
        """The plugin modules its optimizer, behaviour, options and scene come
        from, each with its distribution (:func:`locustjump.plugins.provenance`)."""
        return plugins.provenance(
            (type(self.optimizer), behaviour_class(self.behaviour),
             type(self.options), type(self.scene.scene))
        )  # fmt: skip

    def hash(self) -> str:
        """Identity of the experiment: everything but ``generations`` (a run may
        be extended), as 16 hex digits, of the table as format 1 spelled it
        (:func:`~locustjump.rundir.migrations.hashed_config`), so that runs
        made before keep their hash."""
        d = self.to_dict()
        del d["generations"], d["format"]
        d.pop("plugins", None)  # where the classes came from, not what they do
        if self.scene == Terrains():  # runs made before scenes keep their hash
            del d["scene"]
        d = hashed_config(
            d,
            _table(lm.LocustParams()),
            _table(CommonOptions()),
            self.options == type(self.options)(),
        )
        text = json.dumps(d, sort_keys=True)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str) -> TrainConfig:
        """Checked conversion; a ``UserError`` names ``source`` and the key
        (or the plugin the file names that is missing here, if one is)."""
        d = dict(d)
        used = d.pop("plugins", {})
        if not (
            isinstance(used, dict) and all(isinstance(v, str) for v in used.values())
        ):
            raise UserError(f"{source}: plugins must be a table of strings")
        try:  # the lookups load the plugins' entry points
            return cls._from_dict(d, source)
        except UserError:
            plugins.check_loaded(used, source)  # the reason, if it is one
            raise

    @classmethod
    def _from_dict(cls, d: dict[str, Any], source: str) -> TrainConfig:
        top = {"behaviour": "kick", "seed": 0, "generations": 1000,
               "frozen_digest": "", "engine": DEFAULT_ENGINE}  # fmt: skip
        kwargs: dict[str, Any] = {}
        options = None
        for key, value in migrate_config(d, source).items():
            if key in top:
                kwargs[key] = coerce(value, top[key], key, source)
            elif key == "optimizer":
                section = "rcga" if "rcga" in d else key  # as the file names it
                kwargs["optimizer"] = optimizer_from_table(value, source, section)
            elif key == "model":
                kwargs[key] = from_table(lm.LocustParams, value, key, source)
            elif key == "options":
                options = value
            elif key == "scene":
                kwargs[key] = terrains_from_table(value, source)
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
        except (ValueError, SettingError) as e:
            raise UserError(f"{source}: {e}") from None


def scene_table(t: Terrains) -> dict[str, Any]:
    """``[scene]`` as written: ``kind``, the scene's fields, ``terrains`` and
    ``aggregate``."""
    return {
        "kind": t.scene.name,
        **_table(t.scene),
        "terrains": t.count,
        "aggregate": t.aggregate,
    }


def terrains_from_table(table: Any, source: str) -> Terrains:
    """A ``[scene]`` table (every key checked) as the training terrains."""
    table, cls = _kind(table, "scene", DEFAULT_SCENE, scene_class, source)
    top = {"terrains": 1, "aggregate": "mean"}
    extra = {k: coerce(table.pop(k), v, f"scene.{k}", source)
             for k, v in top.items() if k in table}  # fmt: skip
    fields = [f.name for f in dataclasses.fields(cls)]
    scene = from_table(cls, scene_before(cls.name, table, fields), "scene", source)
    try:
        return Terrains(scene, extra.get("terrains", 1), extra.get("aggregate", "mean"))
    except (ValueError, SettingError) as e:
        raise UserError(f"{source}: [scene] {e}") from None


def _table(obj: Any) -> dict[str, Any]:
    return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj)}


def _plain(v: Any) -> Any:
    """Tuples (of tuples) as lists, as TOML and JSON hold them."""
    return [_plain(x) for x in v] if isinstance(v, tuple) else v


def optimizer_from_table(table: Any, source: str, section: str = "optimizer") -> Any:
    """An ``[optimizer]`` table (``kind`` + settings) as that optimizer's
    settings (``section``: its name in the file, for the errors)."""
    if not isinstance(table, dict):
        raise UserError(f"{source}: {section} must be a table")
    table, cls = _kind(table, "optimizer", "rcga", params_class, source)
    return from_table(cls, table, section, source)


T = TypeVar("T")


def _kind(
    table: Any,
    section: str,
    default: str,
    lookup: Callable[[str], type[T]],
    source: str,
) -> tuple[dict[str, Any], type[T]]:
    """A ``[section]`` table without its ``kind`` key, and the class that
    ``kind`` (default ``default``) names through ``lookup``; errors name the
    file ``source``."""
    if not isinstance(table, dict):
        raise UserError(f"{source}: {section} must be a table")
    table = dict(table)
    kind = table.pop("kind", default)
    if not isinstance(kind, str):
        raise UserError(f"{source}: {section}.kind must be a string, got {kind!r}")
    try:
        return table, lookup(kind)
    except ValueError as e:
        raise UserError(f"{source}: {section}.kind: {e}") from None


def coerce(value: Any, default: Any, key: str, source: str, item: Any = 0) -> Any:
    """``value`` as the type of ``default``, or a ``UserError`` naming ``key``;
    an empty tuple ``default`` takes an array of any length, each entry as
    the type of ``item`` (an integer unless the field's metadata names
    another ``item``)."""
    ok: bool
    if isinstance(default, bool):
        ok = isinstance(value, bool)
    elif isinstance(default, int):
        ok = isinstance(value, int) and not isinstance(value, bool)
        if ok and not -(2**63) <= value < 2**63:
            raise UserError(
                f"{source}: {key} must be a 64-bit integer (TOML's), got {value}"
            )
    elif isinstance(default, float):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        value = float(value) if ok else value
    elif isinstance(default, str):
        ok = isinstance(value, str)
    elif default == ():  # a list of any length
        if not isinstance(value, list):
            what = {int: "integers", str: "strings"}.get(type(item), "arrays")
            raise UserError(
                f"{source}: {key} must be an array of {what}, got {value!r}"
            )
        return tuple(
            coerce(v, item, f"{key}[{i}]", source) for i, v in enumerate(value)
        )
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
    items = {f.name: f.metadata.get("item", 0) for f in dataclasses.fields(cls)}
    kwargs = {}
    for key, value in table.items():
        if key not in items:
            raise UserError(f"{source}: unknown key '{section}.{key}'")
        kwargs[key] = coerce(
            value, getattr(defaults, key), f"{section}.{key}", source, items[key]
        )
    try:
        return cls(**kwargs)
    except (ValueError, SettingError) as e:
        raise UserError(f"{source}: [{section}] {e}") from None
