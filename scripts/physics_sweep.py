"""Measure the physics gates for candidate model settings (docs/physics.md).

For each setting: the max-rate kick apex at substeps n and 4n (convergence),
rest drift/jitter/penetration over 10 s, random-controller stress (NaN /
instability warnings, penetration), and the cost of one control step.

    python scripts/physics_sweep.py --scale 10 --substeps 1 2 4
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import mujoco
import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.actuation import MAX_DELTA, apply_deltas


def kick_apex(p: lm.LocustParams, steps: int = 300) -> tuple[float, float]:
    """Apex height gain (m) and peak penetration (m) of the max-rate kick."""
    m = lm.load_model(p)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    idx = lm.ModelIndex.of(m)
    z0 = d.qpos[2]
    goal = p.kick_angles()
    apex, pen = z0, 0.0
    for _ in range(steps):
        delta = np.clip(goal - d.ctrl, -MAX_DELTA, MAX_DELTA)
        d.ctrl[:] = apply_deltas(d.ctrl[None], delta[None], idx.ranges)[0]
        for _ in range(p.substeps):
            mujoco.mj_step(m, d)
            apex = max(apex, d.qpos[2])
            if d.ncon:
                pen = max(pen, -d.contact.dist[: d.ncon].min())
    return apex - z0, pen


def rest(p: lm.LocustParams, seconds: float = 10.0) -> tuple[float, float, float]:
    """Drift (m), final speed (m/s) and peak penetration (m) standing still."""
    m = lm.load_model(p)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    q0 = d.qpos[:3].copy()
    pen = 0.0
    for _ in range(round(seconds / m.opt.timestep)):
        mujoco.mj_step(m, d)
        if d.ncon:
            pen = max(pen, -d.contact.dist[: d.ncon].min())
    drift = float(np.linalg.norm(d.qpos[:3] - q0))
    return drift, float(np.linalg.norm(d.qvel[:3])), pen


def stress(
    p: lm.LocustParams, episodes: int, seconds: float, seed: int = 0
) -> tuple[int, float, float]:
    """Random-delta episodes: count of NaN/warning episodes, peak penetration."""
    m = lm.load_model(p)
    d = mujoco.MjData(m)
    idx = lm.ModelIndex.of(m)
    rng = np.random.default_rng(seed)
    bad, pen, t0 = 0, 0.0, time.perf_counter()
    nctrl = round(seconds / lm.CONTROL_DT)
    for _ in range(episodes):
        mujoco.mj_resetDataKeyframe(m, d, 0)
        # a random persistent "style": each episode holds a delta for a while
        hold = rng.integers(1, 30)
        delta = np.zeros(4)
        ok = True
        for k in range(nctrl):
            if k % hold == 0:
                delta = rng.uniform(-MAX_DELTA, MAX_DELTA, 4)
            d.ctrl[:] = apply_deltas(d.ctrl[None], delta[None], idx.ranges)[0]
            for _ in range(p.substeps):
                mujoco.mj_step(m, d)
                if d.ncon:
                    pen = max(pen, -d.contact.dist[: d.ncon].min())
            if not np.isfinite(d.qpos).all() or d.warning.number.any():
                ok = False
                break
        bad += not ok
    cost = (time.perf_counter() - t0) / (episodes * nctrl)
    return bad, pen, cost


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--scale", type=float, nargs="+", default=[10.0])
    ap.add_argument("--substeps", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--episodes", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument(
        "--set", nargs="*", default=[], help="extra LocustParams fields, k=v"
    )
    args = ap.parse_args()
    extra: dict[str, Any] = {}  # LocustParams fields: each of its own type
    for kv in args.set:
        k, v = kv.split("=")
        default = getattr(lm.LocustParams(), k)
        if isinstance(default, tuple):
            extra[k] = tuple(float(x) for x in v.split(","))
        else:
            extra[k] = type(default)(v)
    for scale in args.scale:
        for n in args.substeps:
            p = lm.LocustParams(scale=scale, substeps=n, **extra)
            bl = p.body_length
            apex, kpen = kick_apex(p)
            apex4, _ = kick_apex(p.replace(substeps=4 * n))
            drift, speed, rpen = rest(p)
            bad, spen, cost = stress(p, args.episodes, args.seconds)
            print(
                f"scale={scale:g} substeps={n}: kick apex {apex:.3f} m "
                f"({apex / bl:.2f} BL), x4-finer {apex4:.3f} m "
                f"(change {abs(apex - apex4) / apex4:.1%}), kick pen "
                f"{kpen / bl:.2%} BL | rest drift {drift / bl:.2%} BL, speed "
                f"{speed:.1e} m/s, pen {rpen / bl:.2%} BL | stress "
                f"{bad}/{args.episodes} unstable, pen {spen / bl:.2%} BL, "
                f"{cost * 1e6:.0f} us/control step"
            )


if __name__ == "__main__":
    main()
