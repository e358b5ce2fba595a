"""The commands of ``locustjump``: each a few lines over the public API."""

from __future__ import annotations

import argparse
import json
import sys

from locustjump import rundir
from locustjump.cli.resolve import resolve_config, scene_override, terrains_arg
from locustjump.errors import UserError
from locustjump.present.compare import (
    TOTAL_LABEL,
    budget_note,
    convergence_figure,
    load_groups,
    table,
)
from locustjump.present.evaluate import (
    TerrainEvaluation,
    evaluate_run,
    evaluate_terrains,
)
from locustjump.present.render import render_run
from locustjump.present.report import write_report
from locustjump.present.rules import write_rules_run
from locustjump.present.stages import reporter_of
from locustjump.present.stages.getup import sweep_run
from locustjump.present.viewer import view
from locustjump.runs.multiseed import reproduce_seeds
from locustjump.runs.reproduce import replay, reproduce
from locustjump.runs.trainer import train
from locustjump.sim import model as lm
from locustjump.sim.engine.backends import Backend, make_backend
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks import behaviour_class, behaviour_names
from locustjump.tasks.getup import sweep_angles


def _scene(args: argparse.Namespace) -> Scene:
    """The one scene of a command that makes its own episodes (flat unless
    ``--scene``/``--terrain-seed`` say otherwise)."""
    t = terrains_arg(args.scene, args.terrain_seed)
    return Flat() if t is None else t.scene


def terrain_table(te: TerrainEvaluation) -> str:
    """``evaluate --terrain-seeds``' printout: a row per terrain, the summary."""
    wanted = ("jumps", "distance_m", "overturned", "recovered", "rules_fitness")
    keys = tuple(k for k in wanted if k in te.metrics[0])
    head = f"{'seed':>6} {'fitness':>12} " + " ".join(f"{k:>13}" for k in keys)
    lines = [f"{te.behaviour} on {te.scene} terrains (* = a training terrain)", head]
    for s, f, t, m in zip(te.seeds, te.fitness, te.trained, te.metrics, strict=True):
        cells = " ".join(
            f"{m[k]:>13.4g}" if isinstance(m[k], float) else f"{m[k]!s:>13}"
            for k in keys
        )
        lines.append(f"{s:>5}{'*' if t else ' '} {f:>12.6g} {cells}")
    lines.append(
        f"training fitness (recorded, {te.aggregate} of its terrains): "
        f"{te.train_fitness:.6g}"
    )
    if te.held_out is None:
        lines.append("held out: none (every terrain given was a training terrain)")
    else:
        n = te.trained.count(False)
        lines.append(
            f"held out ({te.aggregate} of {n} unseen terrains): {te.held_out:.6g}; "
            f"generalisation gap (training - held out): {te.gap:.6g}"
        )
    return "\n".join(lines)


def _backend(args: argparse.Namespace) -> Backend:

    return make_backend(
        args.backend, threads=args.threads, address=args.address, actors=args.actors
    )


def cmd_model(args: argparse.Namespace) -> int:
    p = lm.LocustParams(scale=args.scale, strut_stiffness=args.strut_stiffness)
    scene = _scene(args)
    with rundir.output_file(args.out, force=args.force) as out:
        rundir.atomic_write_text(out, lm.to_mjcf(p, scene=scene))
    print(
        f"wrote {out} (scale {p.scale:g}, body length {p.body_length:.3g} m, "
        f"scene {scene.name})"
    )
    return 0


def cmd_rules(args: argparse.Namespace) -> int:

    scene = _scene(args)
    p = lm.LocustParams(strut_stiffness=args.strut_stiffness)
    with rundir.output_dir(args.out, force=args.force) as out:
        run = write_rules_run(
            out, args.change_time, args.steps, model_params=p,
            backend=_backend(args), scene=scene,
        )  # fmt: skip
    apexes = ", ".join(f"{j.apex_height:.2f}" for j in run.jumps) or "none"
    print(f"{len(run.jumps)} jumps in {args.steps} steps; apex heights [m]: {apexes}")
    if run.unstable:
        print("warning: the simulation went unstable", file=sys.stderr)
    print(f"wrote {out}/trajectory.csv, trajectory.png and summary.json")
    return 0


def cmd_train(args: argparse.Namespace) -> int:

    cfg = resolve_config(
        args.behaviour,
        args.out,
        resume=args.resume,
        config=args.config,
        optimizer=args.optimizer,
        seed=args.seed,
        population=args.population,
        generations=args.generations,
        engine=args.engine,
        options={
            name: value
            for name in args.behaviour_options
            if (value := getattr(args, f"option_{name}")) is not None
        },
        scene=args.scene,
        terrain_seed=args.terrain_seed,
        terrains=args.terrains,
    )
    requires = behaviour_class(args.behaviour).requires
    dirs = {name: getattr(args, frozen_dest(name)) for name in frozen_options()}
    given = [f"--{k}" for k, v in dirs.items() if v is not None and k not in requires]
    if given:
        raise UserError(
            f"{', '.join(given)}: only for train "
            + " or ".join(b for b in behaviour_names() if behaviour_class(b).requires)
            + f" ({args.behaviour} builds on no other run)"
        )
    frozen = None
    if requires and (not args.resume or any(dirs[r] is not None for r in requires)):
        frozen = rundir.FrozenGenomes.from_runs(
            requires,
            dirs,
            cfg.model,
            behaviour_class(args.behaviour).frozen_num_params(),
            behaviour_class(args.behaviour).frozen_elites(cfg.options),
        )
    res = train(
        cfg,
        args.out,
        resume=args.resume,
        backend=_backend(args),
        progress=not args.quiet,
        frozen=frozen,
    )
    stopped = ""
    if res.stopped:
        why = ", ".join(f"{k} {v}" for k, v in res.stopped.items())
        stopped = f"; the optimizer stopped early ({why}, in {rundir.STOP})"
    print(
        f"{cfg.behaviour}: {res.generation} generations, best fitness "
        f"{res.best.fitness:.6g} (generation {res.best.generation}){stopped}; "
        f"wrote {res.out}"
    )
    return 0


def cmd_evaluate(args: argparse.Namespace) -> int:

    scene = scene_override(args, args.run)
    pick = {"elite": args.elite, "cell": args.cell}
    if args.terrain_seeds is not None:
        te = evaluate_terrains(
            args.run, args.terrain_seeds, scene=scene, backend=_backend(args), **pick
        )
        print(json.dumps(te.to_dict(), indent=2) if args.json else terrain_table(te))
        return 0
    eval_dir = None
    if args.out is not None:
        eval_dir = rundir.check_out_dir(args.out, force=args.force)
    ev = evaluate_run(
        args.run, backend=_backend(args), eval_dir=eval_dir, scene=scene, **pick
    )
    if args.json:
        print(json.dumps(ev.to_dict(), indent=2))
    else:
        status = "matches training" if ev.matches else "DIFFERS from training"
        if ev.elsewhere:
            status = "trained in another scene"
        print(
            f"{ev.behaviour}: fitness {ev.fitness:.10g} "
            f"(recorded {ev.recorded_fitness:.10g}: {status})"
        )
        shown = dict(ev.metrics)
        recorded = ev.recorded_descriptors or {}
        if ev.descriptors is not None:  # an elite: where it sits, re-simulated
            shown |= {f"{k} (recorded {recorded[k]:.6g})": v
                      for k, v in ev.descriptors.items()}  # fmt: skip
        width = max(map(len, shown))
        for k, v in shown.items():
            text = f"{v:.4g}" if isinstance(v, float) else str(v)
            print(f"  {k:<{width}}  {text}")
        print("wrote " + ", ".join(str(f) for f in ev.files))
    if not ev.matches:
        print(
            "locustjump: error: re-simulated fitness differs from the recorded one",
            file=sys.stderr,
        )
        return 1
    return 0


def cmd_sweep_getup(args: argparse.Namespace) -> int:

    angles = sweep_angles(args.step_deg, args.from_deg, args.to_deg)
    sw, files = sweep_run(
        args.run, angles, backend=_backend(args), scene=scene_override(args, args.run)
    )
    n_train = int(sw.training.sum())
    print(
        f"got up from {sw.got_up} of {sw.n_sweep} (the paper: 65 of 180); "
        f"training states: {int(sw.success[sw.training].sum())} of {n_train}"
    )
    print("wrote " + " and ".join(str(f) for f in files))
    return 0


def cmd_reproduce(args: argparse.Namespace) -> int:

    common = {
        "budget": args.budget,
        "optimizer": args.optimizer,
        "engine": args.engine,
        "progress": not args.quiet,
        "videos": not args.no_videos,
        "monolithic": not args.no_monolithic,
        "terrains": terrains_arg(args.scene, args.terrain_seed, args.terrains),
    }
    if args.seeds is not None:
        if args.actors is not None:
            raise UserError(
                "--actors is for one seed; with --seeds every stage is a Ray task "
                "(--threads CPUs each)"
            )
        path = reproduce_seeds(
            args.out, args.seeds, backend=args.backend, threads=args.threads,
            address=args.address, **common,
        )  # fmt: skip
        print(rundir.read_text(path).split("## Best fitness")[0].rstrip())
        return 0
    seed = 0 if args.seed is None else args.seed
    path = reproduce(args.out, seed=seed, backend=_backend(args), **common)
    print(rundir.read_text(path).split("## Beyond")[0].rstrip())
    return 0


def cmd_replay(args: argparse.Namespace) -> int:

    failed = 0
    scene = scene_override(args)
    for stage, ev in replay(
        args.dir, args.out, force=args.force, backend=_backend(args), scene=scene
    ):
        status = "matches" if ev.matches else "DIFFERS from"
        failed += not ev.matches
        keys = reporter_of(stage).headline
        shown = ", ".join(f"{k} {ev.metrics.get(k)}" for k in keys)
        print(f"[{stage}] fitness {ev.fitness:.6g} ({status} the record); {shown}")
    print(f"wrote {args.out}/<stage>/ (figures and trajectories)")
    if failed:
        print(
            f"locustjump: error: {failed} stage(s) re-simulated to another fitness",
            file=sys.stderr,
        )
        return 1
    return 0


def cmd_render(args: argparse.Namespace) -> int:

    out = render_run(
        args.dir,
        args.out,
        fps=args.fps,
        camera=args.camera,
        force=args.force,
        progress=not args.quiet,
        backend=_backend(args),
        scene=scene_override(args, args.dir),
        elite=args.elite,
        cell=args.cell,
    )
    print(f"wrote {out}")
    return 0


def cmd_view(args: argparse.Namespace) -> int:

    view(args.dir, duration=args.duration, scene=scene_override(args, args.dir))
    return 0


def cmd_report(args: argparse.Namespace) -> int:

    out = None
    if args.out is not None:
        out = rundir.prepare_out_file(args.out, force=args.force)
    print(f"wrote {write_report(args.dir, backend=_backend(args), out=out)}")
    return 0


def cmd_compare(args: argparse.Namespace) -> int:

    if args.figure is not None:
        rundir.prepare_out_file(args.figure, force=args.force, setting="figure")
    groups = load_groups(args.dirs, by=args.by, total_budget=args.total_budget)
    text = table(groups, args.reference, margin=args.margin)
    if args.figure is not None:
        with rundir.output_file(
            args.figure, force=args.force, setting="figure"
        ) as figure:
            xlabel = TOTAL_LABEL if args.total_budget else "genome evaluations"
            convergence_figure(groups, figure, title=args.title, xlabel=xlabel)
    print(text)
    print(f"\n{budget_note(groups)}")
    if args.figure is not None:
        print(f"wrote {args.figure}")
    return 0


def frozen_options() -> tuple[str, ...]:
    """Every run some behaviour builds on (``--kick DIR`` ...), in order."""

    seen: dict[str, None] = {}
    for name in behaviour_names():
        seen.update(dict.fromkeys(behaviour_class(name).requires))
    return tuple(seen)


def frozen_dest(option: str) -> str:
    return rundir.frozen_setting(option)
