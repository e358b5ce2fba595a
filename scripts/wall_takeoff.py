"""Issue #45: what the wall does in the debris study's highest jump
(exploratory).

``docs/science.md`` ("What the episodes show") records that the shipped run
``results/study/debris-pipeline-s0`` (the composed pipeline, seed 0) rises
2.32 m above the ground on held-out debris terrain 139 at 12 substeps,
touching a side wall as it takes off. This script takes that take-off apart
and prints Markdown tables:

1. **Reproduction.** The episode as the study scores it (``score_run`` on the
   run's engine) and again, recording its servo targets, inputs and the
   engine's ``wall_contact`` record; then those targets replayed, open loop,
   on one ``MjData`` (the engine's arithmetic), checked against the engine's
   ``qpos`` and inputs at every control step (bit for bit) and against its
   ``wall_contact`` record.
2. **Impulses.** On that replay, at every physics substep, each contact's
   force on the creature (``mj_contactForce``, contact frame to world) times
   the timestep, summed by what it touches (the floor, rubble boxes, the
   walls) and by direction: up (z), away from the nearest side wall
   (horizontal, across the field) and forward (x), and by contact pair.
   Gravity's impulse and the change of the whole creature's momentum close
   the budget. Beside it the energy: the change of kinetic + gravitational
   energy against the work of the servos, joint damping, each contact class
   and the joint limits; and each servo's work, how much of the push it
   spent at its force limit, and its joint's angle at the push's start and
   at take-off. The same for two jumps without a wall, over the same spans
   (the last 132 steps to the apex: the brief's window 1290-1422 for the
   wall jump; the push: the last ``PUSH`` steps up to the take-off, the
   last step in which the floor and the rubble push up; the flight): the
   run's highest jump that touches no wall in the ``QUIET`` steps to its
   apex (``--compare auto``: searched over terrains 100-139 and the flat
   floor at 12 substeps), and a flat-floor jump at the kick's ceiling (seed 0),
   ``results/study/kick-apex-cma-s0`` ("The kick's ceiling"). And per
   control step of the wall jump's push, the mean force by class.
3. **Counterfactuals.** From the recorded state after control step 1290 the
   controller runs on, closed loop (its NumPy ``act``; the run's engine is
   the compiled one, a few ulp apart, so the unchanged run comes first, as
   the check), with the touched wall's contacts switched off, with the wall
   moved 0.5-50 mm away, and with the box that holds the body down switched
   off: the highest point above the ground in the next 300 steps, how many
   of the steps to it touched the wall and the longest stretch of them with
   both knee servos at their force limit.

Deterministic. About 35 s on one core of the busy 2-core VM, 23 s of it the
search (``--compare 112``, the terrain it finds, skips it: 11 s).

    .venv/bin/python scripts/wall_takeoff.py [--compare auto|flat|SEED] [--per-step]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

import contact_budget as cb
from locustjump import rundir
from locustjump.present.episodes import score_run
from locustjump.sim import actuation, names
from locustjump.sim import model as lm
from locustjump.sim.analysis import clearance
from locustjump.sim.engine.backends import Backend, ThreadBackend
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.base import Behaviour

RUN = Path("results/study/debris-pipeline-s0")
#: a flat-floor jump at the kick's ceiling (seed 0 of "The kick's ceiling")
CEILING = Path("results/study/kick-apex-cma-s0")
TERRAIN = 139  #: the episode of docs/science.md
SUBSTEPS = 12
WINDOW = (1290, 1422)  #: the brief's take-off window (control steps)
BRANCH = 1290  #: the counterfactuals start from the state after this step
AFTER = 300  #: and run this many steps on (the recorded apex is at +132)
SCAN = range(100, 140)  #: the study's held-out terrains
#: control steps of the push, up to the take-off (both jumps measured here
#: start it near v_z = 0: 0.25 and -0.06 m/s)
PUSH = 12
SHOW = 20  #: the per-step table: this many steps to the take-off
#: a model change for a counterfactual, applied to the model and its data
Change = Callable[[mujoco.MjModel, mujoco.MjData], None]


@dataclass(frozen=True)
class Outcome:
    """A counterfactual's jump (:func:`run_on`)."""

    jump: cb.Jump  #: its highest point above the ground after the branch
    touched: int  #: steps from the branch to the apex touching the wall
    #: the longest stretch of steps from the branch to the apex with both
    #: knee servos at their force limit in every substep
    held: int
    diff: float  #: largest servo-target difference from the record (rad)
    note: str


def run_on(
    r: cb.Recorded, at: int, until: int, wall: int, change: Change | None
) -> Outcome:
    """The controller closed loop (its NumPy ``act``) from the recorded state
    after step ``at`` (the recorded targets replayed up to it) to step
    ``until``, with ``change`` made to the model then (``wall``: the geom
    whose contacts are counted). The servo-target difference is nan when
    changed."""
    rp = cb.Replay(r.here, r.p)
    rp.reset(r.here.start_states(r.p))
    rec = r.rec
    for t in range(1, at + 1):
        rp.step(rec["ctrl"][t])
    if change is not None:
        change(rp.m, rp.d)
    ctl = r.here.controller
    prepared = ctl.prepare(r.genome[None])
    memory = rec["memory"][at][None].copy()
    obs = rp.obs()
    q = list(rec["qpos"][: at + 1])
    touched, caught = [False] * (at + 1), [False] * (at + 1)  # after ``at``
    diff, note = 0.0, ""
    for t in range(at, until):
        deltas, memory = ctl.act(prepared, memory, obs, rp.d.ctrl[None], t)
        new = actuation.apply_deltas(rp.d.ctrl[None], deltas, rp.ranges)[0]
        diff = max(diff, float(np.abs(new - rec["ctrl"][t + 1]).max()))
        meter = cb.Meter(rp.m.ngeom, float(rp.m.opt.timestep))
        hit = wall in rp.step(new, meter)
        obs = rp.obs()
        if rp.d.warning.number.any() or not np.isfinite(rp.d.qpos).all():
            note = f"went unstable at step {t + 1}"
            break
        q.append(rp.d.qpos.copy())
        touched.append(hit)
        caught.append(all(meter.at_limit[k] == meter.substeps for k in cb.KNEES))
    qs = np.array(q)
    z = clearance(qs, r.p, r.here.scene)
    apex = at + 1 + int(np.argmax(z[at + 1 :]))
    longest = run = 0
    for c in caught[: apex + 1]:
        run = run + 1 if c else 0
        longest = max(longest, run)
    return Outcome(cb.jump_of(r, qs, apex), sum(touched[: apex + 1]), longest,
                   np.nan if change else diff, note)  # fmt: skip


def comparison(
    choice: str, beh: Behaviour, genome: np.ndarray, engine: str,
    p: lm.LocustParams, backend: Backend,
) -> tuple[cb.Jump, int]:  # fmt: skip
    """The highest jump touching no wall (``choice``: auto, flat or a terrain
    seed) and how many episodes were searched."""
    base = beh.terrains.scene
    if choice == "auto":
        scenes: list[Scene] = [base.with_seed(s) for s in SCAN] + [Flat()]
    elif choice == "flat":
        scenes = [Flat()]
    else:
        scenes = [base.with_seed(int(choice))]
    found: list[cb.Jump] = []
    for scene in scenes:
        found += cb.quiet_jumps(cb.simulate(beh, genome, engine, scene, p, backend))
    if not found:
        raise SystemExit(f"wall_takeoff.py: no jump touching no wall in {choice}")
    return max(found, key=lambda j: j.height), len(scenes)


def _f(v: float, fmt: str = ".2f") -> str:
    return "-" if not np.isfinite(v) else format(v, fmt)


def _row(*cells: object) -> str:
    return "| " + " | ".join(str(c) for c in cells) + " |"


def _head(*cells: str) -> str:
    return _row(*cells) + "\n" + _row(*["---"] * len(cells))


def report(compare: str, per_step: bool, backend: Backend) -> None:
    cfg, beh, best = rundir.load_run(RUN)
    p = dataclasses.replace(cfg.model, substeps=SUBSTEPS)
    study = score_run(RUN, terrain_seeds=[TERRAIN], substeps=SUBSTEPS,
                      backend=backend)[0]  # fmt: skip
    r = cb.simulate(beh, best.genome, cfg.engine,
                    beh.terrains.scene.with_seed(TERRAIN), p, backend)  # fmt: skip
    qpos, wall = r.rec["qpos"], r.rec["wall_contact"]
    w = cb.Studied.of("wall jump", cb.jump_of(r, qpos, int(np.argmax(
        clearance(qpos, p, r.here.scene)))))  # fmt: skip
    tr, to, axes = w.trace, w.take_off, w.axes
    other, searched = comparison(compare, beh, best.genome, cfg.engine, p, backend)
    ccfg, cbeh, cbest = rundir.load_run(CEILING)
    if ccfg.model != cfg.model:
        raise SystemExit(f"wall_takeoff.py: {CEILING} has another creature")
    cr = cb.simulate(cbeh, cbest.genome, ccfg.engine, cbeh.terrains.scene, p, backend)
    cq = cr.rec["qpos"]
    cz = clearance(cq, p, cr.here.scene)
    ceiling = cb.Studied.of("flat ceiling", cb.jump_of(cr, cq, int(np.argmax(cz))))
    jumps = [w, cb.Studied.of("no wall", other), ceiling]
    model = lm.load_model(p, r.here.scene)
    side = [g for g in np.flatnonzero(tr.kind == cb.WALL) if model.geom_size[g, 0] > 1]

    def face(t: int) -> float:
        """The body centre's distance from the nearest side wall's face."""
        return min(abs(float(qpos[t, 1] - model.geom_pos[g, 1]))
                   - float(model.geom_size[g, 1]) for g in side)  # fmt: skip

    print(f"## {RUN} on debris terrain {TERRAIN}, {SUBSTEPS} substeps\n")
    print(_head("check", "value"))
    print(_row("highest above the ground (`score_run`, as the study scores it)",
               f"{study.highest_m:.4f} m"))  # fmt: skip
    print(_row("the same episode, recorded here",
               f"{r.score.highest_m:.4f} m at step {w.jump.apex}, body rise "
               f"{w.jump.rise:.3f} m (apex minus the lowest in the {cb.QUIET} steps "
               f"before); the same EpisodeScore: {r.score == study}"))  # fmt: skip
    print(_row(f"the engine's `wall_contact`, steps {tr.a}-{w.jump.apex}",
               cb.stretches(wall, tr.a, w.jump.apex)))  # fmt: skip
    print(_row("the creature's mass, weight",
               f"{tr.weight / 9.81:.4f} kg, {tr.weight:.2f} N"))  # fmt: skip
    print(_row("wall jump: take-off (the last step the floor and rubble push up)",
               f"step {to}; the body centre {qpos[to, 2]:.3f} m high; "
               f"{face(to - SHOW):.3f} m from the side wall's face {SHOW} steps "
               f"before, {face(to):.3f} m at take-off"))  # fmt: skip
    gaps = tr.gap[: to - tr.a][np.isfinite(tr.gap[: to - tr.a])]
    print(_row(f"wall jump: how far its wall contacts are from the wall's face "
               f"(MuJoCo's `dist`), steps {tr.a + 1}-{to}",
               f"{1e3 * gaps.min():.1f}-{1e3 * gaps.max():.1f} mm; the walls' "
               f"contact margin {1e3 * model.geom_margin[side[0]]:.0f} mm"),
          )  # fmt: skip
    print(_row(f"no wall: the highest jump touching no wall in the {cb.QUIET} steps "
               f"to its apex ({searched} episodes of this run)",
               f"{other.label}: {other.height:.4f} m above the ground, body rise "
               f"{other.rise:.3f} m"))  # fmt: skip
    cj = jumps[2].jump
    print(_row(f"flat ceiling: {CEILING} (the apex as fitness; \"The kick's "
               "ceiling\")", f"{cj.label}: {cj.height:.4f} m, rise from the start "
               f"{cj.height - float(cq[0, 2]):.3f} m"))  # fmt: skip
    for st in jumps:
        trc = st.trace
        q = st.jump.r.rec["qpos"]
        print(_row(f"{st.name}: replay of the recorded targets on one MjData, "
                   f"steps 0-{st.jump.apex}",
                   f"max abs(qpos - engine's) {trc.deviation:g}; inputs identical: "
                   f"{trc.obs_equal}; wall contact differs from the record at "
                   f"{trc.wall_mismatch or 'no step'}; take-off step "
                   f"{st.take_off}"))  # fmt: skip
        print(_row(f"{st.name}: steps {trc.a + 1}-{st.take_off} with both knee "
                   "servos at their force limit",
                   cb.held(trc, q, st.take_off)))  # fmt: skip

    n = WINDOW[1] - WINDOW[0]
    rows: list[cb.Budget] = []
    for st in jumps:
        q, o, apex = st.jump.r.rec["qpos"], st.take_off, st.jump.apex
        for span, a, b in (
            (f"up to {n} steps to the apex", max(apex - n, st.trace.a), apex),
            (f"push ({PUSH} steps)", o - PUSH, o),
            ("flight", o, apex),
        ):
            rows.append(cb.budget(f"{st.name}, {span}", st.trace, q, a, b, st.axes))
    pushes = rows[1::3]

    print("\n### Vertical impulse on the creature (N s, up +)\n")
    print(_head("jump, span", "steps", "floor", "rubble", "walls", "gravity",
                "sum", "momentum change", "residual",
                "v_z at start, end (m/s)"))  # fmt: skip
    for x in rows:
        s = float(x.by_class[:, 0].sum()) + x.gravity
        print(_row(x.label, f"{x.a + 1}-{x.b}", *(_f(v) for v in x.by_class[:, 0]),
                   _f(x.gravity), _f(s), _f(x.change[0]), _f(s - x.change[0], ".3f"),
                   f"{x.v_z[0]:.2f}, {x.v_z[1]:.2f}"))  # fmt: skip
    print("\n### Horizontal impulse on the creature (N s): away from the nearest "
          "side wall (flat floor: +y), forward (x)\n")  # fmt: skip
    print(_head("jump, span", "direction", "floor", "rubble", "walls", "sum",
                "momentum change"))  # fmt: skip
    for x in rows:
        for k, name in ((1, "away"), (2, "forward")):
            print(_row(x.label, name, *(_f(v) for v in x.by_class[:, k]),
                       _f(float(x.by_class[:, k].sum())),
                       _f(x.change[k])))  # fmt: skip
    print("\n### Each contact pair during the push (N s)\n")
    print(_head("jump", "creature geom \\| world geom", "up", "away", "forward"))
    for x in pushes:
        for key, v in sorted(x.by_pair.items(), key=lambda kv: kv[0]):
            print(_row(x.label.split(",")[0], key, *(_f(c) for c in v)))
    print("\n### Energy (J): the change of kinetic + gravitational energy and "
          "the work done on the creature\n")  # fmt: skip
    print(_head("jump, span", "energy change", "servos", "joint damping", "floor",
                "rubble", "walls", "joint limits", "residual",
                "centre of mass rise (m)"))  # fmt: skip
    for x in rows:
        done = float(x.servo.sum()) + x.passive + float(x.work.sum()) + x.limits
        print(_row(x.label, _f(x.energy), _f(float(x.servo.sum())), _f(x.passive),
                   *(_f(v) for v in x.work), _f(x.limits), _f(x.energy - done),
                   _f(x.rise, ".3f")))  # fmt: skip
    print(
        "\n### The servos during the push: work (J), share of the substeps at "
        "the force limit, joint angle (deg) at its start -> at take-off\n"
    )
    servos = [s.removeprefix("servo_") for s in names.ACTUATORS]
    print(_head("jump", *servos))
    for x in pushes:
        print(_row(x.label.split(",")[0], *(
            f"{x.servo[k]:.1f} J, {x.at_limit[k]:.0%}, "
            f"{x.angles[0][k]:.0f} -> {x.angles[1][k]:.0f}"
            for k in range(4))))  # fmt: skip

    a0 = WINDOW[0] if per_step else to - SHOW
    print(f"\n### The wall jump per control step {a0 + 1}-{to + 3} (mean force, "
          "N; servo force / its limit)\n")  # fmt: skip
    print(_head("step", "floor up", "rubble up", "rubble away", "walls away",
                "knee_l servo", "knee_r servo", "body z (m)",
                "centre of mass v_z (m/s)", "engine's wall_contact"))  # fmt: skip
    mass = tr.weight / 9.81
    for t in range(a0 + 1, min(to + 3, w.jump.apex) + 1):
        m = tr.meter(t)
        f = m.impulse @ axes.T / lm.CONTROL_DT
        cls = [f[tr.kind == k].sum(axis=0) for k in (cb.FLOOR, cb.RUBBLE, cb.WALL)]
        print(_row(t, f"{cls[0][0]:.1f}", f"{cls[1][0]:.1f}", f"{cls[1][1]:.1f}",
                   f"{cls[2][1]:.1f}",
                   *(f"{m.force[k] / m.substeps:.2f}" for k in cb.KNEES),
                   f"{qpos[t, 2]:.3f}", f"{tr.momentum[t - tr.a, 2] / mass:.2f}",
                   int(wall[t])))  # fmt: skip

    by = rows[0].by_pair
    on_wall = [k for k in by if k.split(" \\| ")[1].startswith(names.WALL)]
    wname = max(on_wall, key=lambda k: float(np.abs(by[k]).sum())).split(" \\| ")[1]
    push = rows[1].by_pair
    down = min(push, key=lambda k: float(push[k][0]))
    box = down.split(" \\| ")[1]
    gid, bid = tr.geoms.index(wname), tr.geoms.index(box)
    away = -float(axes[1, 1])  # the wall lies this way along y

    def off(g: int) -> Change:
        def f(m: mujoco.MjModel, d: mujoco.MjData) -> None:
            m.geom_contype[g] = m.geom_conaffinity[g] = 0

        return f

    def moved(by: float) -> Change:
        def f(m: mujoco.MjModel, d: mujoco.MjData) -> None:
            # a world geom's position: mj_kinematics does not recompute it
            m.geom_pos[gid, 1] += away * by
            d.geom_xpos[gid, 1] += away * by

        return f

    variants: list[tuple[str, Change | None]] = [
        ("none (the check: the NumPy controller)", None),
        (f"{wname}'s contacts off", off(gid)),
        *((f"{wname} moved {by * 1000:g} mm away", moved(by))
          for by in (0.0005, 0.001, 0.002, 0.005, 0.05)),
        (f"{box}'s contacts off (it pushes the {down.split(' ')[0]} down)",
         off(bid)),
    ]  # fmt: skip
    until = min(BRANCH + AFTER, len(qpos) - 1)
    print(f"\n### Counterfactuals: from the state after step {BRANCH}, closed loop "
          f"to step {until}, changed\n")  # fmt: skip
    print(_head("change", "highest above the ground (m)", "at step",
                "body rise (m)", f"steps {BRANCH + 1} to it touching {wname}",
                "longest stretch of them with both knees at the force limit",
                "servo targets vs the record (max, rad)"))  # fmt: skip
    wjp = w.jump
    print(_row("none (the engine's record; any wall)", f"{wjp.height:.4f}", wjp.apex,
               f"{wjp.rise:.3f}", int(wall[BRANCH + 1 : wjp.apex + 1].sum()),
               "-", "-"))  # fmt: skip
    for what, change in variants:
        out = run_on(r, BRANCH, until, gid, change)
        j = out.jump
        print(_row(what + (f"; {out.note}" if out.note else ""), f"{j.height:.4f}",
                   j.apex, f"{j.rise:.3f}", out.touched, out.held,
                   _f(out.diff, ".1e")))  # fmt: skip


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--compare", default="auto",
                    help="where to find the jump touching no wall: auto (terrains "
                    "100-139 and the flat floor), flat, or a terrain seed")  # fmt: skip
    ap.add_argument("--per-step", action="store_true", help="per control step "
                    "from step 1291, not only the push")  # fmt: skip
    args = ap.parse_args(argv)
    backend = ThreadBackend(1)
    try:
        report(args.compare, args.per_step, backend)
    finally:
        backend.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
