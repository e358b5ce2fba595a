"""Behaviour metrics computed from recorded trajectories (pure functions)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.scene import Flat, Scene

#: A jump is a stretch where the body centre is this many body lengths above
#: its standing height.
JUMP_THRESHOLD_BL = 0.1
#: A bounce splits a high stretch into two jumps when z rises this many body
#: lengths above the bounce on both sides.
BOUNCE_PROMINENCE_BL = 0.2


@dataclass(frozen=True)
class Jump:
    start: int  # control step the body rose above the threshold
    apex_step: int
    end: int
    apex_height: float  # (m) body-centre height above the ground at the apex
    apex_x: float  # (m) x at the apex
    rise: float  # (m) apex height minus standing height


def clearance(
    qpos: np.ndarray, p: lm.LocustParams = lm.LocustParams(), scene: Scene = Flat()
) -> np.ndarray:
    """Height (m) of the body centre above the ground under it, of trajectories
    ``qpos (..., nq)`` (shape ``qpos.shape[:-1]``): ``z`` on the flat floor,
    ``z - h(x, y)`` on a terrain (``h``: :meth:`Scene.heights`)."""
    z: np.ndarray = qpos[..., 2]
    if scene.is_flat:
        return z
    above: np.ndarray = z - scene.heights(qpos[..., 0], qpos[..., 1], p.body_length)
    return above


def ground_profile(
    qpos: np.ndarray,
    p: lm.LocustParams = lm.LocustParams(),
    scene: Scene = Flat(),
    points: int = 2000,
) -> tuple[np.ndarray, np.ndarray] | None:
    """The ground's height (m) under the path of one trajectory ``qpos (T,
    nq)``: ``(x, h)`` at ``points`` distances from its least to its largest x
    (half a body length beyond each), the ground at the path's y there;
    ``None`` on the flat floor."""
    if scene.is_flat:
        return None
    order = np.argsort(qpos[:, 0], kind="stable")
    xs, ys = qpos[order, 0], qpos[order, 1]
    x = np.linspace(xs[0] - p.body_length / 2, xs[-1] + p.body_length / 2, points)
    return x, scene.heights(x, np.interp(x, xs, ys), p.body_length)


def find_jumps(
    qpos: np.ndarray, p: lm.LocustParams = lm.LocustParams(), scene: Scene = Flat()
) -> list[Jump]:
    """Jumps of one trajectory ``qpos (T, nq)`` (heights above the ground of
    ``scene``: :func:`clearance`).

    A jump is a stretch where the body centre is more than ``JUMP_THRESHOLD_BL``
    body lengths above its standing height. A stretch is split where the body
    bounces off the ground without coming that low (landing on its legs or its
    side): in flight z is concave, so a local minimum of z with more than
    ``BOUNCE_PROMINENCE_BL`` of rise on both sides is a landing.
    """
    z = clearance(qpos, p, scene)
    thr = JUMP_THRESHOLD_BL * p.body_length
    prom = BOUNCE_PROMINENCE_BL * p.body_length
    stand = lm.standing_height(p)
    high = z > stand + thr
    edges = np.diff(np.concatenate([[0], high.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    bounds = []
    for a, b in zip(starts, ends, strict=True):
        s = a
        seg = z[a:b]
        minima = a + 1 + np.flatnonzero((seg[1:-1] < seg[:-2]) & (seg[1:-1] <= seg[2:]))
        for k in minima:
            if z[s:k].max() - z[k] > prom and z[k:b].max() - z[k] > prom:
                bounds.append((s, k))
                s = k
        bounds.append((s, b))
    jumps = []
    for a, b in bounds:
        k = int(a) + int(np.argmax(z[a:b]))
        jumps.append(
            Jump(int(a), k, int(b), float(z[k]), float(qpos[k, 0]), float(z[k] - stand))
        )
    return jumps


#: (Seconds) on its back or side this long counts as stuck overturned.
STUCK_S = 1.0


def stuck_overturned(uz: np.ndarray, dt: float = lm.CONTROL_DT) -> int | None:
    """The first control step from which the body's up vector points down
    (``U_z < 0``) for ``STUCK_S`` on end: the creature lies overturned (a
    somersault in flight is shorter); ``None`` if it never does."""
    n = max(1, round(STUCK_S / dt))
    if len(uz) < n:
        return None
    runs = np.convolve(uz < 0, np.ones(n, int), "valid")
    hit = np.flatnonzero(runs == n)
    return int(hit[0]) if len(hit) else None
