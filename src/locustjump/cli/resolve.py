"""``locustjump train``'s options resolved into the configuration it runs."""

from __future__ import annotations

import argparse
import dataclasses
import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, TypeVar

from locustjump import rundir
from locustjump.cli.options import option_flag, takers
from locustjump.errors import UserError, setting_ref
from locustjump.evo import params_class
from locustjump.ranges import SettingError
from locustjump.rundir.config import TrainConfig, terrains_from_table
from locustjump.sim.scene import Scene, Terrains, scene_class, scene_names
from locustjump.tasks.base import option_fields

_T = TypeVar("_T")


def resolve_config(
    behaviour: str,
    out: str | os.PathLike[str],
    *,
    resume: bool = False,
    config: str | os.PathLike[str] | None = None,
    optimizer: str | None = None,
    seed: int | None = None,
    population: int | None = None,
    generations: int | None = None,
    engine: str | None = None,
    options: Mapping[str, Any] | None = None,
    scene: str | None = None,
    terrain_seed: int | None = None,
    terrains: int | None = None,
) -> TrainConfig:
    """The configuration ``locustjump train`` runs: a resumed run's own
    ``config.toml``, or the defaults overridden by a ``config`` file, and then
    by the options given (resuming, :func:`~locustjump.runs.trainer.train`
    refuses any that differ from the run's but ``generations``, which may
    extend it). ``options``: the behaviour's options given (name -> value;
    those its ``Options`` declares)."""

    if resume:  # the run's own config; the trainer checks what differs
        if config is not None:
            raise UserError("--resume reads the run's own config.toml; drop --config")
        path = Path(out) / rundir.CONFIG
        if not os.path.lexists(path):
            stopped = Path(out).is_dir() and rundir.is_unstarted(Path(out))
            raise UserError(
                f"--resume: {out} holds no run (no {rundir.CONFIG})"
                + ("; it was stopped before it started: rerun without --resume"
                   if stopped else "")
            )  # fmt: skip
        cfg = rundir.load_config(path)
        if cfg.behaviour != behaviour:  # the command's behaviour, not an option
            raise UserError(
                f"--resume: {out} holds a {cfg.behaviour!r} run, not {behaviour!r}"
            )
    else:
        cfg = TrainConfig(behaviour=behaviour)
        if config is not None:
            try:
                cfg = rundir.load_config(config, behaviour=behaviour)
            except UserError as e:  # no file to read: named as the option
                if Path(config).is_file():
                    raise
                raise UserError(f"--config: {e.message}") from None
            if cfg.behaviour != behaviour:
                raise UserError(
                    f"{config}: behaviour {cfg.behaviour!r} differs from the "
                    f"command's {behaviour!r}"
                )
    # the options given, over either
    if optimizer is not None and optimizer != cfg.optimizer.kind:
        try:
            cfg = cfg.replace(optimizer=params_class(optimizer)())
        except ValueError as e:
            raise UserError(f"--optimizer: {e}") from None
    if seed is not None:
        cfg = _checked("--seed", cfg.replace, seed=seed)
    if engine is not None:
        cfg = cfg.replace(engine=engine)
    cfg = cfg.replace(scene=terrains_arg(scene, terrain_seed, terrains, cfg.scene))
    for name, value in (options or {}).items():
        flag = option_flag(name)
        if name not in {f.name for f in option_fields(type(cfg.options))}:
            raise UserError(f"{flag}: only {takers(name)}, not {behaviour!r}")
        opts = _checked(flag, dataclasses.replace, cfg.options, **{name: value})
        cfg = cfg.replace(options=opts)
    if population is not None:
        opt = _checked("--population", cfg.optimizer.replace, population=population)
        cfg = cfg.replace(optimizer=opt)
    if generations is not None:
        cfg = _checked("--generations", cfg.replace, generations=generations)
    return cfg


def _checked(option: str, make: Callable[..., _T], *args: Any, **changes: Any) -> _T:
    """``make(*args, **changes)``, its ``ValueError`` as a one-line error
    naming ``option`` (in place of the setting it changes)."""
    try:
        return make(*args, **changes)
    except SettingError as e:  # its setting is the option's: named by it
        if e.name in changes or e.name == option.lstrip("-").replace("-", "_"):
            raise UserError(e.message.replace(setting_ref(e.name), option, 1)) from None
        raise UserError(f"{option}: {e.message}") from None
    except ValueError as e:
        raise UserError(f"{option}: {e}") from None


def terrains_arg(
    scene: str | None,
    terrain_seed: int | None = None,
    terrains: int | None = None,
    base: Terrains | None = None,
) -> Terrains | None:
    """``--scene`` (a name, or a TOML file with a ``[scene]`` table),
    ``--terrain-seed`` and ``--terrains`` over ``base`` (a configuration's or
    a run's own; ``None``: the flat floor); ``None`` if none is given and
    there is no ``base``."""
    if scene is None and terrain_seed is None and terrains is None:
        return base
    t = Terrains() if base is None else base
    if scene is not None:
        t = _scene_named(scene)
    if terrain_seed is not None:
        if not t.scene.seeded:
            raise UserError(
                f"--terrain-seed: the {t.scene.name} scene has no terrains to "
                f"choose from (e.g. --scene debris)"
            )
        seeded = _checked("--terrain-seed", t.scene.with_seed, seed=terrain_seed)
        if terrains is None:  # the count of base, from this seed on
            t = _checked("--terrain-seed", dataclasses.replace, t, scene=seeded)
        else:
            t = dataclasses.replace(t, scene=seeded, count=1)
    if terrains is not None:
        t = _checked("--terrains", dataclasses.replace, t, count=terrains)
    return t


def _scene_named(text: str) -> Terrains:
    if text in scene_names():
        return Terrains(scene_class(text)())
    path = Path(text)
    if path.suffix != ".toml":
        raise UserError(
            f"--scene: unknown scene {text!r}; choose from "
            f"{', '.join(scene_names())}, or give a .toml file with a [scene] table"
        )
    table = rundir.read_toml(path, "scene file")
    if "scene" not in table:
        raise UserError(f"--scene: {text}: no [scene] table")
    return terrains_from_table(table["scene"], text)


def own_terrains(path: str | os.PathLike[str]) -> Terrains:
    """The terrains of run directory ``path`` (the flat floor for a rule-based
    run made before scenes)."""
    path = Path(path)
    if rundir.is_run(path):
        return rundir.load_config(path / rundir.CONFIG).scene
    if rundir.is_rules_run(path):
        summary = rundir.read_json(path / rundir.RULES_SUMMARY)
        scene = summary.get("scene", {}) if isinstance(summary, dict) else {}
        return terrains_from_table(scene, str(path / rundir.RULES_SUMMARY))
    raise UserError(f"--terrain-seed: {path} is not a run; give --scene too")


def scene_override(
    args: argparse.Namespace, path: str | os.PathLike[str] | None = None
) -> Scene | None:
    """The scene a command that reads directory ``path`` runs in, if its
    ``--scene``/``--terrain-seed`` ask for another than the run's own."""
    if args.scene is None and args.terrain_seed is None:
        return None
    base = None
    if args.scene is None and path is not None:
        base = own_terrains(path)
    t = terrains_arg(args.scene, args.terrain_seed, base=base)
    return None if t is None else t.scene
