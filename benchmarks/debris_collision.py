"""Where a debris physics step's time goes, by MuJoCo's own stage timers
(``d.timer``), on the flat floor, on the debris model as MuJoCo compiles its
MJCF without this package's collision work (issue #45: the floor in the world
body's tree, the compiler's tree, every static geom's pose recomputed each
step), on the engine's debris model, and on a bound: the engine's model
less every static geom the replayed episodes never touch (an oracle that
knows the trajectories in advance; what no culling of "work that can never
produce a contact" can beat, since it does none of that work).

Rule-based controllers (--episodes change times in [0, 1] s, --steps control
steps) run through the engine on each scene; their servo targets are replayed
substep by substep on one ``MjData``, one thread, on each model of that
scene, --repeats times (medians). Every debris model must give the same
trajectory, bit for bit (printed).

    python benchmarks/debris_collision.py [--terrains 3] [--repeats 3]
"""

from __future__ import annotations

import argparse
import re
import statistics
from collections.abc import Iterator

import mujoco
import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.bvh import rebuild_bvh
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.job import StartStates
from locustjump.sim.engine.rollout import rollout
from locustjump.sim.scene import Debris, Flat, Scene
from locustjump.tasks.rules import RuleController
from locustjump.tasks.starts import ready_state

STAGES = {
    "step": "STEP",
    "kinematics": "POS_KINEMATICS",
    "collision": "POS_COLLISION",
    "broad phase": "COL_BROAD",
    "mid + narrow": "COL_NARROW",
    "make constraints": "POS_MAKE",
    "solver": "CONSTRAINT",
}


def as_compiled(p: lm.LocustParams, scene: Scene) -> mujoco.MjModel:
    """The debris model before issue #45, from today's MJCF: no sleeping, the
    floor plane in the world body's tree (contype 1), the compiler's tree."""
    xml = lm.to_mjcf(p, scene=scene).replace('<flag sleep="enable"/>', "")
    xml = xml.replace('type="plane" contype="0"', 'type="plane" contype="1"')
    return mujoco.MjModel.from_xml_string(xml)


def _physics_steps(
    m: mujoco.MjModel,
    d: mujoco.MjData,
    p: lm.LocustParams,
    start: StartStates,
    ctrl: np.ndarray,
) -> Iterator[str]:
    """Replay the servo targets ``ctrl (n, T + 1, nu)`` from ``start`` on
    ``d``, one physics step at a time; after each, what it ended: "" (a
    substep), "control step", or "episode" (the last control step of one)."""
    for e in range(len(ctrl)):
        mujoco.mj_resetData(m, d)
        d.qpos[:], d.qvel[:] = start.qpos[0], start.qvel[0]
        mujoco.mj_forward(m, d)
        for t in range(1, ctrl.shape[1]):
            d.ctrl[:] = ctrl[e, t]
            for k in range(p.substeps):
                mujoco.mj_step(m, d)
                if k < p.substeps - 1:
                    yield ""
                else:
                    yield "episode" if t == ctrl.shape[1] - 1 else "control step"


def touched_only(
    p: lm.LocustParams, scene: Scene, start: StartStates, ctrl: np.ndarray
) -> mujoco.MjModel:
    """The engine's model of ``scene`` less the boxes and walls (and the walls'
    contact sensors) that no contact of the episodes ``ctrl`` ever names."""
    m = lm.load_model(p, scene)
    d = mujoco.MjData(m)
    touched: set[str] = set()
    for _ in _physics_steps(m, d, p, start, ctrl):
        for g in d.contact.geom[: d.ncon].ravel():
            touched.add(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g))

    def keep(element: re.Match[str]) -> str:
        return element[0] if element[1] in touched else ""

    # a box or wall, and a wall's contact sensor, are one element each
    element = r'<(?:geom name|contact name="[^"]*" geom1)="((?:debris|wall)\d+)"[^>]*/>'
    xml = re.sub(element, keep, lm.to_mjcf(p, scene=scene))
    m = mujoco.MjModel.from_xml_string(xml)
    rebuild_bvh(m)
    return m


def replay(
    m: mujoco.MjModel, p: lm.LocustParams, start: StartStates, ctrl: np.ndarray
) -> tuple[dict[str, float], float, np.ndarray]:
    """(us a physics step per stage, contacts a step, qpos after each control
    step) of the servo targets ``ctrl (n, T + 1, nu)`` from ``start``."""
    d = mujoco.MjData(m)
    total = dict.fromkeys(STAGES, 0.0)
    steps = contacts = 0
    qpos = []
    for last in _physics_steps(m, d, p, start, ctrl):
        contacts += d.ncon
        if last:  # a control step's last substep
            qpos.append(d.qpos.copy())
        if last == "episode":  # its timers: since the episode's reset
            steps += d.timer[mujoco.mjtTimer.mjTIMER_STEP].number
            for k, t in STAGES.items():
                total[k] += d.timer[getattr(mujoco.mjtTimer, "mjTIMER_" + t)].duration
    return (
        {k: v / steps * 1e6 for k, v in total.items()},
        contacts / steps,
        np.array(qpos),
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--terrains", type=int, default=3)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--episodes", type=int, default=8)
    ap.add_argument("--steps", type=int, default=3000)
    args = ap.parse_args()
    p = lm.LocustParams()
    rc = RuleController.for_model(p)
    params = rc.params_for(np.linspace(0.0, 1.0, args.episodes))
    rows: dict[str, list[dict[str, float]]] = {
        "flat floor": [], "debris, as compiled": [],
        "debris, engine's model": [],
        "debris, touched geoms only (bound)": []}  # fmt: skip
    identical = True
    with ThreadBackend(1) as backend:
        for seed in range(args.terrains):
            runs = []
            for scene in (Flat(), Debris(seed=seed)):
                start = ready_state(p, scene)
                res = rollout(
                    rc, params, start, args.steps, model_params=p,
                    record=("ctrl",), backend=backend, scene=scene,
                )  # fmt: skip
                runs.append((scene, start, res["ctrl"]))
            (flat, fs, fc), (debris, ds, dc) = runs
            models = [(lm.load_model(p, flat), fs, fc),
                      (as_compiled(p, debris), ds, dc),
                      (lm.load_model(p, debris), ds, dc),
                      (touched_only(p, debris, ds, dc), ds, dc)]  # fmt: skip
            kept = int(np.sum(models[3][0].geom_bodyid == 0)) - 1  # less the floor
            print(f"terrain {seed}: {kept} of "
                  f"{int(np.sum(models[2][0].geom_bodyid == 0)) - 1} boxes and walls "
                  "touched")  # fmt: skip
            for _ in range(args.repeats):
                out = [replay(m, p, s, c) for m, s, c in models]
                identical &= all(np.array_equal(out[1][2], o[2]) for o in out[2:])
                for name, (t, ncon, _) in zip(rows, out, strict=True):
                    rows[name].append({**t, "contacts": ncon})
    print(f"us a physics step, median of {args.terrains} terrains x {args.repeats}; "
          f"debris trajectories identical: {identical}\n")  # fmt: skip
    cols = [*STAGES, "contacts"]
    print("| model | " + " | ".join(cols) + " |")
    print("| --- |" + " --- |" * len(cols))
    for name, r in rows.items():
        cells = [f"{statistics.median(x[c] for x in r):.2f}" for c in cols]
        print(f"| {name} | " + " | ".join(cells) + " |")
    step = {k: statistics.median(x["step"] for x in r) for k, r in rows.items()}
    flat_step = step["flat floor"]
    print("\nflat / debris, a physics step: " + ", ".join(
        f"{k.removeprefix('debris, ')} {flat_step / v:.2f}" for k, v in step.items()
        if k != "flat floor"))  # fmt: skip


if __name__ == "__main__":
    main()
