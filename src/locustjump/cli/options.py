"""Options that several commands share: the backend, the optimizer and engine,
the creature's struts, what each behaviour of ``train`` is and the options
the behaviours declare."""

from __future__ import annotations

import argparse
import dataclasses
from typing import Any

from locustjump.cli.argtypes import accepts, int_list, option_type, ranged
from locustjump.evo import optimizer_kinds
from locustjump.ranges import range_of
from locustjump.rundir.elites import CELL_INDEX, ELITE
from locustjump.sim.engine.backends import ACTORS, BACKENDS, THREADS
from locustjump.sim.engine.job import ENGINES
from locustjump.sim.params import LocustParams
from locustjump.sim.scene import TERRAIN_SEED, TERRAINS, scene_names
from locustjump.tasks import behaviour_class, behaviour_names
from locustjump.tasks.base import OPTION_HELP, option_fields


def strut_stiffness_arg(p: argparse.ArgumentParser) -> None:
    valid = range_of(LocustParams, "strut_stiffness")
    p.add_argument(
        "--strut-stiffness",
        type=ranged("--strut-stiffness", valid),
        default=0.0,
        metavar="NM_PER_RAD",
        help="fore and middle legs on sprung hinges of this stiffness at real "
        f"scale, e.g. 2e-4; {accepts(valid)} (default 0: rigid struts, the "
        "trained creature)",
    )


def add_scene(
    p: argparse.ArgumentParser, *, of_run: bool = False, train: bool = False
) -> None:
    """``--scene`` and ``--terrain-seed`` (``train``: also ``--terrains``)."""
    own = "the run's own; " if of_run else ""
    p.add_argument(
        "--scene",
        metavar="NAME|FILE",
        help=f"the world: {' or '.join(scene_names())}, or a TOML file with a "
        f"[scene] table (a run's config.toml is one) for its parameters "
        f"(default: {own}flat, the paper's floor)",
    )
    p.add_argument(
        "--terrain-seed",
        type=ranged("--terrain-seed", TERRAIN_SEED),
        metavar="N",
        help="the terrain of a seeded scene (debris), apart from the evolution's "
        f"--seed; {accepts(TERRAIN_SEED)} (default 0"
        + (", or the run's first training terrain" if of_run else "")
        + (": training terrains N .. N+K-1" if train else "") + ")",
    )  # fmt: skip
    if train:
        p.add_argument(
            "--terrains",
            type=ranged("--terrains", TERRAINS),
            metavar="K",
            help="score every genome on K terrains (seeds from --terrain-seed), "
            'fitness their mean ([scene] aggregate = "min": the worst); '
            f"{accepts(TERRAINS)} (default 1)",
        )


def add_elite(p: argparse.ArgumentParser) -> None:
    """``--elite K`` or ``--cell I,J``: one elite of a quality-diversity run."""
    g = p.add_mutually_exclusive_group()
    g.add_argument(
        "--elite",
        type=ranged("--elite", ELITE),
        metavar="K",
        help="a quality-diversity run (map-elites, cma-me): its archive's K-th "
        f"best elite instead of the best genome, {accepts(ELITE)} (0: the best; "
        "default: none)",
    )
    g.add_argument(
        "--cell",
        type=int_list("--cell", CELL_INDEX),
        metavar="I,J",
        help="... or the elite in this cell of its descriptor grid (indices "
        f"{CELL_INDEX.interval()}, as DIR/archive.png's top and right axes count "
        "them)",
    )


def add_backend(p: argparse.ArgumentParser) -> None:

    p.add_argument(
        "--backend",
        choices=BACKENDS,
        default="threads",
        help="where episodes run: threads on this machine or Ray tasks (default "
        "threads; the result does not depend on it)",
    )
    p.add_argument(
        "--threads",
        type=ranged("--threads", THREADS),
        help=f"simulation threads, {accepts(THREADS)} (threads: default all "
        "CPUs; ray: per actor, default 1, or per task with reproduce --seeds, "
        "default a whole node's CPUs); the result does not depend on it",
    )
    p.add_argument(
        "--address",
        metavar="HOST:PORT",
        help="ray: the cluster to join ('auto': the one `ray start` made here; "
        "default: a local Ray instance)",
    )
    p.add_argument(
        "--actors",
        type=ranged("--actors", ACTORS),
        help=f"ray: how many actors, {accepts(ACTORS)} (default: the cluster's "
        "CPUs / --threads)",
    )


def add_optimizer(p: argparse.ArgumentParser, default: str | None) -> None:

    p.add_argument(
        "--optimizer",
        choices=optimizer_kinds(),
        default=default,
        help="rcga: the paper's GA (default); cma: CMA-ES (pycma); random: "
        "random search; map-elites, cma-me: quality diversity (pyribs), a "
        "repertoire over the task's behaviour descriptors"
        + ("" if default else "; --resume: the run's"),
    )
    p.add_argument(
        "--engine",
        choices=ENGINES,
        help="how the controllers are computed between physics steps: numba "
        "(compiled; the default for new runs) or numpy (the reference; runs "
        "made before the compiled path); recorded in config.toml (default: "
        "numba, or the run's when it continues one)",
    )


#: what each behaviour of ``train`` evolves (a registered one: its docstring)
_BEHAVIOUR_HELP = {
    "kick": "kick the ground: fitness max dx*dz over 300 steps (paper Eq. 1)",
    "getup": "get up from 5 rolled start states: fitness mean U_z",
    "return-legs": "return the hind legs to the ready posture",
    "composed": "a switcher between 3 frozen runs (--kick, --getup, --return-legs)",
    "monolithic": "beyond the paper: one network on the composed task",
    "composed-repertoire": "beyond the paper: a switcher among a kick repertoire's "
    "best elites ([options] elites, from a map-elites or cma-me --kick run), "
    "--getup and --return-legs",
    "kick-apex": "beyond the paper: the kick, fitness the apex rise (m)",
    "kick-open": "beyond the paper: the kick (Eq. 1) as an open-loop sequence of "
    "target changes (240 genes) instead of a network",
    "kick-apex-open": "beyond the paper: the apex rise, open-loop (240 genes)",
}


def behaviours_help() -> str:
    """One line per behaviour of ``train``: its name and what it evolves."""
    lines = ["behaviours:"]
    for name in behaviour_names():
        doc = (behaviour_class(name).__doc__ or "").strip().splitlines()
        what = _BEHAVIOUR_HELP.get(name, doc[0] if doc else name)
        lines.append(f"  {name}: {what}")
    return "\n".join(lines)


def option_flag(name: str) -> str:
    """The command line's flag of a behaviour's option ``name``."""
    return "--" + name.replace("_", "-")


def behaviour_options() -> dict[str, tuple[dataclasses.Field[Any], tuple[str, ...]]]:
    """Every option a registered behaviour declares
    (:func:`locustjump.tasks.options.option`): its name -> (its field, the
    behaviours that take it), in the order first declared."""
    found: dict[str, tuple[dataclasses.Field[Any], tuple[str, ...]]] = {}
    for b in behaviour_names():
        for f in option_fields(behaviour_class(b).Options):
            field, takers = found.get(f.name, (f, ()))
            found[f.name] = (field, (*takers, b))
    return found


def takers(name: str) -> str:
    """Who takes option ``name``, for an error: "the composed behaviour takes
    it", "the a and b behaviours take it"."""
    who = behaviour_options().get(name, (None, ()))[1]
    if len(who) == 1:
        return f"the {who[0]} behaviour takes it"
    listed = " and ".join([", ".join(who[:-1]), who[-1]]) if who else "no"
    return f"the {listed} behaviours take it"


def add_behaviour_options(p: argparse.ArgumentParser) -> None:
    """``train``'s ``--NAME`` for every option a behaviour declares; the
    names given are ``args.behaviour_options``, their values ``args.option_NAME``
    (``None`` if not given)."""
    every = set(behaviour_names())
    taken = {s for a in p._actions for s in a.option_strings}
    names = []
    for name, (field, who) in behaviour_options().items():
        flag = option_flag(name)
        if flag in taken:  # a plugin's option may not shadow train's own
            raise ValueError(
                f"behaviour {who[0]!r} declares the option {name!r}, but train's "
                f"{flag} is another; rename it"
            )
        help = field.metadata[OPTION_HELP]
        if "range" in field.metadata:  # the range it declares, said once more
            help += f"; {accepts(field.metadata['range'])}"
        elif "each" in field.metadata:
            help += f"; each {accepts(field.metadata['each'])}"
        p.add_argument(
            flag,
            dest=f"option_{name}",
            type=option_type(flag, field),
            metavar=field.metadata["metavar"],
            help=help if set(who) == every else f"{', '.join(who)}: {help}",
        )
        names.append(name)
    p.set_defaults(behaviour_options=tuple(names))
