"""Every reader of an older file format, in one place.

Each file that has changed records its format version; a reader checks it
(a newer one than this locustjump reads is refused with a one-line error)
and hands an older one to the migration here, which returns it in today's
form. Nothing on disk is rewritten: a run made by an older version stays as
it was and replays on the path it was made with.

``config.toml`` (:data:`CONFIG_FORMAT`; a file without ``format`` is version 1,
which every run made before 2026-11 holds, and any partial ``--config`` file):

* ``[rcga]`` instead of ``[optimizer]`` (before optimizers were pluggable):
  ``kind = "rcga"``;
* ``model.engine`` (before the engine was the run's): the run's ``engine``;
  no engine at all beside a whole ``[model]`` table (a run's own file from
  before the compiled engine): ``"numpy"``; a partial one (a hand-written
  ``--config``) gets today's default;
* ``simple`` (the digest of the frozen genomes): ``frozen_digest``.

The config hash is the identity of an experiment, so it is computed on the
table as version 1 spelled it (:func:`hashed_config`): every run keeps its
hash whatever version reads it.

``checkpoint.npz``, ``best.npz``, ``frozen.npz`` (``format``, :data:`~.layout.FORMAT`,
checked by :func:`npz_format`): a checkpoint written before optimizers were
pluggable names no optimizer and holds the RCGA's state unprefixed
(:func:`checkpoint_state`).

``[scene]`` (wherever it is read: ``config.toml``, ``reproduce.toml``, a
rule-based run's ``summary.json``, a ``--scene`` file; :func:`scene_before`):
a scene parameter added after runs were shipped (:data:`SCENE_FIELDS_LATER`:
the debris field's ``wall_height``, 2026-11-24, and ``wall_margin``,
2026-11-26) is absent from a table that names every other parameter of its
scene, as locustjump wrote it before: there it takes the value its absence
meant (no walls; walls without a margin). A table written before several were
added lacks the last of them, in the order they came (a walled field's table
lacks ``wall_margin``, an open field's both). Any other partial table, as a
person writes one, gets today's defaults. Each is in the hash only when not
at that value, so those runs keep theirs.

``reproduce.toml``: keys added later take the value their absence meant
(:func:`reproduction_marker`). ``summary.json`` of a rule-based run: the
engine under ``model`` as above (:func:`rules_summary`). The frozen genomes
of a composed run: ``simple.npz`` before version 2 (:func:`frozen_path`).
"""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from locustjump.errors import UserError
from locustjump.rundir.layout import FORMAT, FROZEN, SEEDS_MARKER
from locustjump.sim.params import LocustParams

#: version of ``config.toml`` this locustjump writes
CONFIG_FORMAT = 2
#: what the frozen genomes' file was called before config format 2
FROZEN_BEFORE = "simple.npz"
#: the engine of a run whose config names none (made before the compiled one)
ENGINE_BEFORE = "numpy"
#: ``reproduce.toml`` keys added later, and what their absence means
MARKER_BEFORE = {
    "optimizer": "rcga",
    "engine": ENGINE_BEFORE,
    "scene": {"kind": "flat", "terrains": 1, "aggregate": "mean"},  # the floor
}
#: keys of the optimizer's state in a checkpoint, prefixed so they never clash
#: with the run's
STATE_PREFIX = "opt_"
#: what checkpoints written before optimizers were pluggable hold (the RCGA's)
RCGA_STATE_BEFORE = ("generation", "population", "fitness", "rng_state")
#: ``[scene]`` parameters added after runs were shipped, per scene kind, in
#: the order they were added, and what their absence meant
SCENE_FIELDS_LATER: dict[str, dict[str, Any]] = {
    "debris": {"wall_height": 0.0, "wall_margin": 0.0}
}
#: ``[model]`` fields added after runs were shipped: in the hash only when not
#: at their default (the creature those runs used)
MODEL_FIELDS_LATER = ("strut_stiffness", "strut_damping", "strut_swing")


def config_format(d: dict[str, Any], source: str) -> int:
    """The format version of a ``config.toml`` table (``UserError`` if it is
    not one this locustjump reads)."""
    v = d.get("format", 1)
    if not isinstance(v, int) or isinstance(v, bool) or v < 1:
        raise UserError(f"{source}: format must be an integer >= 1, got {v!r}")
    if v > CONFIG_FORMAT:
        raise UserError(
            f"{source}: written by a newer locustjump (config format {v}; this "
            f"one reads up to {CONFIG_FORMAT}); upgrade locustjump"
        )
    return v


def migrate_config(d: dict[str, Any], source: str) -> dict[str, Any]:
    """A ``config.toml`` table in today's spelling (without ``format``)."""
    version = config_format(d, source)
    d = copy.deepcopy({k: v for k, v in d.items() if k != "format"})
    if version >= 2:
        return d
    if "rcga" in d:
        if "optimizer" in d:
            raise UserError(f"{source}: give [optimizer] or the older [rcga], not both")
        rcga = d.pop("rcga")
        d["optimizer"] = {"kind": "rcga", **rcga} if isinstance(rcga, dict) else rcga
    model = d.get("model")
    if isinstance(model, dict):
        if "engine" in model:
            if "engine" in d:
                raise UserError(
                    f"{source}: give engine or the older model.engine, not two"
                )
            d["engine"] = model.pop("engine")
        elif _whole_model(model):  # a run's own file, made before the engine
            d.setdefault("engine", ENGINE_BEFORE)
    if "simple" in d:
        if "frozen_digest" in d:
            raise UserError(
                f"{source}: give frozen_digest or the older simple, not both"
            )
        d["frozen_digest"] = d.pop("simple")
    return d


def _whole_model(model: dict[str, Any]) -> bool:
    """Whether a ``[model]`` table names every field locustjump wrote before
    the compiled engine (today's but :data:`MODEL_FIELDS_LATER`): a run's own
    ``config.toml`` of that time. A partial table (a hand-written ``--config``
    or a study's arm) is today's spelling: it gets today's engine."""
    names = {f.name for f in dataclasses.fields(LocustParams)}
    return names - set(MODEL_FIELDS_LATER) <= set(model)


def scene_before(kind: str, table: dict[str, Any], fields: list[str]) -> dict[str, Any]:
    """A ``[scene]`` table (without ``kind``) of scene ``kind`` whose
    parameters are ``fields``, with the parameters added later filled in
    where locustjump wrote it before they existed: it names every other, and
    lacks the last ones added (:data:`SCENE_FIELDS_LATER`)."""
    later = list(SCENE_FIELDS_LATER.get(kind, {}))
    missing = {f for f in fields if f not in table}
    k = len(missing)
    if 0 < k <= len(later) and missing == set(later[-k:]):
        return {**table, **{f: SCENE_FIELDS_LATER[kind][f] for f in missing}}
    return table


def hashed_config(
    d: dict[str, Any],
    model_defaults: dict[str, Any],
    common_defaults: dict[str, Any],
    options_default: bool,
) -> dict[str, Any]:
    """The table whose hash is a run's identity: today's ``config.toml``
    table ``d`` (without ``generations``) as format 1 spelled it.
    ``model_defaults``: the default ``[model]`` table; ``common_defaults``:
    the default options every behaviour takes (added after runs were
    shipped, so in the hash only when changed); ``options_default``: whether
    the behaviour's options are all at their defaults."""
    d = copy.deepcopy(d)
    engine = d.pop("engine")
    if engine != ENGINE_BEFORE:  # where it was hashed when it was the creature's
        d["model"]["engine"] = engine
    opt = d.pop("optimizer")
    if opt["kind"] == "rcga":
        d["rcga"] = {k: v for k, v in opt.items() if k != "kind"}
    else:
        d["optimizer"] = opt
    for name in MODEL_FIELDS_LATER:
        if d["model"][name] == model_defaults[name]:
            del d["model"][name]
    scene = d.get("scene", {})
    for name, before in SCENE_FIELDS_LATER.get(scene.get("kind"), {}).items():
        if scene.get(name) == before:
            del scene[name]
    if "frozen_digest" in d:
        d["simple"] = d.pop("frozen_digest")
    if options_default:  # runs made before options
        d.pop("options", None)
    elif "options" in d:  # options added later count only when changed
        for name, value in common_defaults.items():
            if d["options"][name] == value:
                del d["options"][name]
    return d


def npz_format(z: dict[str, np.ndarray], path: Path) -> int:
    """The format version of a run's ``.npz`` file (``UserError`` if it is not
    one this locustjump reads)."""
    try:
        v = int(z["format"])
    except (KeyError, TypeError, ValueError):
        raise UserError(f"{path}: no format version") from None
    if not 1 <= v <= FORMAT:
        raise UserError(
            f"{path}: format {v}, not one this locustjump reads (1 to {FORMAT}); "
            "a newer locustjump wrote it?"
        )
    return v


def checkpoint_optimizer(z: dict[str, np.ndarray]) -> str:
    """The optimizer kind a checkpoint was written by."""
    return str(z.get("optimizer", "rcga"))


def checkpoint_state(z: dict[str, np.ndarray], path: Path) -> dict[str, np.ndarray]:
    """The optimizer's state in a checkpoint."""
    npz_format(z, path)
    if "optimizer" in z:
        n = len(STATE_PREFIX)
        return {k[n:]: v for k, v in z.items() if k.startswith(STATE_PREFIX)}
    missing = [k for k in RCGA_STATE_BEFORE if k not in z]
    if missing:
        raise UserError(f"{path}: missing {', '.join(missing)}")
    return {k: z[k] for k in RCGA_STATE_BEFORE}


#: what every reproduction's marker has held since the first, and in what
#: form (``seeds.toml``: ``seeds``, a list, for ``seed``, and ``optimizer``)
MARKER_KEYS = {
    "budget": (str, "a budget's name"),
    "seed": (int, "a seed"),
    "population": (int, "an integer"),
    "generations": (dict, "a table of each stage's generations"),
    "command": (str, "the command"),
    "locustjump": (str, "the version"),
}


def _is(value: Any, kind: type) -> bool:
    return isinstance(value, kind) and not isinstance(value, bool)


def check_marker(table: dict[str, Any], path: Path) -> dict[str, Any]:
    """A ``reproduce.toml`` or ``seeds.toml`` table as every locustjump has
    written one (``UserError`` naming the file and the key otherwise: a
    marker no locustjump wrote, for a directory no reproduction made)."""
    keys = dict(MARKER_KEYS)
    if Path(path).name == SEEDS_MARKER:
        del keys["seed"]
        keys["seeds"] = (list, "a list of seeds")
        keys["optimizer"] = (str, "an optimizer's name")
    missing = [k for k in keys if k not in table]
    if missing:
        raise UserError(
            f"{path}: missing {', '.join(missing)} (every reproduction's marker "
            "holds them: a directory no reproduction made?)"
        )
    for key, (kind, words) in keys.items():
        v = table[key]
        ok = _is(v, kind)
        if ok and kind is dict:
            ok = all(_is(n, int) and n >= 1 for n in v.values())
        elif ok and kind is list:
            ok = all(_is(s, int) and s >= 0 for s in v)
        if not ok:
            raise UserError(f"{path}: {key} must be {words}, got {str(v)[:60]!r}")
    return table


def reproduction_marker(table: dict[str, Any]) -> dict[str, Any]:
    """A ``reproduce.toml`` table with the keys added later filled in."""
    return {**MARKER_BEFORE, **table}


def rules_summary(summary: dict[str, Any], default_engine: str) -> dict[str, Any]:
    """A rule-based run's ``summary.json`` with ``engine`` beside ``model``
    (summaries written before the creature was recorded: the default one, on
    ``default_engine``)."""
    summary = copy.deepcopy(summary)
    model = summary.setdefault("model", {})
    if isinstance(model, dict) and "engine" in model:
        summary.setdefault("engine", model.pop("engine"))
    summary.setdefault("engine", default_engine)
    return summary


def frozen_path(run: Path) -> Path:
    """The frozen genomes' file of run directory ``run``, under the name it
    was written with."""
    new, old = Path(run) / FROZEN, Path(run) / FROZEN_BEFORE
    return old if not new.exists() and old.exists() else new
